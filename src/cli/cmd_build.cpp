// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead build CORPUS -o MODEL.thm
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/corpus_filter.h"
#include "corpus/build.h"
#include "base/progress.h"
#include "media/image_io.h"
#include "model/face_model.h"
#include "model/model_file.h"

namespace talkhead::cli {

namespace {

// "--components 40" (every region) or "--components face=200,lips=all"; same for --evr.
// regions == nullptr: check the values only (before the corpus is read).
void parseComponentOption(const Args& args, const std::string& name, const std::vector<std::string>* regions, BuildOptions& opts) {
	auto v = args.get(name);
	if (!v) return;
	const bool isEvr = name == "--evr";
	auto apply = [&](PcaOptions& p, const std::string& value) {
		if (value == "all") {
			p = PcaOptions{};
			return;
		}
		double d;
		if (isEvr) {
			if (!parseDouble(value, d) || d <= 0 || d > 1) throw UsageError("build: --evr values must be in (0, 1] or 'all', got '" + value + "'");
			p.evr = d;
		} else {
			long long n;
			if (!parseInt(value, n) || n < 1) throw UsageError("build: --components values must be positive integers or 'all', got '" + value + "'");
			p.maxComponents = int(n);
		}
	};
	for (const std::string& item : split(*v, ',')) {
		auto eq = item.find('=');
		if (eq == std::string::npos) {
			apply(opts.pca, item);
			for (auto& [region, p] : opts.regionPca) apply(p, item);
			continue;
		}
		std::string region = item.substr(0, eq);
		if (regions && std::find(regions->begin(), regions->end(), region) == regions->end()) {
			std::string known;
			for (const auto& r : *regions) known += (known.empty() ? "" : ", ") + r;
			throw UsageError("build: " + name + ": unknown region '" + region + "' (regions: " + known + ")");
		}
		auto [it, inserted] = opts.regionPca.try_emplace(region, opts.pca);
		apply(it->second, item.substr(eq + 1));
	}
}

}  // namespace

int runBuild(const std::vector<std::string>& argv) {
	Args args("build", "talkhead build CORPUS -o MODEL.thm [options]",
	          {{"--output", "MODEL.thm", "the model file to write (required)", "-o"},
	           {"--scheme", "NAME", "landmark scheme (default: from the corpus: ch-unicamp-56, ibug-68 or imm-73)"},
	           {"--components", "N|R=N,...", "keep at most N principal components (per region: face=200,lips=all)"},
	           {"--evr", "X|R=X,...", "keep the fewest components explaining the fraction X of variance (per region too)"},
	           {"--threads", "N", "worker threads (default: all cores)"},
	           kIncludeOption,
	           kExcludeOption,
	           {"--quiet", "", "no progress bar and no summary", "-q"}},
	          "Builds a face model (weighted Procrustes, Delaunay piecewise-affine warps, one correlation PCA per\n"
	          "face region) from a CH-Unicamp CSV corpus or a folder of images with .asf/.pts landmark files.\n"
	          "All components are kept unless --components or --evr says otherwise.");
	if (!args.parse(argv)) return 0;
	args.onePositional("expected one CORPUS argument");
	const std::string output = args.required("--output", "-o MODEL.thm is required");
	const bool quiet = args.has("--quiet");
	BuildOptions opts;
	opts.threads = unsigned(args.number("--threads", 0, 0, 256));
	if (args.has("--components") && args.has("--evr") && args.get("--components")->find('=') == std::string::npos &&
	    args.get("--evr")->find('=') == std::string::npos)
		throw UsageError("build: give either --components N or --evr X for all regions, not both");
	parseComponentOption(args, "--components", nullptr, opts);
	parseComponentOption(args, "--evr", nullptr, opts);
	const auto started = std::chrono::steady_clock::now();

	Corpus corpus = loadFilteredCorpus(args.positionals()[0], args);
	const std::string schemeName = args.get("--scheme", corpus.schemeName);
	if (schemeName.empty())
		throw Error(corpus.path, 0, "cannot tell the landmark scheme from " + std::to_string(corpus.entries.front().points.rows()) +
		                                " points; name one with --scheme");
	const Scheme scheme = corpusScheme(corpus, schemeName);

	std::vector<std::string> regionNames;
	for (const auto& r : scheme.regions) regionNames.push_back(r.name);
	opts = BuildOptions{};
	opts.threads = unsigned(args.number("--threads", 0, 0, 256));
	parseComponentOption(args, "--components", &regionNames, opts);
	parseComponentOption(args, "--evr", &regionNames, opts);

	// Check the output location before the expensive part.
	std::filesystem::path out(output);
	std::error_code ec;
	if (!out.parent_path().empty() && !std::filesystem::is_directory(out.parent_path(), ec))
		throw Error(output, 0, "cannot write model: folder '" + out.parent_path().string() + "' does not exist");

	ProgressBar bar(quiet);
	const FaceModel model = buildFaceModel(corpus, scheme, opts, bar);
	saveModel(model, output);
	bar.finish();
	if (!quiet) {
		double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
		std::fprintf(stderr, "built %s: %zu images %dx%d, %d points (%s), Procrustes %d iterations;", output.c_str(), model.sampleCount(),
		             model.width, model.height, model.pointCount(), scheme.name.c_str(), model.procrustesIterations);
		for (const auto& r : model.regions)
			std::fprintf(stderr, " %s %zu px %ld PCs;", r.name.c_str(), r.pixels.size(), long(r.pca.components()));
		std::fprintf(stderr, " %.1f s (%.3f s/image)\n", secs, secs / double(model.sampleCount()));
	}
	return 0;
}

}  // namespace talkhead::cli
