// SPDX-License-Identifier: GPL-3.0-or-later
#include "warp/dissolve_detail.h"

#include <algorithm>
#include <cmath>

namespace talkhead {

std::vector<std::int16_t> fineDetail(const std::uint8_t* plane, int w, int h) {
	// In integers: the 5 × 5 binomial sum S (weights 1 4 6 4 1 ⊗ the same, 256 in all, the edge repeated);
	// H·8 = (256·Y − S) / 32, rounded.
	std::vector<std::int16_t> out(std::size_t(w) * std::size_t(std::max(h, 0)));
	if (w < 1 || h < 1) return out;
	static constexpr int k[5] = {1, 4, 6, 4, 1};
	std::vector<int> rows(std::size_t(w) * std::size_t(h));
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x) {
			int s = 0;
			for (int j = -2; j <= 2; ++j) s += k[j + 2] * plane[std::size_t(y) * std::size_t(w) + std::size_t(std::clamp(x + j, 0, w - 1))];
			rows[std::size_t(y) * std::size_t(w) + std::size_t(x)] = s;
		}
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x) {
			int s = 0;
			for (int j = -2; j <= 2; ++j) s += k[j + 2] * rows[std::size_t(std::clamp(y + j, 0, h - 1)) * std::size_t(w) + std::size_t(x)];
			const int d = 256 * plane[std::size_t(y) * std::size_t(w) + std::size_t(x)] - s;  // |d| ≤ 65280
			out[std::size_t(y) * std::size_t(w) + std::size_t(x)] = std::int16_t(d >= 0 ? (d + 16) / 32 : -((-d + 16) / 32));
		}
	return out;
}

namespace {
// out = the 7 × 7 box sum of in (w × h), the edge repeated; scratch holds the row pass.
void boxSum7(const std::vector<float>& in, int w, int h, std::vector<float>& scratch, std::vector<float>& out) {
	scratch.resize(in.size());
	out.resize(in.size());
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x) {
			float s = 0;
			for (int j = -3; j <= 3; ++j) s += in[std::size_t(y) * std::size_t(w) + std::size_t(std::clamp(x + j, 0, w - 1))];
			scratch[std::size_t(y) * std::size_t(w) + std::size_t(x)] = s;
		}
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x) {
			float s = 0;
			for (int j = -3; j <= 3; ++j) s += scratch[std::size_t(std::clamp(y + j, 0, h - 1)) * std::size_t(w) + std::size_t(x)];
			out[std::size_t(y) * std::size_t(w) + std::size_t(x)] = s;
		}
}
}  // namespace

void DetailDissolve::prepare(const std::int16_t* a, const std::int16_t* b, int w, int h) {
	a_ = a, b_ = b, w_ = w, h_ = h;
	const std::size_t n = std::size_t(std::max(w, 0)) * std::size_t(std::max(h, 0));
	// The box of the pixels whose details differ, grown by the energy window's reach.
	x0_ = w, x1_ = 0, y0_ = h, y1_ = 0;
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x)
			if (a[std::size_t(y) * std::size_t(w) + std::size_t(x)] != b[std::size_t(y) * std::size_t(w) + std::size_t(x)])
				x0_ = std::min(x0_, x), x1_ = std::max(x1_, x + 1), y0_ = std::min(y0_, y), y1_ = std::max(y1_, y + 1);
	if (x1_ <= x0_) {
		x0_ = x1_ = y0_ = y1_ = 0;
		return;
	}
	x0_ = std::max(0, x0_ - 3), x1_ = std::min(w, x1_ + 3), y0_ = std::max(0, y0_ - 3), y1_ = std::min(h, y1_ + 3);
	auto energy = [&](auto value, std::vector<float>& out) {  // box(H²), H in luma levels
		squares_.resize(n);
		for (std::size_t i = 0; i < n; ++i) {
			const float v = value(i) * 0.125f;
			squares_[i] = v * v;
		}
		boxSum7(squares_, w, h, scratch_, out);
	};
	energy([&](std::size_t i) { return float(a[i]); }, ea_);
	energy([&](std::size_t i) { return float(b[i]); }, eb_);
	energy([&](std::size_t i) { return float(a[i] - b[i]); }, ed_);
}

void DetailDissolve::restoreRow(int y, double w, std::uint8_t* row, int channels, float scale) const {
	if (y < y0_ || y >= y1_ || !(w > 0 && w < 1)) return;
	const float wb = float(w), wa = 1.f - wb, cross = wa * wb;
	const std::size_t at = std::size_t(y) * std::size_t(w_);
	for (int x = x0_; x < x1_; ++x) {
		const std::size_t i = at + std::size_t(x);
		const float t = wa * ea_[i] + wb * eb_[i];
		if (!(t > 0.f)) continue;
		const float kept = std::max(t - cross * ed_[i], t * (1.f / 2.25f));  // k ≤ 1.5
		const float k = std::sqrt(t / kept);
		const float d = (k - 1.f) * (wa * float(a_[i]) + wb * float(b_[i])) * 0.125f * scale;
		std::uint8_t* p = row + std::size_t(x) * std::size_t(channels);
		for (int c = 0; c < channels; ++c) {
			const float v = float(p[c]) + d + 0.5f;
			p[c] = std::uint8_t(v <= 0.f ? 0.f : (v >= 255.f ? 255.f : v));
		}
	}
}

}  // namespace talkhead
