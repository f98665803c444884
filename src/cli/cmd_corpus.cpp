// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead corpus synth -o DIR
#include <chrono>
#include <cstdio>

#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "base/progress.h"
#include "phonetics/labels.h"
#include "synth_corpus.h"

namespace talkhead::cli {

namespace {

int runSynth(const std::vector<std::string>& argv) {
	Args args("corpus synth", "talkhead corpus synth -o DIR [options]",
	          {{"--output", "DIR", "folder to write the PNG images and corpus.csv into (required)", "-o"},
	           {"--size", "WxH", "image size (default 1280x720; the thesis used 1920x1080)"},
	           {"--seed", "N", "seed of the per-image head jitter (default 1)"},
	           {"--emotions", "LIST", "comma-separated emotion labels or aliases (default: all 23)"},
	           {"--visemes", "LIST", "comma-separated viseme labels or ASCII aliases (default: all 34)"},
	           {"--threads", "N", "worker threads (default: all cores)"},
	           {"--quiet", "", "no progress bar and no summary", "-q"}},
	          "Writes the synthetic expressive viseme corpus in CH-Unicamp CSV format: one image of a parametric,\n"
	          "shaded 2D face per (expression x viseme) — 23 x 34 = 782 at full settings — with its 56\n"
	          "ch-unicamp-56 feature points as exact ground truth. Build a model from it with\n"
	          "'talkhead build DIR/corpus.csv -o face.thm'.");
	if (!args.parse(argv)) return 0;
	if (!args.positionals().empty()) throw UsageError("corpus synth: unexpected argument '" + args.positionals()[0] + "'");
	auto out = args.get("--output");
	if (!out) throw UsageError("corpus synth: -o DIR is required");
	SynthCorpusOptions o;
	if (auto s = args.get("--size")) parseSize("corpus synth: --size", *s, o.width, o.height, 64, false);
	o.seed = std::uint64_t(args.number("--seed", 1, 0, 9.0e15));
	o.threads = unsigned(args.number("--threads", 0, 0, 256));
	if (auto e = args.get("--emotions"))
		for (const auto& name : split(*e, ',')) {
			auto c = canonicalEmotion(name);
			if (!c) {
				std::string known;
				for (const auto& l : emotionLabels()) known += (known.empty() ? "" : ", ") + l.label;
				throw UsageError("corpus synth: unknown emotion '" + name + "' (known: " + known + ")");
			}
			o.emotions.push_back(*c);
		}
	if (auto v = args.get("--visemes"))
		for (const auto& name : split(*v, ',')) {
			auto c = canonicalViseme(name);
			if (!c) {
				std::string known;
				for (const auto& l : visemeLabels()) known += (known.empty() ? "" : " ") + l.label;
				throw UsageError("corpus synth: unknown viseme '" + name + "' (known: " + known + ")");
			}
			o.visemes.push_back(*c);
		}
	const bool quiet = args.has("--quiet");
	const auto t0 = std::chrono::steady_clock::now();
	ProgressBar bar(quiet);
	writeSynthCorpus(*out, o, bar);
	bar.finish();
	if (!quiet) {
		const std::size_t n = (o.emotions.empty() ? emotionLabels().size() : o.emotions.size()) *
		                      (o.visemes.empty() ? visemeLabels().size() : o.visemes.size());
		double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		std::fprintf(stderr, "wrote %s/corpus.csv: %zu images %dx%d in %.1f s\n", out->c_str(), n, o.width, o.height, secs);
	}
	return 0;
}

}  // namespace

int runCorpus(const std::vector<std::string>& argv) {
	if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
		std::printf("usage: talkhead corpus synth -o DIR [options]                        the synthetic corpus\n"
		            "       talkhead corpus landmarks VIDEO|FOLDER -o DIR [options]         68 face points per frame (dlib)\n"
		            "       talkhead corpus from-video VIDEO [--text T] -o DIR [options]    a viseme corpus from a video\n"
		            "(see 'talkhead corpus SUBCOMMAND --help')\n");
		return argv.empty() ? 2 : 0;
	}
	if (argv[0] == "synth") return runSynth(std::vector<std::string>(argv.begin() + 1, argv.end()));
	const std::vector<std::string> rest(argv.begin() + 1, argv.end());
	if (argv[0] == "landmarks") return runCorpusLandmarks(rest);
	if (argv[0] == "from-video") return runCorpusFromVideo(rest);
	throw UsageError("corpus: unknown subcommand '" + argv[0] + "' (expected synth, landmarks or from-video)");
}

}  // namespace talkhead::cli
