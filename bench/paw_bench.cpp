// SPDX-License-Identifier: GPL-3.0-or-later
// Times talkhead's piecewise-affine warp on a 1280×720 RGB image with a 64-point mesh (56 face points
// + 8 frame-border points) and writes the inputs and its output for bench/paw_vs_skimage.py, which
// runs scikit-image's PiecewiseAffineTransform + warp on the same data and compares.
//
// usage: bench_paw OUTDIR [IMM_FOLDER]
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "corpus/corpus.h"
#include "image/yuv.h"
#include "media/image_io.h"
#include "warp/piecewise_affine.h"

using namespace talkhead;
using Clock = std::chrono::steady_clock;

static void writePoints(const std::string& path, const Points& p) {
	std::ofstream out(path);
	out.precision(10);
	for (Eigen::Index i = 0; i < p.rows(); ++i) out << p(i, 0) << " " << p(i, 1) << "\n";
}

int main(int argc, char** argv) {
	if (argc < 2) {
		std::fprintf(stderr, "usage: bench_paw OUTDIR [IMM_FOLDER]\n");
		return 2;
	}
	const std::string out = argv[1];
	std::filesystem::create_directories(out);
	const int W = 1280, H = 720;
	const std::string imm = argc > 2 ? argv[2] : "../shared/data/imm-frontal/IMM-Frontal_Face_DB_SMALL";
	Corpus c = loadCorpus(imm);
	const CorpusEntry& a = c.entries.at(0);
	const CorpusEntry& b = c.entries.at(57);
	Image8 src0 = readImage(a.imagePath);
	// Scale the 800×600 image and its shape to 1280×720.
	Image8 src(W, H, 3);
	cv::resize(cv::Mat(src0.height, src0.width, CV_8UC3, src0.data.data()), cv::Mat(H, W, CV_8UC3, src.data.data()), cv::Size(W, H), 0, 0,
	           cv::INTER_LINEAR);
	const double sx = double(W) / src0.width, sy = double(H) / src0.height;
	Points s = a.points.topRows(56), t = b.points.topRows(56);
	s.col(0) *= sx;
	s.col(1) *= sy;
	t.col(0) *= sx;
	t.col(1) *= sy;
	// The target: another person's face, similarity-aligned onto this one, so the warp is a real
	// non-rigid deformation of a face.
	t = alignSimilarity(t, s, Eigen::VectorXd::Ones(56)).apply(t);
	const Points srcPts = withFrameBorder(s, W, H), dstPts = withFrameBorder(t, W, H);
	const TriangleMesh mesh = delaunayTriangulation(srcPts);

	// Map construction (rasterising the destination mesh) and the warp itself, timed separately.
	const int reps = 50;
	std::vector<double> mapMs, warpMs;
	Image8 dst(W, H, 3);
	for (int r = 0; r < 10; ++r) {
		auto t0 = Clock::now();
		PiecewiseAffineWarp warp(mesh, dstPts, W, H);
		warp.setSource(srcPts);
		mapMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
	}
	PiecewiseAffineWarp warp(mesh, dstPts, W, H);
	warp.setSource(srcPts);
	for (int r = 0; r < reps; ++r) {
		auto t0 = Clock::now();
		warp.apply(src, dst);
		warpMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
	}
	std::sort(mapMs.begin(), mapMs.end());
	std::sort(warpMs.begin(), warpMs.end());
	writeImage(out + "/src.png", src);
	writeImage(out + "/talkhead.png", dst);
	writePoints(out + "/src_points.txt", srcPts);
	writePoints(out + "/dst_points.txt", dstPts);
	// The render path's planes: luma (1280×720) and interleaved chroma (640×360 → two planes).
	YuvImage yuv;
	rgbToYuv420(src, yuv);
	std::vector<std::uint8_t> uv(yuv.u.size() * 2), outY(yuv.y.size()), outU(yuv.u.size()), outV(yuv.v.size());
	for (std::size_t i = 0; i < yuv.u.size(); ++i) uv[2 * i] = yuv.u[i], uv[2 * i + 1] = yuv.v[i];
	const int cw = yuv.chromaWidth(), ch = yuv.chromaHeight();
	auto half = [&](const Points& p) { return withFrameBorder((p.topRows(56).array() - 0.5) * 0.5, cw, ch); };
	PiecewiseAffineWarp chroma(mesh, half(dstPts), cw, ch);
	chroma.setSource(half(srcPts));
	std::vector<double> lumaMs, chromaMs;
	for (int r = 0; r < reps; ++r) {
		std::uint8_t* y[1] = {outY.data()};
		std::uint8_t* c[2] = {outU.data(), outV.data()};
		auto t0 = Clock::now();
		warp.applyPlanes(yuv.y.data(), W, H, std::size_t(W), 1, y, std::size_t(W));
		auto t1 = Clock::now();
		chroma.applyPlanes(uv.data(), cw, ch, std::size_t(cw) * 2, 2, c, std::size_t(cw));
		lumaMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
		chromaMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t1).count());
	}
	std::sort(lumaMs.begin(), lumaMs.end());
	std::sort(chromaMs.begin(), chromaMs.end());
	std::printf("talkhead_map_ms %.3f\ntalkhead_warp_ms %.3f\ntalkhead_luma_ms %.3f\ntalkhead_chroma_ms %.3f\ntriangles %zu\npoints %ld\n",
	            mapMs[mapMs.size() / 2], warpMs[warpMs.size() / 2], lumaMs[lumaMs.size() / 2], chromaMs[chromaMs.size() / 2],
	            mesh.triangles.size(), long(srcPts.rows()));
	return 0;
}
