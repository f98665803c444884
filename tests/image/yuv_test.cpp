// SPDX-License-Identifier: GPL-3.0-or-later
// The image module (issue 30: it had no tests of its own): RGB → YUV 4:2:0 against BT.601's known values,
// in both ranges, with chroma the mean of its 2×2 block; PSNR and SSIM at their known points.
#include <gtest/gtest.h>

#include <cmath>

#include "image/image.h"
#include "image/yuv.h"

using namespace talkhead;

namespace {
Image8 solid(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
	Image8 im(w, h, 3);
	for (std::size_t i = 0; i < im.pixelCount(); ++i) im.data[3 * i] = r, im.data[3 * i + 1] = g, im.data[3 * i + 2] = b;
	return im;
}
}  // namespace

TEST(Yuv, bt601LevelsInBothRanges) {
	YuvImage yuv;
	rgbToYuv420(solid(4, 2, 0, 0, 0), yuv, YuvRange::Limited);
	EXPECT_EQ(yuv.y[0], 16);
	EXPECT_EQ(yuv.u[0], 128);
	EXPECT_EQ(yuv.v[0], 128);
	rgbToYuv420(solid(4, 2, 255, 255, 255), yuv, YuvRange::Limited);
	EXPECT_EQ(yuv.y[0], 235);
	EXPECT_EQ(yuv.u[0], 128);
	rgbToYuv420(solid(4, 2, 255, 255, 255), yuv, YuvRange::Full);
	EXPECT_EQ(yuv.y[0], 255);
	// Pure red, limited range: Y 81, Cb 90, Cr 240 (BT.601).
	rgbToYuv420(solid(4, 2, 255, 0, 0), yuv, YuvRange::Limited);
	EXPECT_NEAR(yuv.y[0], 81, 1);
	EXPECT_NEAR(yuv.u[0], 90, 1);
	EXPECT_NEAR(yuv.v[0], 240, 1);
	ASSERT_EQ(yuv.y.size(), 8u);
	ASSERT_EQ(yuv.u.size(), 2u);  // ⌈4/2⌉ × ⌈2/2⌉
}

TEST(Yuv, chromaIsTheMeanOfItsBlockAndOddSizesRoundUp) {
	Image8 im = solid(3, 3, 0, 0, 0);
	// The top-left 2×2 block: two red and two black pixels → Cr halfway between black's 128 and red's 240.
	im.at(0, 0, 0) = 255;
	im.at(1, 1, 0) = 255;
	YuvImage yuv;
	rgbToYuv420(im, yuv, YuvRange::Limited);
	EXPECT_EQ(yuv.chromaWidth(), 2);
	EXPECT_EQ(yuv.chromaHeight(), 2);
	EXPECT_NEAR(yuv.v[0], (128 + 240) / 2.0, 1);
	EXPECT_EQ(yuv.v[3], 128);  // the corner block: black only
	// No allocation once sized: the same buffers are reused.
	const std::uint8_t* before = yuv.y.data();
	rgbToYuv420(im, yuv, YuvRange::Limited);
	EXPECT_EQ(yuv.y.data(), before);
}

TEST(ImageMetrics, psnrAndSsimAtKnownPoints) {
	const Image a = toFloat(solid(16, 16, 100, 100, 100));
	Image b = a;
	EXPECT_TRUE(std::isinf(psnr(a, b)) || psnr(a, b) > 100);
	EXPECT_NEAR(ssim(a, b), 1.0, 1e-9);
	for (float& v : b.data) v += 10;  // MSE 100 → 10·log10(255² / 100) = 28.13 dB
	EXPECT_NEAR(psnr(a, b), 28.13, 0.01);
	EXPECT_NEAR(psnrFromMse(100), 28.13, 0.01);
}
