// SPDX-License-Identifier: GPL-3.0-or-later
#include "warp/dissolve_detail.h"

#include <algorithm>
#include <cmath>

namespace talkhead {

std::vector<std::int16_t> fineDetail(const std::uint8_t* plane, int w, int h) {
	// In integers: the 5 × 5 binomial sum S (weights 1 4 6 4 1 ⊗ the same, 256 in all, the edge repeated);
	// H·8 = (256·Y − S) / 32, rounded half away from zero.
	std::vector<std::int16_t> out(std::size_t(std::max(w, 0)) * std::size_t(std::max(h, 0)));
	if (w < 1 || h < 1) return out;
	const std::size_t W = std::size_t(w);
	std::vector<int> rows(W * std::size_t(h)), padded(W + 4);
	for (int y = 0; y < h; ++y) {
		const std::uint8_t* p = plane + std::size_t(y) * W;
		for (std::size_t x = 0; x < W; ++x) padded[x + 2] = p[x];
		padded[0] = padded[1] = p[0], padded[W + 2] = padded[W + 3] = p[W - 1];
		int* r = &rows[std::size_t(y) * W];
		for (std::size_t x = 0; x < W; ++x) r[x] = padded[x] + 4 * padded[x + 1] + 6 * padded[x + 2] + 4 * padded[x + 3] + padded[x + 4];
	}
	for (int y = 0; y < h; ++y) {
		const int* r[5];
		for (int j = 0; j < 5; ++j) r[j] = &rows[std::size_t(std::clamp(y + j - 2, 0, h - 1)) * W];
		const std::uint8_t* p = plane + std::size_t(y) * W;
		std::int16_t* o = &out[std::size_t(y) * W];
		for (std::size_t x = 0; x < W; ++x) {
			const int d = 256 * p[x] - (r[0][x] + 4 * r[1][x] + 6 * r[2][x] + 4 * r[3][x] + r[4][x]);  // |d| ≤ 65280
			o[x] = std::int16_t(d >= 0 ? (d + 16) / 32 : -((-d + 16) / 32));
		}
	}
	return out;
}

std::vector<float> detailEnergy(const std::int16_t* detail, int w, int h) {
	// Per block (bx, by): the mean of H² over [4bx − 2, 4bx + 6) × [4by − 2, 4by + 6) inside the image.
	const int gw = (w + 3) / 4, gh = (h + 3) / 4;
	std::vector<float> out(std::size_t(std::max(gw, 0)) * std::size_t(std::max(gh, 0)));
	if (w < 1 || h < 1) return out;
	std::vector<std::int64_t> colSums(std::size_t(gw) * std::size_t(h));  // per row: the sums over each block's x window
	for (int y = 0; y < h; ++y) {
		const std::int16_t* r = detail + std::size_t(y) * std::size_t(w);
		for (int bx = 0; bx < gw; ++bx) {
			std::int64_t s = 0;
			for (int x = std::max(0, 4 * bx - 2); x < std::min(w, 4 * bx + 6); ++x) s += std::int64_t(r[x]) * r[x];
			colSums[std::size_t(y) * std::size_t(gw) + std::size_t(bx)] = s;
		}
	}
	for (int by = 0; by < gh; ++by) {
		const int ya = std::max(0, 4 * by - 2), yb = std::min(h, 4 * by + 6);
		for (int bx = 0; bx < gw; ++bx) {
			std::int64_t s = 0;
			for (int y = ya; y < yb; ++y) s += colSums[std::size_t(y) * std::size_t(gw) + std::size_t(bx)];
			const int n = (yb - ya) * (std::min(w, 4 * bx + 6) - std::max(0, 4 * bx - 2));
			out[std::size_t(by) * std::size_t(gw) + std::size_t(bx)] = float(double(s) / (64.0 * n));  // (1/8 level)² → levels²
		}
	}
	return out;
}

void DetailDissolve::prepare(const std::int16_t* a, const std::vector<float>& energyA, const std::int16_t* b, const std::vector<float>& energyB, int w,
                             int h) {
	a_ = a, b_ = b, ea_ = &energyA, eb_ = &energyB, w_ = w, h_ = h, gw_ = (w + 3) / 4, gh_ = (h + 3) / 4;
	const std::size_t n = std::size_t(std::max(w, 0)) * std::size_t(std::max(h, 0));
	diff_.resize(n);
	y0_ = h, y1_ = 0;
	for (int y = 0; y < h; ++y) {
		bool differs = false;
		for (std::size_t i = std::size_t(y) * std::size_t(w), e = i + std::size_t(w); i < e; ++i) {
			const int d = std::clamp(int(a[i]) - int(b[i]), -32767, 32767);
			diff_[i] = std::int16_t(d);
			differs |= d != 0;
		}
		if (differs) y0_ = std::min(y0_, y), y1_ = y + 1;
	}
	if (y1_ <= y0_) {
		y0_ = y1_ = 0;
		return;
	}
	y0_ = std::max(0, y0_ - 8), y1_ = std::min(h, y1_ + 8);  // the energy windows' and the interpolation's reach
	ed_ = detailEnergy(diff_.data(), w, h);
	k_.resize(ed_.size());
	kRow_.resize(std::size_t(gw_));
}

void DetailDissolve::setWeight(double w) {
	wb_ = float(std::clamp(w, 0.0, 1.0)), wa_ = 1.f - wb_;
	const float cross = wa_ * wb_;
	for (std::size_t i = 0; i < k_.size(); ++i) {
		const float t = wa_ * (*ea_)[i] + wb_ * (*eb_)[i];
		k_[i] = t > 0.f ? std::sqrt(t / std::max(t - cross * ed_[i], t * (1.f / 2.25f))) : 1.f;
	}
}

void DetailDissolve::restoreRow(int y, std::uint8_t* row, int channels, float scale) {
	if (y < y0_ || y >= y1_ || wb_ <= 0.f || wa_ <= 0.f) return;
	// k between the block centres (4b + 1.5): first down the column of blocks, then along the row.
	const float fy = std::clamp((float(y) - 1.5f) / 4.f, 0.f, float(gh_ - 1));
	const int by = std::min(int(fy), gh_ - 2 < 0 ? 0 : gh_ - 2), by1 = std::min(by + 1, gh_ - 1);
	const float ty = fy - float(by);
	for (int bx = 0; bx < gw_; ++bx) {
		const float k0 = k_[std::size_t(by) * std::size_t(gw_) + std::size_t(bx)], k1 = k_[std::size_t(by1) * std::size_t(gw_) + std::size_t(bx)];
		kRow_[std::size_t(bx)] = k0 + ty * (k1 - k0) - 1.f;
	}
	const std::size_t at = std::size_t(y) * std::size_t(w_);
	const float unit = 0.125f * scale;
	for (int x = 0; x < w_; ++x) {
		const float fx = std::clamp((float(x) - 1.5f) / 4.f, 0.f, float(gw_ - 1));
		const int bx = std::min(int(fx), gw_ - 2 < 0 ? 0 : gw_ - 2), bx1 = std::min(bx + 1, gw_ - 1);
		const float g = kRow_[std::size_t(bx)] + (fx - float(bx)) * (kRow_[std::size_t(bx1)] - kRow_[std::size_t(bx)]);
		if (g == 0.f) continue;
		const float change = g * (wa_ * float(a_[at + std::size_t(x)]) + wb_ * float(b_[at + std::size_t(x)])) * unit;
		std::uint8_t* p = row + std::size_t(x) * std::size_t(channels);
		for (int c = 0; c < channels; ++c) {
			const float v = float(p[c]) + change + 0.5f;
			p[c] = std::uint8_t(v <= 0.f ? 0.f : (v >= 255.f ? 255.f : v));
		}
	}
}

}  // namespace talkhead
