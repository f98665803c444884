// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geometry/shape.h"
#include "test_support.h"
#include "warp/piecewise_affine.h"
#include "warp/prefilter.h"

using namespace talkhead;

namespace {

constexpr double kPi = 3.14159265358979323846;

Image8 stripes(int w, int h) {  // period 4 px along x: a quarter cycle per pixel (half the Nyquist rate)
	Image8 im(w, h, 3);
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x)
			for (int c = 0; c < 3; ++c) im.at(x, y, c) = std::uint8_t(std::lround(128 + 80 * std::cos(kPi * x / 2)));
	return im;
}

// The period-4 component along row 24 (columns 12–51) of an image sampled half a pixel to the right.
double amplitude(const Image8& im) {
	double re = 0, imag = 0;
	int n = 0;
	for (int x = 12; x < 52; ++x, ++n) {
		const double v = im.at(x, 24, 0) - 128;
		re += v * std::cos(kPi * (x - 0.5) / 2), imag += v * std::sin(kPi * (x - 0.5) / 2);
	}
	return 2 * std::sqrt(re * re + imag * imag) / n / 80;
}

Image8 shiftedHalfAPixel(const Image8& src) {
	Points p(4, 2);
	p << 2, 2, 61, 2, 61, 45, 2, 45;
	Points q = p;
	q.col(0).array() -= 0.5;
	PiecewiseAffineWarp shift(delaunayTriangulation(p), q, 64, 48);
	shift.setSource(p);
	Image8 out(64, 48, 3);
	shift.apply(src, out);
	return out;
}

}  // namespace

TEST(Prefilter, makesGoodTheBilinearWarpsLossAtHalfTheNyquistRate) {
	// Issue 47, D84: bilinear keeps cos(π/4) = 0.707 of a period-4 pattern shifted by half a pixel; the
	// 3-tap prefilter with a = 1/8 lifts that frequency by 1 + 2a(1 − cos(π/2)) = 1.25, to 0.884.
	const Image8 s = stripes(64, 48);
	EXPECT_NEAR(amplitude(shiftedHalfAPixel(s)), 0.707, 0.02);
	EXPECT_NEAR(amplitude(shiftedHalfAPixel(prefilteredForBilinear(s, 0.125f))), 0.884, 0.02);
}

TEST(Prefilter, leavesAnImageAloneAtNoStrengthAndWhereTheMaskIsZero) {
	const Image8 pattern = test::testPattern(40, 30);
	EXPECT_EQ(prefilteredForBilinear(pattern, 0.f).data, pattern.data);
	std::vector<float> mask(40 * 30, 0.f);
	for (int y = 0; y < 30; ++y)
		for (int x = 20; x < 40; ++x) mask[std::size_t(y) * 40 + std::size_t(x)] = 1.f;
	const Image8 half = prefilteredForBilinear(pattern, 0.125f, &mask), whole = prefilteredForBilinear(pattern, 0.125f);
	int changed = 0;
	for (int y = 0; y < 30; ++y)
		for (int x = 0; x < 40; ++x)
			for (int c = 0; c < 3; ++c) {
				if (x < 20) ASSERT_EQ(half.at(x, y, c), pattern.at(x, y, c)) << x << "," << y;
				else ASSERT_NEAR(half.at(x, y, c), whole.at(x, y, c), 1) << x << "," << y;
				changed += whole.at(x, y, c) != pattern.at(x, y, c);
			}
	EXPECT_GT(changed, 40 * 30);  // the pattern has edges: the prefilter does change it
}

TEST(Prefilter, inPlaceAndRowByRowGiveTheSameValuesAndAStepOvershootsByAtMostItsTaps) {
	// The keyposes are prefiltered in place in floats, the baseface row by row in bytes: the same pixels.
	Image8 step(32, 16, 3);
	for (int y = 0; y < 16; ++y)
		for (int x = 0; x < 32; ++x)
			for (int c = 0; c < 3; ++c) step.at(x, y, c) = std::uint8_t(x < 16 ? 50 : 200);
	std::vector<float> f(step.data.begin(), step.data.end());
	prefilterForBilinear(f.data(), 32, 16, 3, 0.125f);
	const Image8 rows = prefilteredForBilinear(step, 0.125f);
	for (std::size_t i = 0; i < f.size(); ++i) ASSERT_EQ(rows.data[i], std::uint8_t(std::clamp(f[i] + 0.5f, 0.f, 255.f))) << i;
	// A step of 150 overshoots by a·150 = 18.75 on each side, and nowhere else.
	EXPECT_EQ(rows.at(15, 8, 0), 50 - 19);
	EXPECT_EQ(rows.at(16, 8, 0), 200 + 19);
	EXPECT_EQ(rows.at(14, 8, 0), 50);
	EXPECT_EQ(rows.at(17, 8, 0), 200);
}
