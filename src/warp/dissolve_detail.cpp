// SPDX-License-Identifier: GPL-3.0-or-later
#include "warp/dissolve_detail.h"

#include <emmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstring>

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

DetailPair detailPair(const std::int16_t* a, const std::vector<float>& energyA, const std::int16_t* b, const std::vector<float>& energyB, int w, int h) {
	DetailPair p;
	const std::size_t n = std::size_t(std::max(w, 0)) * std::size_t(std::max(h, 0));
	std::vector<std::int16_t> diff(n);
	int y0 = h, y1 = 0;
	for (int y = 0; y < h; ++y) {
		bool differs = false;
		for (std::size_t i = std::size_t(y) * std::size_t(w), e = i + std::size_t(w); i < e; ++i) {
			const int d = std::clamp(int(a[i]) - int(b[i]), -32767, 32767);
			diff[i] = std::int16_t(d);
			differs |= d != 0;
		}
		if (differs) y0 = std::min(y0, y), y1 = y + 1;
	}
	if (y1 <= y0) return p;
	p.y0 = std::max(0, y0 - 8), p.y1 = std::min(h, y1 + 8);  // the energy windows' and the interpolation's reach
	p.ed = detailEnergy(diff.data(), w, h);
	// A block whose k can never reach 1.02 (at any w: t ≥ min(E_A, E_B), w(1 − w) ≤ ¼) keeps k = 1 exactly, and
	// the pixels whose four blocks all do are not visited: most of a face that does not change.
	p.active.assign(p.ed.size(), 0);
	for (std::size_t i = 0; i < p.ed.size(); ++i) {
		const float m = std::min(energyA[i], energyB[i]), kept = m - 0.25f * p.ed[i];
		p.active[i] = p.ed[i] > 0.f && (kept <= 0.f || m > 1.0404f * kept);
	}
	return p;
}

void DetailDissolve::prepare(const std::int16_t* a, const std::vector<float>& energyA, const std::int16_t* b, const std::vector<float>& energyB, int w,
                             int h) {
	own_ = detailPair(a, energyA, b, energyB, w, h);
	prepare(a, energyA, b, energyB, own_, w, h);
}

void DetailDissolve::prepare(const std::int16_t* a, const std::vector<float>& energyA, const std::int16_t* b, const std::vector<float>& energyB,
                             const DetailPair& pair, int w, int h) {
	a_ = a, b_ = b, ea_ = &energyA, eb_ = &energyB, pair_ = &pair, gh_ = (h + 3) / 4;
	if (pair.y1 <= pair.y0) return;
	k_.resize(pair.ed.size());
	if (w == w_) return;  // the column tables below depend on the width alone
	w_ = w, gw_ = (w + 3) / 4;
	kRow_.resize(std::size_t(gw_));
	gain_.resize(std::size_t(w));
	// Per column: the two block columns it lies between and how far (the same for every row).
	bx0_.resize(std::size_t(w)), bx1_.resize(std::size_t(w)), fx_.resize(std::size_t(w));
	for (int x = 0; x < w; ++x) {
		const float fx = std::clamp((float(x) - 1.5f) / 4.f, 0.f, float(gw_ - 1));
		const int bx = std::min(int(fx), std::max(gw_ - 2, 0));
		bx0_[std::size_t(x)] = bx, bx1_[std::size_t(x)] = std::min(bx + 1, gw_ - 1), fx_[std::size_t(x)] = fx - float(bx);
	}
}

void DetailDissolve::setWeight(double w) {
	wb_ = float(std::clamp(w, 0.0, 1.0)), wa_ = 1.f - wb_;
	const float cross = wa_ * wb_;
	for (std::size_t i = 0; i < k_.size(); ++i) {
		const float t = wa_ * (*ea_)[i] + wb_ * (*eb_)[i];
		k_[i] = pair_->active[i] && t > 0.f ? std::sqrt(t / std::max(t - cross * pair_->ed[i], t * (1.f / 2.25f))) : 1.f;
	}
}

void DetailDissolve::restoreRow(int y, std::uint8_t* row, int channels, float scale) {
	if (!pair_ || y < pair_->y0 || y >= pair_->y1 || wb_ <= 0.f || wa_ <= 0.f) return;
	// k between the block centres (4b + 1.5): first down the column of blocks, then along the row.
	const float fy = std::clamp((float(y) - 1.5f) / 4.f, 0.f, float(gh_ - 1));
	const int by = std::min(int(fy), std::max(gh_ - 2, 0)), by1 = std::min(by + 1, gh_ - 1);
	const float ty = fy - float(by);
	int first = gw_, last = -1;
	for (int bx = 0; bx < gw_; ++bx) {
		const std::size_t i0 = std::size_t(by) * std::size_t(gw_) + std::size_t(bx), i1 = std::size_t(by1) * std::size_t(gw_) + std::size_t(bx);
		const bool on = pair_->active[i0] || pair_->active[i1];
		kRow_[std::size_t(bx)] = on ? k_[i0] + ty * (k_[i1] - k_[i0]) - 1.f : 0.f;
		if (on) first = std::min(first, bx), last = bx;
	}
	if (last < 0) return;
	// The pixels between the first and the last active block column's neighbours (k − 1 = 0 beyond): their
	// gain, then one pass, four pixels at a time where there is one channel (SSE: the same IEEE operations as
	// the scalar tail, and packus saturates as the clamp does).
	const int xa = std::max(0, 4 * first - 3), xb = std::min(w_, 4 * last + 10);
	float* gain = gain_.data();
	for (int x = xa; x < xb; ++x) {
		const float g0 = kRow_[std::size_t(bx0_[std::size_t(x)])];
		gain[x] = g0 + fx_[std::size_t(x)] * (kRow_[std::size_t(bx1_[std::size_t(x)])] - g0);
	}
	const std::int16_t* a = a_ + std::size_t(y) * std::size_t(w_);
	const std::int16_t* b = b_ + std::size_t(y) * std::size_t(w_);
	const float ua = wa_ * 0.125f * scale, ub = wb_ * 0.125f * scale;
	auto change = [&](int x) { return gain[x] * (ua * float(a[x]) + ub * float(b[x])); };
	int x = xa;
	if (channels == 1) {
		const __m128 vua = _mm_set1_ps(ua), vub = _mm_set1_ps(ub), half = _mm_set1_ps(0.5f);
		const __m128i zero = _mm_setzero_si128();
		for (; x + 4 <= xb; x += 4) {
			std::int64_t ab;
			std::memcpy(&ab, a + x, 8);
			const __m128 fa = _mm_cvtepi32_ps(_mm_srai_epi32(_mm_unpacklo_epi16(zero, _mm_cvtsi64_si128(ab)), 16));
			std::memcpy(&ab, b + x, 8);
			const __m128 fb = _mm_cvtepi32_ps(_mm_srai_epi32(_mm_unpacklo_epi16(zero, _mm_cvtsi64_si128(ab)), 16));
			std::int32_t px;
			std::memcpy(&px, row + x, 4);
			const __m128 fp = _mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(px), zero), zero));
			const __m128 d = _mm_mul_ps(_mm_loadu_ps(gain + x), _mm_add_ps(_mm_mul_ps(vua, fa), _mm_mul_ps(vub, fb)));
			const __m128i v = _mm_cvttps_epi32(_mm_add_ps(_mm_add_ps(fp, d), half));
			const __m128i packed = _mm_packus_epi16(_mm_packs_epi32(v, v), zero);
			px = _mm_cvtsi128_si32(packed);
			std::memcpy(row + x, &px, 4);
		}
	}
	for (; x < xb; ++x) {
		const float d = change(x);
		std::uint8_t* p = row + std::size_t(x) * std::size_t(channels);
		for (int c = 0; c < channels; ++c) p[c] = std::uint8_t(std::min(std::max(float(p[c]) + d + 0.5f, 0.f), 255.f));
	}
}

}  // namespace talkhead
