// SPDX-License-Identifier: GPL-3.0-or-later
// Where a face from video loses its fine detail (issue 47): for each exemplar of a model built from a
// corpus, the mouth's variance of the Laplacian (luma) in
//   source     the corpus image itself, around its own points (no resampling);
//   one warp   the source warped straight to the points the render draws the keypose at (one bilinear
//              resampling: what "one resampling from the source pixels" would give);
//   bicubic,   the same single resampling with a Catmull-Rom or a Lanczos-3 kernel instead of bilinear;
//   lanczos-3
//   two warps  the source warped to the mean shape (as the model stores it) and from there to the same
//              points (two bilinear resamplings, no appearance model); "two lanczos" the same with Lanczos-3;
//              "lanczos+bil" Lanczos-3 into the mean shape (the build's warp), bilinear out (the render's);
//   rendered   the synthesizer's frame on the keypose (the 8-bit cache of the region models' reconstruction,
//              composited in the mean frame, then warped out);
// all at the model's frame size, the mouth box of each image's own points (grown by a quarter). Prints the
// means over the exemplars and each as a fraction of the source's.
// With SHEET.png: the first exemplar's mouth as source | bilinear | bicubic | Lanczos-3 | rendered, ×4.
//   bench_detail CORPUS.csv MODEL.thm [MAX_SAMPLES [SHEET.png]]
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "base/error.h"
#include "corpus/corpus.h"
#include "geometry/shape.h"
#include "media/image_io.h"
#include "model/model_file.h"
#include "synth/synthesizer.h"
#include "warp/piecewise_affine.h"

using namespace talkhead;

namespace {

// Luma of an RGB image as doubles.
std::vector<double> luma(const Image8& im) {
	std::vector<double> y(std::size_t(im.width) * std::size_t(im.height));
	for (int r = 0; r < im.height; ++r)
		for (int c = 0; c < im.width; ++c) {
			const std::uint8_t* p = im.row(r) + 3 * c;
			y[std::size_t(r) * std::size_t(im.width) + std::size_t(c)] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
		}
	return y;
}

// Variance of the 4-neighbour Laplacian inside the box around `mouth` points (grown by a quarter).
double mouthDetail(const Image8& im, const Points& pts, const std::vector<int>& mouth) {
	double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
	for (int i : mouth) x0 = std::min(x0, pts(i, 0)), x1 = std::max(x1, pts(i, 0)), y0 = std::min(y0, pts(i, 1)), y1 = std::max(y1, pts(i, 1));
	const double gx = 0.25 * (x1 - x0), gy = 0.25 * (y1 - y0);
	const int c0 = std::max(1, int(x0 - gx)), c1 = std::min(im.width - 2, int(x1 + gx)), r0 = std::max(1, int(y0 - gy)), r1 = std::min(im.height - 2, int(y1 + gy));
	const std::vector<double> y = luma(im);
	auto at = [&](int r, int c) { return y[std::size_t(r) * std::size_t(im.width) + std::size_t(c)]; };
	double s = 0, s2 = 0;
	long n = 0;
	for (int r = r0; r <= r1; ++r)
		for (int c = c0; c <= c1; ++c) {
			const double l = at(r - 1, c) + at(r + 1, c) + at(r, c - 1) + at(r, c + 1) - 4 * at(r, c);
			s += l, s2 += l * l, ++n;
		}
	return n > 1 ? s2 / double(n) - (s / double(n)) * (s / double(n)) : 0;
}

Image8 warped(const Image8& src, const Points& from, const Points& to, const TriangleMesh& mesh, int w, int h) {
	PiecewiseAffineWarp warp(mesh, withFrameBorder(to, w, h), w, h);
	warp.setSource(withFrameBorder(from, src.width, src.height));
	Image8 out(w, h, 3);
	warp.apply(src, out);
	return out;
}

// The source coordinates of every destination pixel of a warp: a coordinate image warped (bilinear
// interpolation of a linear function is exact inside each triangle).
ImageT<float> sourceCoordinates(const Image8& src, const Points& from, const Points& to, const TriangleMesh& mesh, int w, int h) {
	ImageT<float> xy(src.width, src.height, 3);
	for (int r = 0; r < src.height; ++r)
		for (int c = 0; c < src.width; ++c) {
			float* p = xy.row(r) + 3 * c;
			p[0] = float(c), p[1] = float(r), p[2] = 0;
		}
	PiecewiseAffineWarp warp(mesh, withFrameBorder(to, w, h), w, h);
	warp.setSource(withFrameBorder(from, src.width, src.height));
	ImageT<float> out(w, h, 3);
	warp.apply(xy, out);
	return out;
}

// One resampling with a separable kernel of radius `radius` (weights normalised), at each destination
// pixel's source position.
template <class Kernel>
Image8 resampled(const Image8& src, const ImageT<float>& at, int radius, Kernel kernel) {
	Image8 out(at.width, at.height, 3);
	for (int r = 0; r < at.height; ++r)
		for (int c = 0; c < at.width; ++c) {
			const float* q = at.row(r) + 3 * c;
			const double x = q[0], y = q[1];
			const int ix = int(std::floor(x)), iy = int(std::floor(y));
			double acc[3] = {0, 0, 0}, wsum = 0;
			for (int dy = -radius + 1; dy <= radius; ++dy)
				for (int dx = -radius + 1; dx <= radius; ++dx) {
					const double wgt = kernel(x - (ix + dx)) * kernel(y - (iy + dy));
					const int sx = std::clamp(ix + dx, 0, src.width - 1), sy = std::clamp(iy + dy, 0, src.height - 1);
					const std::uint8_t* p = src.row(sy) + 3 * sx;
					for (int k = 0; k < 3; ++k) acc[k] += wgt * p[k];
					wsum += wgt;
				}
			for (int k = 0; k < 3; ++k) out.row(r)[3 * c + k] = std::uint8_t(std::clamp(std::lround(acc[k] / wsum), 0L, 255L));
		}
	return out;
}

double cubic(double t) {  // Keys, a = −0.5 (Catmull-Rom)
	t = std::abs(t);
	const double a = -0.5;
	return t < 1 ? (a + 2) * t * t * t - (a + 3) * t * t + 1 : t < 2 ? a * t * t * t - 5 * a * t * t + 8 * a * t - 4 * a : 0;
}
double lanczos3(double t) {
	t = std::abs(t);
	if (t < 1e-9) return 1;
	if (t >= 3) return 0;
	const double pt = 3.14159265358979323846 * t;
	return 3 * std::sin(pt) * std::sin(pt / 3) / (pt * pt);
}

// The box around the mouth (grown by half), cut from each image and enlarged ×4 (nearest), side by side.
Image8 sheet(const std::vector<const Image8*>& ims, const std::vector<const Points*>& pts, const std::vector<int>& mouth) {
	const int z = 4;
	std::vector<std::array<int, 4>> boxes;
	int w = 0, h = 0;
	for (std::size_t k = 0; k < ims.size(); ++k) {
		double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
		for (int i : mouth) x0 = std::min(x0, (*pts[k])(i, 0)), x1 = std::max(x1, (*pts[k])(i, 0)), y0 = std::min(y0, (*pts[k])(i, 1)), y1 = std::max(y1, (*pts[k])(i, 1));
		const double g = 0.5 * std::max(x1 - x0, y1 - y0);
		const int c0 = std::max(0, int(x0 - g)), r0 = std::max(0, int(y0 - g)), c1 = std::min(ims[k]->width, int(x1 + g)), r1 = std::min(ims[k]->height, int(y1 + g));
		boxes.push_back({c0, r0, c1, r1});
		w += (c1 - c0) * z + 4, h = std::max(h, (r1 - r0) * z);
	}
	Image8 out(w, h, 3);
	std::fill(out.data.begin(), out.data.end(), std::uint8_t(255));
	int x = 0;
	for (std::size_t k = 0; k < ims.size(); ++k) {
		const auto [c0, r0, c1, r1] = boxes[k];
		for (int r = 0; r < (r1 - r0) * z; ++r)
			for (int c = 0; c < (c1 - c0) * z; ++c)
				for (int ch = 0; ch < 3; ++ch) out.row(r)[3 * (x + c) + ch] = ims[k]->row(r0 + r / z)[3 * (c0 + c / z) + ch];
		x += (c1 - c0) * z + 4;
	}
	return out;
}

}  // namespace

int main(int argc, char** argv) {
	if (argc < 3) {
		std::fprintf(stderr, "usage: bench_detail CORPUS.csv MODEL.thm [MAX_SAMPLES]\n");
		return 2;
	}
	try {
		const Corpus corpus = loadCorpus(argv[1]);
		const FaceModel model = loadModel(argv[2]);
		const std::size_t most = argc > 3 ? std::size_t(std::stoul(argv[3])) : 40;
		std::vector<int> mouth;
		for (std::size_t i = 0; i < model.scheme.pointNames.size(); ++i)
			if (model.scheme.pointNames[i].rfind("OM", 0) == 0 || model.scheme.pointNames[i].rfind("IM", 0) == 0) mouth.push_back(int(i));
		if (mouth.empty()) throw Error("scheme " + model.scheme.name + " has no OM/IM (mouth) points");
		SynthOptions so;
		so.emotionSource = EmotionSource::Corpus;
		Synthesizer synth(model, so);
		Synthesizer::Workspace ws;
		const int W = synth.width(), H = synth.height();
		double sum[8] = {0, 0, 0, 0, 0, 0, 0, 0};
		std::size_t n = 0;
		// Corpus entries and model samples are in the same order (the baseface and closed eyes aside).
		for (std::size_t i = 0; i < model.sampleCount() && n < most; i += std::max<std::size_t>(1, model.sampleCount() / most)) {
			const SampleInfo& s = model.samples[i];
			const CorpusEntry* e = nullptr;
			for (const CorpusEntry& c : corpus.entries)
				if (c.imagePath.size() >= s.image.size() && c.imagePath.compare(c.imagePath.size() - s.image.size(), s.image.size(), s.image) == 0) e = &c;
			if (!e) continue;
			const Image8 source = readImage(e->imagePath);
			Keypose k;
			k.cdv = Cdv::parse(s.cdv);
			k.emotion = Emotion::of(s.emotion == "-" ? Emotion::neutralLabel() : s.emotion);
			k.sample = long(i);
			const std::vector<Keypose> keys{k};
			synth.prepare(keys);
			Image8 rendered;
			Points at;
			synth.renderFrame(Ticks(0), keys, ws, rendered, at);
			const Image8 one = warped(source, e->points, at, model.frameMesh, W, H);
			const Image8 inMean = warped(source, e->points, model.meanShape, model.frameMesh, model.width, model.height);
			const Image8 two = warped(inMean, model.meanShape, at, model.frameMesh, W, H);
			const ImageT<float> coords = sourceCoordinates(source, e->points, at, model.frameMesh, W, H);
			const Image8 bicubic = resampled(source, coords, 2, cubic), lanczos = resampled(source, coords, 3, lanczos3);
			const Image8 meanL = resampled(source, sourceCoordinates(source, e->points, model.meanShape, model.frameMesh, model.width, model.height), 3, lanczos3);
			const Image8 twoL = resampled(meanL, sourceCoordinates(meanL, model.meanShape, at, model.frameMesh, W, H), 3, lanczos3);
			const Image8 lanczosThenBilinear = warped(meanL, model.meanShape, at, model.frameMesh, W, H);
			const Image8 lanczosThenCubic = resampled(meanL, sourceCoordinates(meanL, model.meanShape, at, model.frameMesh, W, H), 2, cubic);
			auto sharpen = [](const Image8& im, double a) {
				Image8 t = im, o = im;
				for (int r = 0; r < im.height; ++r) for (int c = 1; c + 1 < im.width; ++c) for (int k = 0; k < 3; ++k)
					t.row(r)[3*c+k] = std::uint8_t(std::clamp(std::lround((1+2*a)*im.row(r)[3*c+k] - a*(im.row(r)[3*c-3+k] + im.row(r)[3*c+3+k])), 0L, 255L));
				for (int r = 1; r + 1 < im.height; ++r) for (int c = 0; c < im.width; ++c) for (int k = 0; k < 3; ++k)
					o.row(r)[3*c+k] = std::uint8_t(std::clamp(std::lround((1+2*a)*t.row(r)[3*c+k] - a*(t.row(r-1)[3*c+k] + t.row(r+1)[3*c+k])), 0L, 255L));
				return o;
			};
			const Image8 sh1 = warped(sharpen(meanL, 0.125), model.meanShape, at, model.frameMesh, W, H);
			const Image8 sh2 = warped(sharpen(meanL, 0.2), model.meanShape, at, model.frameMesh, W, H);
			std::fprintf(stderr, "%g %g %g %g %g\n", mouthDetail(lanczosThenCubic, at, mouth), mouthDetail(sh1, at, mouth), mouthDetail(sh2, at, mouth), mouthDetail(lanczosThenBilinear, at, mouth), mouthDetail(source, e->points, mouth));
			const double d[8] = {mouthDetail(source, e->points, mouth), mouthDetail(one, at, mouth), mouthDetail(bicubic, at, mouth),
			                     mouthDetail(lanczos, at, mouth), mouthDetail(two, at, mouth), mouthDetail(twoL, at, mouth),
			                     mouthDetail(lanczosThenBilinear, at, mouth), mouthDetail(rendered, at, mouth)};
			for (int j = 0; j < 8; ++j) sum[j] += d[j];
			if (n == 0 && argc > 4)
				writeImage(argv[4], sheet({&source, &one, &bicubic, &lanczos, &rendered}, {&e->points, &at, &at, &at, &at}, mouth));
			++n;
		}
		if (n == 0) throw Error("no exemplar of the model found in the corpus");
		const char* names[8] = {"source", "one warp", "bicubic", "lanczos-3", "two warps", "two lanczos", "lanczos+bil", "rendered"};
		std::printf("mouth detail (variance of the Laplacian, luma), mean of %zu exemplars, %dx%d\n", n, W, H);
		for (int j = 0; j < 8; ++j) std::printf("  %-10s %8.2f  %5.2fx source\n", names[j], sum[j] / double(n), sum[j] / sum[0]);
	} catch (const std::exception& e) {
		std::fprintf(stderr, "bench_detail: %s\n", e.what());
		return 1;
	}
	return 0;
}
