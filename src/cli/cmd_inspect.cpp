// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead inspect MODEL.thm [-o DIR] [--recon CORPUS]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "base/error.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/corpus_filter.h"
#include "cli/progress_bar.h"
#include "media/image_io.h"
#include "model/face_model.h"
#include "model/model_file.h"
#include "viz/inspect_images.h"

namespace talkhead::cli {

namespace {

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
	for (const auto& e : corpus.entries) {
		Image8 img = readImage(e.imagePath);
		Projection p = projectImage(model, img, e.points);
		std::printf("%-28s", std::filesystem::path(e.imagePath).filename().string().c_str());
		for (std::size_t ri = 0; ri < model.regions.size(); ++ri) {
			const RegionModel& r = model.regions[ri];
			// Compare in the shape-free frame over the region's pixels (thesis App. B, Eq. B.6).
			Image recon = p.shapeFree;
			scatterAppearance(r, synthesizeAppearance(r, p.coefficients[ri]), recon);
			for (float& v : recon.data) v = std::min(255.f, std::max(0.f, v));
			std::vector<std::uint8_t> mask(p.shapeFree.pixelCount(), 0);
			for (auto px : r.pixels) mask[std::size_t(px)] = 1;
			Quality qu;
			qu.psnr = psnr(p.shapeFree, recon, mask);
			qu.mse = 255.0 * 255.0 / std::pow(10.0, qu.psnr / 10.0);
			qu.ssim = ssim(p.shapeFree, recon, mask);
			q[ri].push_back(qu);
			std::printf(" | %-12s %8.2f %8.2f %7.4f", "", qu.mse, qu.psnr, qu.ssim);
		}
		std::printf("\n");
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
	Args args("inspect", "talkhead inspect MODEL.thm [-o DIR] [--recon CORPUS]",
	          {{"--output", "DIR", "write pictures of the model (PNG) into DIR", "-o"},
	           {"--recon", "CORPUS", "project and reconstruct each image of CORPUS; print MSE, PSNR, SSIM per region"},
	           kIncludeOption,
	           kExcludeOption,
	           {"--quiet", "", "no summary", "-q"}},
	          "Prints a summary of a face model; writes pictures of it (baseface and mesh, modes, explained\n"
	          "variance, contact sheet of every keypose) with -o; measures reconstruction with --recon.");
	if (!args.parse(argv)) return 0;
	if (args.positionals().size() != 1) throw UsageError("inspect: expected one MODEL.thm argument");
	const std::string path = args.positionals()[0];
	FaceModel model = loadModel(path);
	if (!args.has("--quiet")) printSummary(model, path);
	if (auto dir = args.get("--output")) {
		namespace fs = std::filesystem;
		std::error_code ec;
		fs::create_directories(*dir, ec);
		if (ec) throw Error(*dir, 0, "cannot create folder: " + ec.message());
		std::vector<std::string> written;
		auto write = [&](const std::string& name, const Image8& img) {
			std::string p = (fs::path(*dir) / name).string();
			writeImage(p, img);
			written.push_back(p);
		};
		write("baseface_mesh.png", drawBasefaceMesh(model));
		for (std::size_t r = 0; r < model.regions.size(); ++r) write("modes_" + model.regions[r].name + ".png", drawRegionModes(model, int(r)));
		write("explained_variance.png", drawVarianceCurves(model));
		write("contact_sheet.png", drawContactSheet(model));
		for (const auto& w : written) std::printf("wrote %s\n", w.c_str());
	}
	if (auto corpus = args.get("--recon")) return reconstruct(model, *corpus, args);
	return 0;
}

}  // namespace talkhead::cli
