// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "base/error.h"

#include "media/image_io.h"
#include "test_support.h"
#include "warp/piecewise_affine.h"

using namespace talkhead;

namespace {

// Pixels at least `margin` px inside the hull of the points.
std::vector<std::uint8_t> hullMask(const Points& p, int w, int h, double margin) {
	std::vector<cv::Point2f> pts, hull;
	for (Eigen::Index i = 0; i < p.rows(); ++i) pts.emplace_back(float(p(i, 0)), float(p(i, 1)));
	cv::convexHull(pts, hull);
	std::vector<std::uint8_t> m(std::size_t(w) * h, 0);
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x) m[std::size_t(y) * w + x] = cv::pointPolygonTest(hull, cv::Point2f(float(x), float(y)), true) >= margin;
	return m;
}

const CorpusEntry& immEntry(std::size_t i) { return test::immCorpus().entries.at(i); }

}  // namespace

TEST(PiecewiseAffineWarp, identityWarpReturnsTheImage) {
	SKIP_WITHOUT_IMM();
	const CorpusEntry& e = immEntry(0);
	Image8 img = readImage(e.imagePath);
	TriangleMesh mesh = delaunayTriangulation(e.points);
	PiecewiseAffineWarp warp(mesh, e.points, img.width, img.height);
	warp.setSource(e.points);
	Image out(img.width, img.height, 3);
	warp.apply(img, out);
	auto mask = hullMask(e.points, img.width, img.height, 0.5);
	EXPECT_GE(psnr(toFloat(img), out, mask), 60.0);
}

TEST(PiecewiseAffineWarp, globalSimilarityEqualsWarpAffine) {
	SKIP_WITHOUT_IMM();
	const CorpusEntry& e = immEntry(3);
	Image8 img = readImage(e.imagePath);
	const Similarity t = Similarity::fromScaleAngle(1.08, 0.12, -30.0, 12.5);
	Points dst = t.apply(e.points);
	TriangleMesh mesh = delaunayTriangulation(e.points);
	PiecewiseAffineWarp warp(mesh, dst, img.width, img.height);
	warp.setSource(e.points);
	Image8 ours(img.width, img.height, 3);
	warp.apply(img, ours);

	cv::Mat src(img.height, img.width, CV_8UC3, img.data.data()), ref;
	cv::Matx23d M(t.a, -t.b, t.tx, t.b, t.a, t.ty);
	cv::warpAffine(src, ref, M, src.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
	Image8 refImg(img.width, img.height, 3);
	std::memcpy(refImg.data.data(), ref.data, refImg.data.size());
	auto mask = hullMask(dst, img.width, img.height, 1.0);
	EXPECT_GE(psnr(toFloat(ours), toFloat(refImg), mask), 40.0);
}

TEST(PiecewiseAffineWarp, roundTripThroughAnotherShape) {
	SKIP_WITHOUT_IMM();
	const CorpusEntry& s = immEntry(0);
	const CorpusEntry& other = immEntry(15);  // another person's shape, aligned onto this one
	Image8 img = readImage(s.imagePath);
	Eigen::VectorXd w = Eigen::VectorXd::Ones(s.points.rows());
	Points t = alignSimilarity(other.points, s.points, w).apply(other.points);
	TriangleMesh mesh = delaunayTriangulation(s.points);
	PiecewiseAffineWarp forward(mesh, t, img.width, img.height);
	forward.setSource(s.points);
	Image there(img.width, img.height, 3, 0.f);
	forward.apply(img, there);
	PiecewiseAffineWarp back(mesh, s.points, img.width, img.height);
	back.setSource(t);
	Image again(img.width, img.height, 3, 0.f);
	back.apply(there, again);
	auto mask = hullMask(s.points, img.width, img.height, 2.0);
	EXPECT_GE(psnr(toFloat(img), again, mask), 30.0);
}

TEST(PiecewiseAffineWarp, leavesPixelsOutsideTheMeshAlone) {
	Points p(3, 2);
	p << 10, 10, 50, 12, 20, 40;
	TriangleMesh mesh = delaunayTriangulation(p);
	PiecewiseAffineWarp warp(mesh, p, 64, 48);
	warp.setSource(p);
	Image8 src = test::testPattern(64, 48);
	Image8 dst(64, 48, 3, 7);
	warp.apply(src, dst);
	EXPECT_EQ(dst.at(0, 0, 0), 7);
	EXPECT_EQ(dst.at(60, 45, 2), 7);
	EXPECT_EQ(dst.at(25, 20, 1), src.at(25, 20, 1));
}

TEST(PiecewiseAffineWarp, translationBySubpixelMatchesBilinear) {
	// A pure translation by (0.25, 0.5): every output pixel is a known bilinear mix of four inputs.
	Points p(4, 2);
	p << 5, 5, 58, 5, 58, 42, 5, 42;
	Points q = p;
	q.col(0).array() -= 0.25;
	q.col(1).array() -= 0.5;
	TriangleMesh mesh = delaunayTriangulation(p);
	PiecewiseAffineWarp warp(mesh, q, 64, 48);
	warp.setSource(p);
	Image8 src = test::testPattern(64, 48);
	Image dst(64, 48, 3, -1.f);
	warp.apply(src, dst);
	for (int y = 10; y < 38; ++y)
		for (int x = 10; x < 54; ++x)
			for (int c = 0; c < 3; ++c) {
				float expect = 0.75f * 0.5f * src.at(x, y, c) + 0.25f * 0.5f * src.at(x + 1, y, c) + 0.75f * 0.5f * src.at(x, y + 1, c) +
				               0.25f * 0.5f * src.at(x + 1, y + 1, c);
				ASSERT_NEAR(dst.at(x, y, c), expect, 1e-3) << x << "," << y;
			}
}

TEST(PiecewiseAffineWarp, eightBitFastPathAgreesWithFloatPathEverywhere) {
	// Random meshes that reach past every image border: the fixed-point interior path and the clamped
	// border path must agree with the float reference to within rounding (≤ 2 levels).
	Image8 src = test::testPattern(97, 61);
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> u(-20, 120);
	for (int trial = 0; trial < 20; ++trial) {
		Points s(6, 2), d(6, 2);
		for (int i = 0; i < 6; ++i) {
			s.row(i) << u(rng), u(rng) * 0.7;
			d.row(i) << u(rng), u(rng) * 0.7;
		}
		Points sb = withFrameBorder(s, 97, 61), db = withFrameBorder(d, 97, 61);
		TriangleMesh mesh;
		try {
			mesh = delaunayTriangulation(db);
		} catch (const Error&) {
			continue;
		}
		PiecewiseAffineWarp warp(mesh, db, 97, 61);
		warp.setSource(sb);
		Image8 fast(97, 61, 3);
		Image ref(97, 61, 3);
		warp.apply(src, fast);
		warp.apply(toFloat(src), ref);
		for (std::size_t i = 0; i < fast.data.size(); ++i) ASSERT_LE(std::abs(float(fast.data[i]) - ref.data[i]), 2.0f) << "trial " << trial << " at " << i;
	}
}

TEST(PiecewiseAffineWarp, fusedDissolveEqualsTwoWarpsAndABlend) {
	Image8 a = test::testPattern(97, 61), b(97, 61, 3);
	for (std::size_t i = 0; i < b.data.size(); ++i) b.data[i] = std::uint8_t(255 - a.data[i] / 2);
	std::mt19937 rng(11);
	std::uniform_real_distribution<double> u(-10, 105);
	for (int trial = 0; trial < 10; ++trial) {
		Points s(5, 2), t(5, 2), d(5, 2);
		for (int i = 0; i < 5; ++i) {
			s.row(i) << u(rng), u(rng) * 0.6;
			t.row(i) << u(rng), u(rng) * 0.6;
			d.row(i) << u(rng), u(rng) * 0.6;
		}
		Points sb = withFrameBorder(s, 97, 61), tb = withFrameBorder(t, 97, 61), db = withFrameBorder(d, 97, 61);
		TriangleMesh mesh;
		try {
			mesh = delaunayTriangulation(db);
		} catch (const Error&) {
			continue;
		}
		PiecewiseAffineWarp warp(mesh, db, 97, 61);
		for (double w : {0.0, 0.3, 1.0}) {
			Image8 fused(97, 61, 3), wa(97, 61, 3), wb(97, 61, 3);
			warp.dissolve(a, sb, b, tb, w, fused);
			warp.setSource(sb);
			warp.apply(a, wa);
			warp.setSource(tb);
			warp.apply(b, wb);
			for (std::size_t i = 0; i < fused.data.size(); ++i)
				ASSERT_LE(std::abs(double(fused.data[i]) - ((1 - w) * wa.data[i] + w * wb.data[i])), 2.5) << "trial " << trial << " w " << w;
		}
	}
}

TEST(PiecewiseAffineWarp, planeWarpsAgreeWithTheFloatPathEverywhere) {
	// Luma (one channel) and interleaved chroma (two channels into two planes), on random meshes reaching
	// past every border and wide enough for the vector kernel: within rounding of the float reference.
	const int w = 131, h = 67;
	Image8 rgb = test::testPattern(w, h);
	Image8 gray(w, h, 1), pair(w, h, 2);
	for (std::size_t i = 0; i < gray.data.size(); ++i) {
		gray.data[i] = rgb.data[i * 3];
		pair.data[i * 2] = rgb.data[i * 3 + 1];
		pair.data[i * 2 + 1] = rgb.data[i * 3 + 2];
	}
	std::mt19937 rng(5);
	std::uniform_real_distribution<double> u(-20, 150);
	int tested = 0;
	for (int trial = 0; trial < 20; ++trial) {
		Points s(6, 2), d(6, 2);
		for (int i = 0; i < 6; ++i) {
			s.row(i) << u(rng), u(rng) * 0.5;
			d.row(i) << u(rng), u(rng) * 0.5;
		}
		// Every other trial a near-identity map (the vector kernels' row-window paths), the others anything.
		if (trial % 2) d = s + (d - s) * 0.03;
		Points sb = withFrameBorder(s, w, h), db = withFrameBorder(d, w, h);
		TriangleMesh mesh;
		try {
			mesh = delaunayTriangulation(db);
		} catch (const Error&) {
			continue;
		}
		++tested;
		PiecewiseAffineWarp warp(mesh, db, w, h);
		warp.setSource(sb);
		for (int ch : {1, 2}) {
			const Image8& src = ch == 1 ? gray : pair;
			Image ref(w, h, ch);
			warp.apply(toFloat(src), ref);
			std::vector<std::uint8_t> p0(std::size_t(w) * h), p1(std::size_t(w) * h);
			std::uint8_t* planes[2] = {p0.data(), p1.data()};
			warp.applyPlanes(src.data.data(), w, h, std::size_t(w) * ch, ch, planes, std::size_t(w));
			for (std::size_t i = 0; i < p0.size(); ++i)
				for (int c = 0; c < ch; ++c)
					ASSERT_LE(std::abs(float(planes[c][i]) - ref.data[i * std::size_t(ch) + std::size_t(c)]), 2.0f)
					    << "trial " << trial << " channels " << ch << " at " << i;
			// The run-time kernel (AVX2 where the CPU has it) and the scalar one give the same bytes (D74):
			// frames do not depend on the CPU.
			std::vector<std::uint8_t> s0(p0.size(), 7), s1(p0.size(), 7);
			std::uint8_t* scalarPlanes[2] = {s0.data(), s1.data()};
			warp.applyPlanes(src.data.data(), w, h, std::size_t(w) * ch, ch, scalarPlanes, std::size_t(w), true);
			for (std::size_t i = 0; i < p0.size(); ++i)
				for (int c = 0; c < ch; ++c)
					ASSERT_EQ(int(planes[c][i]), int(scalarPlanes[c][i])) << "trial " << trial << " channels " << ch << " at " << i;
		}
	}
	EXPECT_GE(tested, 10);
}

TEST(PiecewiseAffineWarp, lanczosKeepsWhatDoesNotMoveAndTheFineDetailOfAShift) {
	// Issue 47, D80: through the identity, Lanczos-3 returns the image (its weights at a whole pixel are
	// one and zeros); shifted by half a pixel, a pattern of period 4 px keeps ≥ 0.95 of its amplitude
	// where bilinear keeps cos(π/4) = 0.707 (its response at a quarter cycle per pixel).
	Points p(4, 2);
	p << 2, 2, 61, 2, 61, 45, 2, 45;
	TriangleMesh mesh = delaunayTriangulation(p);
	const Image8 pattern = test::testPattern(64, 48);
	PiecewiseAffineWarp same(mesh, p, 64, 48);
	same.setSource(p);
	Image out(64, 48, 3, -1.f);
	same.applyLanczos3(pattern, out);
	for (int y = 3; y < 45; ++y)
		for (int x = 3; x < 61; ++x)
			for (int c = 0; c < 3; ++c) ASSERT_NEAR(out.at(x, y, c), pattern.at(x, y, c), 1e-3) << x << "," << y;
	Image8 stripes(64, 48, 3);
	for (int y = 0; y < 48; ++y)
		for (int x = 0; x < 64; ++x)
			for (int c = 0; c < 3; ++c) stripes.at(x, y, c) = std::uint8_t(std::lround(128 + 100 * std::cos(3.14159265358979 * x / 2)));
	Points q = p;
	q.col(0).array() -= 0.5;
	PiecewiseAffineWarp shift(mesh, q, 64, 48);
	shift.setSource(p);
	Image sharp(64, 48, 3, 0.f), soft(64, 48, 3, 0.f);
	shift.applyLanczos3(stripes, sharp);
	shift.apply(stripes, soft);
	auto amplitude = [](const Image& im) {  // the period-4 component along a row, away from the edges
		double re = 0, im2 = 0;
		int n = 0;
		for (int x = 12; x < 52; ++x, ++n) {
			const double v = im.at(x, 24, 0) - 128;
			re += v * std::cos(3.14159265358979 * (x - 0.5) / 2), im2 += v * std::sin(3.14159265358979 * (x - 0.5) / 2);
		}
		return 2 * std::sqrt(re * re + im2 * im2) / n / 100;
	};
	EXPECT_NEAR(amplitude(soft), 0.707, 0.02);
	EXPECT_GT(amplitude(sharp), 0.95);
}
