// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead inspect MODEL.thm [-o DIR] [--recon CORPUS]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "base/data_dirs.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "base/parallel.h"
#include "cli/args.h"
#include "cli/run.h"
#include "cli/commands.h"
#include "cli/corpus_filter.h"
#include "base/progress.h"
#include "media/image_io.h"
#include "cli/video_options.h"
#include "model/face_model.h"
#include "model/model_file.h"
#include "phonetics/labels.h"
#include "synth/synthesizer.h"
#include "viz/inspect_images.h"

namespace talkhead::cli {

namespace {

// The default face model, or an Error saying where it was looked for and how to get it.
std::string defaultModelPath() {
	ensureDefaultFace(false);
	if (auto p = findDefaultModel()) return *p;
	std::string where;
	for (const auto& c : defaultModelCandidates()) where += (where.empty() ? "" : ", ") + c;
	throw Error("no default face model found (looked for " + where + "); build one with scripts/demo (or the 'default_model' build target), or name a model");
}

// Issue 47: per recorded emotion, where each of the CDVs comes from — its own sample, another (the
// fallbacks: neutral's, the group's, the nearest mouth), or the neutral mouth moved by its action units.
void printCoverage(const FaceModel& m) {
	std::vector<Emotion> recorded;
	for (const SampleInfo& s : m.samples)
		if (auto e = Emotion::find(s.emotion); e && std::find(recorded.begin(), recorded.end(), *e) == recorded.end()) recorded.push_back(*e);
	if (recorded.empty()) return;
	const Synthesizer synth(m, SynthOptions{});
	std::printf("emotions   of the %zu CDVs: own sample, another sample (the nearest mouth it has), the neutral mouth by its action units\n", Cdv::count());
	for (Emotion e : recorded) {
		int own = 0, units = 0;
		std::string borrowed;
		for (std::size_t i = 0; i < Cdv::count(); ++i) {
			const KeyposeSource s = synth.keyposeSource(Cdv::at(i), e);
			if (s.kind == KeyposeSource::Kind::Own) ++own;
			else if (s.kind == KeyposeSource::Kind::ActionUnits) ++units;
			else {  // a model sample's CDV: a known label, or an unlabelled row's name as it is
				const auto used = Cdv::find(s.cdv);
				borrowed += " " + Cdv::at(i).ascii() + ">" + (s.emotion == e.label() ? "" : s.emotion + ":") + (used ? used->ascii() : s.cdv);
			}
		}
		const int others = int(Cdv::count()) - own - units;
		std::printf("  %-14s %2d own, %2d by action units, %2d from another sample%s%s\n", e.label().c_str(), own, units, others, others ? ":" : "", borrowed.c_str());
	}
}

void printSummary(const FaceModel& m, const std::string& path) {
	std::error_code ec;
	auto bytes = std::filesystem::file_size(path, ec);
	std::printf("model      %s (%.1f MiB)\n", path.c_str(), ec ? 0.0 : double(bytes) / (1024.0 * 1024.0));
	std::printf("scheme     %s: %d points\n", m.scheme.name.c_str(), m.pointCount());
	std::printf("frame      %dx%d\n", m.width, m.height);
	std::printf("samples    %zu (baseface: #%zu %s; Procrustes reference #%zu, %d iterations, last change %.2g)\n", m.sampleCount(),
	            m.basefaceIndex, m.samples[m.basefaceIndex].image.c_str(), m.referenceIndex, m.procrustesIterations, m.procrustesChange);
	std::printf("meshes     face %zu triangles, frame %zu triangles (+%d border points)\n", m.faceMesh.triangles.size(),
	            m.frameMesh.triangles.size(), kFrameBorderPoints);
	std::printf("regions    %zu\n", m.regions.size());
	std::printf("  %-12s %9s %9s %8s %8s %8s %8s %8s\n", "region", "pixels", "n", "PCs", "of", "EVR kept", "PCs@80%", "PCs@90%");
	for (const auto& r : m.regions) {
		const auto& p = r.pca;
		double kept = p.eigenvalues.head(p.components()).sum() / p.eigenvalues.sum();
		std::printf("  %-12s %9zu %9ld %8ld %8ld %7.1f%% %8ld %8ld\n", r.name.c_str(), r.pixels.size(), long(p.mean.size()), long(p.components()),
		            long(p.eigenvalues.size()), 100 * kept, long(p.componentsFor(0.8)), long(p.componentsFor(0.9)));
	}
}

struct Quality {
	double mse = 0, psnr = 0, ssim = 0;
};

int reconstruct(const FaceModel& model, const std::string& corpusPath, const Args& args) {
	Corpus corpus = loadFilteredCorpus(corpusPath, args);
	if (corpus.entries.front().points.rows() != model.pointCount())
		throw Error(corpusPath, 0, "has " + std::to_string(corpus.entries.front().points.rows()) + " points per shape, the model has " +
		                               std::to_string(model.pointCount()));
	std::vector<std::vector<Quality>> q(model.regions.size());
	std::printf("%-28s", "image");
	for (const auto& r : model.regions) std::printf(" | %-12s %8s %8s %7s", r.name.c_str(), "MSE", "PSNR", "SSIM");
	std::printf("\n");
	// In batches: shape-free vectors of a chunk of images (in parallel), then one GEMM per region to
	// project and one to reconstruct.
	const std::size_t chunk = 64;
	for (std::size_t first = 0; first < corpus.entries.size(); first += chunk) {
		const std::size_t count = std::min(chunk, corpus.entries.size() - first);
		std::vector<Eigen::MatrixXf> combined(model.regions.size());
		for (std::size_t r = 0; r < model.regions.size(); ++r) combined[r].resize(model.regions[r].pca.mean.size(), Eigen::Index(count));
		parallelFor(count, 0, [&](std::size_t k) {
			const CorpusEntry& e = corpus.entries[first + k];
			Projection p = projectImage(model, readImage(e.imagePath), e.points, false);
			for (std::size_t r = 0; r < model.regions.size(); ++r)
				combined[r].col(Eigen::Index(k)) = combinedVector(model.regions[r], p.shapeFree, p.alignedShape);
		});
		std::vector<Eigen::MatrixXf> recon;
		for (std::size_t r = 0; r < model.regions.size(); ++r)
			recon.push_back(synthesizeAppearances(model.regions[r], projectCombined(model.regions[r], combined[r])));
		std::vector<std::vector<Quality>> chunkQ(count, std::vector<Quality>(model.regions.size()));
		parallelFor(count, 0, [&](std::size_t k) {
			for (std::size_t ri = 0; ri < model.regions.size(); ++ri) {
				const RegionModel& r = model.regions[ri];
				// Compare in the shape-free frame over the region's pixels (thesis App. B, Eq. B.6); outside
				// the region both images hold the baseface, so the SSIM window sees the same surroundings.
				Image actual = toFloat(model.baseface), rec = actual;
				scatterAppearance(r, combined[ri].col(Eigen::Index(k)).head(r.appearanceSize()), actual);
				Eigen::VectorXf a = recon[ri].col(Eigen::Index(k)).cwiseMax(0.f).cwiseMin(255.f);
				scatterAppearance(r, a, rec);
				std::vector<std::uint8_t> mask(actual.pixelCount(), 0);
				for (auto px : r.pixels) mask[std::size_t(px)] = 1;
				Quality& qu = chunkQ[k][ri];
				qu.mse = (combined[ri].col(Eigen::Index(k)).head(r.appearanceSize()) - a).squaredNorm() / double(r.appearanceSize());
				qu.psnr = psnrFromMse(qu.mse);
				qu.ssim = ssim(actual, rec, mask);
			}
		});
		for (std::size_t k = 0; k < count; ++k) {
			std::printf("%-28s", std::filesystem::path(corpus.entries[first + k].imagePath).filename().string().c_str());
			for (std::size_t ri = 0; ri < model.regions.size(); ++ri) {
				q[ri].push_back(chunkQ[k][ri]);
				std::printf(" | %-12s %8.2f %8.2f %7.4f", "", chunkQ[k][ri].mse, chunkQ[k][ri].psnr, chunkQ[k][ri].ssim);
			}
			std::printf("\n");
		}
	}
	std::printf("%-28s", "mean");
	for (std::size_t ri = 0; ri < model.regions.size(); ++ri) {
		Quality mean;
		for (const auto& qu : q[ri]) {
			mean.mse += qu.mse / q[ri].size();
			mean.ssim += qu.ssim / q[ri].size();
		}
		mean.psnr = psnrFromMse(mean.mse);
		std::printf(" | %-12s %8.2f %8.2f %7.4f", model.regions[ri].name.c_str(), mean.mse, mean.psnr, mean.ssim);
	}
	std::printf("\n(MSE over the region's pixels and RGB channels, 0-255 scale; PSNR of the mean MSE; SSIM 11x11 Gaussian window)\n");
	return 0;
}

}  // namespace

int runInspect(const std::vector<std::string>& argv) {
	Args args("inspect", "talkhead inspect [MODEL.thm | --face NAME] [-o DIR] [--recon CORPUS]",
	          {faceOption(),
	           {"--output", "DIR", "write pictures of the model (PNG) into DIR", "-o"},
	           {"--recon", "CORPUS", "project and reconstruct each image of CORPUS; print MSE, PSNR, SSIM per region"},
	           kIncludeOption,
	           kExcludeOption,
	           {"--quiet", "", "no summary", "-q"}},
	          "Prints a summary of a face model (default: the embedded default face); writes pictures of it\n"
	          "(baseface and mesh, modes, explained variance, contact sheet of every keypose) with -o; measures\n"
	          "reconstruction with --recon.");
	if (!args.parse(argv)) return 0;
	if (args.positionals().size() > 1) throw UsageError("inspect: expected at most one MODEL.thm argument");
	if (args.has("--face") && !args.positionals().empty()) throw UsageError("inspect: give a MODEL.thm or --face NAME, not both");
	std::string path = args.positionals().empty() ? "" : args.positionals()[0];
	if (auto face = args.get("--face")) path = shippedFaceModel(*face, args.has("--quiet"));
	if (path.empty()) path = defaultModelPath();
	FaceModel model = loadModel(path);
	if (!args.has("--quiet")) printSummary(model, path), printCoverage(model);
	if (auto dir = args.get("--output")) {
		namespace fs = std::filesystem;
		// All or nothing: the pictures go to a staged folder that replaces DIR once all are written.
		StagedFolder staged(*dir, [](const std::string& n) { return n.size() > 4 && n.compare(n.size() - 4, 4, ".png") == 0; });
		std::vector<std::string> written;
		auto write = [&](const std::string& name, const Image8& img) {
			staged.writeFile(name, [&](const std::string& p) { writeImage(p, img); });
			written.push_back((fs::path(*dir) / name).string());
		};
		write("baseface_mesh.png", drawBasefaceMesh(model));
		for (std::size_t r = 0; r < model.regions.size(); ++r) write("modes_" + model.regions[r].name + ".png", drawRegionModes(model, int(r)));
		write("explained_variance.png", drawVarianceCurves(model));
		// Captions in ASCII (the drawing font has no IPA): viseme labels by their ASCII alias.
		write("contact_sheet.png", drawContactSheet(model, 160, [](const SampleInfo& s) {
			      std::string cdv = s.cdv;
			      if (auto c = canonicalViseme(cdv))
				      for (const auto& v : visemeLabels())
					      if (v.label == *c) cdv = v.ascii;
			      return (s.emotion == "-" ? std::string() : s.emotion + " ") + cdv;
		      }));
		staged.commit();
		for (const auto& w : written) std::printf("wrote %s\n", w.c_str());
	}
	if (auto corpus = args.get("--recon")) return reconstruct(model, *corpus, args);
	return 0;
}

}  // namespace talkhead::cli
