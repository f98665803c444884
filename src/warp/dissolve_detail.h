// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <vector>

namespace talkhead {

// A cross-dissolve (1 − w)·A + w·B of two images whose fine texture differs loses that texture: where the two
// are uncorrelated, the blend's fine detail has (1 − w)² + w² of their energy, half of it halfway (issue 47:
// franck's mouth keeps 0.82 of his exemplars' detail on a keypose and 0.68 mid-dissolve). Where they agree
// (an edge both share, a part of the face that does not change between the two keyposes) the blend keeps it.
//
// DetailDissolve restores, pixel by pixel, the detail energy a dissolve lost: the fine detail of each image
// is H = Y − G(Y) (G: the 5-tap binomial, σ 1 pixel, along rows and columns); its local energy E = box(H²)
// (7 × 7). The blend's detail (1 − w)·H_A + w·H_B has local energy (1 − w)·E_A + w·E_B − w(1 − w)·E_{A−B},
// and is scaled by k = √(((1 − w)·E_A + w·E_B) / that), at most 1.5: k = 1 where the two images' details
// are the same, √2 halfway where they are unrelated. Made once per pair of images, applied per frame.
// Deterministic (plain float arithmetic with no contraction and √, D74).

// The fine detail of an 8-bit plane (w × h, stride w), in luma levels, as 16-bit fixed point (1/8 level).
std::vector<std::int16_t> fineDetail(const std::uint8_t* plane, int w, int h);

class DetailDissolve {
public:
	// For two planes' fine details (fineDetail, w × h each). Reuses its buffers (no allocation once large enough).
	void prepare(const std::int16_t* a, const std::int16_t* b, int w, int h);
	// Row y of the dissolve at weight w (0 … 1): adds (k − 1)·((1 − w)·H_A + w·H_B)·scale to row[0 … w),
	// rounded and clamped to [0, 255]. `channels` interleaved channels of the same pixel get the same change
	// (an RGB row: scale converts luma levels to the channels' levels).
	void restoreRow(int y, double w, std::uint8_t* row, int channels, float scale) const;
	// The box [x0, x1) × [y0, y1) outside which the two details are the same (k = 1 everywhere there).
	int x0() const { return x0_; }
	int x1() const { return x1_; }
	int y0() const { return y0_; }
	int y1() const { return y1_; }

private:
	const std::int16_t *a_ = nullptr, *b_ = nullptr;
	int w_ = 0, h_ = 0, x0_ = 0, x1_ = 0, y0_ = 0, y1_ = 0;
	std::vector<float> ea_, eb_, ed_, squares_, scratch_;
};

}  // namespace talkhead
