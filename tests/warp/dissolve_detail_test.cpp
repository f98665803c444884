// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "warp/dissolve_detail.h"

using namespace talkhead;

namespace {

constexpr int W = 64, H = 48;

// A flat grey plane with its own fine texture: independent noise of ±`amp` levels per seed.
std::vector<std::uint8_t> textured(unsigned seed, int amp) {
	std::mt19937 rng(seed);
	std::uniform_int_distribution<int> d(-amp, amp);
	std::vector<std::uint8_t> p(std::size_t(W) * H);
	for (auto& v : p) v = std::uint8_t(128 + d(rng));
	return p;
}

std::vector<std::uint8_t> blend(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int wb) {
	std::vector<std::uint8_t> o(a.size());
	for (std::size_t i = 0; i < a.size(); ++i) o[i] = std::uint8_t((a[i] * (256 - wb) + b[i] * wb + 128) >> 8);
	return o;
}

// Mean energy of the fine detail (fineDetail, luma levels²) over the interior.
double detailEnergy(const std::vector<std::uint8_t>& p) {
	const std::vector<std::int16_t> h = fineDetail(p.data(), W, H);
	double e = 0;
	int n = 0;
	for (int y = 4; y < H - 4; ++y)
		for (int x = 4; x < W - 4; ++x, ++n) {
			const double v = h[std::size_t(y) * W + std::size_t(x)] / 8.0;
			e += v * v;
		}
	return e / n;
}

}  // namespace

TEST(DissolveDetail, twoUnrelatedTexturesKeepTheirEnergyHalfwayWhereThePlainBlendHalvesIt) {
	// Known answer: for independent textures of equal energy E the blend at ½ has E/2; restored, E (± a tenth).
	const auto a = textured(1, 20), b = textured(2, 20);
	const auto ha = fineDetail(a.data(), W, H), hb = fineDetail(b.data(), W, H);
	const double ea = detailEnergy(a), eb = detailEnergy(b);
	auto plain = blend(a, b, 128);
	EXPECT_NEAR(detailEnergy(plain) / (0.5 * (ea + eb)), 0.5, 0.06);
	const auto ga = detailEnergy(ha.data(), W, H), gb = detailEnergy(hb.data(), W, H);
	DetailDissolve d;
	d.prepare(ha.data(), ga, hb.data(), gb, W, H);
	d.setWeight(0.5);
	for (int y = 0; y < H; ++y) d.restoreRow(y, plain.data() + std::size_t(y) * W, 1, 1.f);
	EXPECT_NEAR(detailEnergy(plain) / (0.5 * (ea + eb)), 1.0, 0.1);
	// The mean is untouched (the detail has none).
	double mean = 0;
	for (auto v : plain) mean += v;
	EXPECT_NEAR(mean / double(plain.size()), 128.0, 0.5);
}

TEST(DissolveDetail, whatBothImagesShareIsLeftByteForByte) {
	// The same texture on the pair's left side (a shared edge, a part that does not change), different textures
	// on the right: the left 20 columns (beyond the energy windows' and the interpolation's reach) stay as blended.
	auto a = textured(3, 30), b = textured(4, 30);
	for (int y = 0; y < H; ++y)
		for (int x = 0; x < 36; ++x) b[std::size_t(y) * W + std::size_t(x)] = a[std::size_t(y) * W + std::size_t(x)];
	const auto ha = fineDetail(a.data(), W, H), hb = fineDetail(b.data(), W, H);
	const auto ga = detailEnergy(ha.data(), W, H), gb = detailEnergy(hb.data(), W, H);
	DetailDissolve d;
	d.prepare(ha.data(), ga, hb.data(), gb, W, H);
	const auto plain = blend(a, b, 100);
	auto restored = plain;
	d.setWeight(100 / 256.0);
	for (int y = 0; y < H; ++y) d.restoreRow(y, restored.data() + std::size_t(y) * W, 1, 1.f);
	int changed = 0;
	for (int y = 0; y < H; ++y)
		for (int x = 0; x < W; ++x) {
			const std::size_t i = std::size_t(y) * W + std::size_t(x);
			if (x < 20) {
				ASSERT_EQ(restored[i], plain[i]) << x << "," << y;
			}
			changed += restored[i] != plain[i];
		}
	EXPECT_GT(changed, 20 * H);
	// At the ends of the dissolve (w = 0 or 1) nothing changes, and identical images give an empty box.
	auto end = plain;
	for (double w : {0.0, 1.0}) {
		d.setWeight(w);
		for (int y = 0; y < H; ++y) d.restoreRow(y, end.data() + std::size_t(y) * W, 1, 1.f);
	}
	EXPECT_EQ(end, plain);
	d.prepare(ha.data(), ga, ha.data(), ga, W, H);
	EXPECT_EQ(d.y1(), d.y0());
}

TEST(DissolveDetail, anRgbRowGetsTheSameChangeInEveryChannel) {
	const auto a = textured(5, 25), b = textured(6, 25);
	const auto ha = fineDetail(a.data(), W, H), hb = fineDetail(b.data(), W, H);
	const auto ga = detailEnergy(ha.data(), W, H), gb = detailEnergy(hb.data(), W, H);
	DetailDissolve d;
	d.prepare(ha.data(), ga, hb.data(), gb, W, H);
	d.setWeight(0.5);
	auto luma = blend(a, b, 128);
	std::vector<std::uint8_t> rgb(luma.size() * 3);
	for (std::size_t i = 0; i < luma.size(); ++i) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = luma[i];
	const int y = H / 2;
	d.restoreRow(y, luma.data() + std::size_t(y) * W, 1, 1.f);
	d.restoreRow(y, rgb.data() + std::size_t(y) * W * 3, 3, 1.f);
	for (int x = 0; x < W; ++x)
		for (int c = 0; c < 3; ++c) ASSERT_EQ(rgb[(std::size_t(y) * W + std::size_t(x)) * 3 + std::size_t(c)], luma[std::size_t(y) * W + std::size_t(x)]);
}
