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
// DetailDissolve restores the detail energy a dissolve lost. Each image's fine detail is H = Y − G(Y) (G: the
// 5-tap binomial, σ 1 pixel, along rows and columns); its local energy E is the mean of H² over 8 × 8 pixels
// around each 4 × 4 block. The blend's detail (1 − w)·H_A + w·H_B has local energy (1 − w)·E_A + w·E_B −
// w(1 − w)·E_{A−B}; it is scaled by k = √(((1 − w)·E_A + w·E_B) / that), at most 1.5, interpolated bilinearly
// between the blocks' centres: k = 1 where the two images' details are the same, √2 halfway where they are
// unrelated. The details and energies are made once per image, E_{A−B} once per pair; a frame costs a
// square root per block and a multiply-add per pixel where k may exceed 1.02 (elsewhere k stays 1). Deterministic: integer details, IEEE float
// operations in a fixed order (no contraction, D74).

// The fine detail of an 8-bit plane (w × h, stride w), in luma levels, as 16-bit fixed point (1/8 level).
std::vector<std::int16_t> fineDetail(const std::uint8_t* plane, int w, int h);
// The local energies of a detail (levels²), one per 4 × 4 block (ceil(w/4) × ceil(h/4), row-major).
std::vector<float> detailEnergy(const std::int16_t* detail, int w, int h);

// What a pair of details needs, made once per pair and shared by the threads drawing its frames: E_{A−B} per
// block, the blocks whose k may exceed 1.02 (elsewhere k stays 1), and the rows [y0, y1) where any may.
struct DetailPair {
	std::vector<float> ed;
	std::vector<std::uint8_t> active;
	int y0 = 0, y1 = 0;
};
DetailPair detailPair(const std::int16_t* a, const std::vector<float>& energyA, const std::int16_t* b, const std::vector<float>& energyB, int w, int h);

class DetailDissolve {
public:
	// For two planes' details and energies (w × h) and their pair (kept by reference until the next prepare),
	// or with a pair of its own. Reuses its buffers (no allocation once large enough).
	void prepare(const std::int16_t* a, const std::vector<float>& energyA, const std::int16_t* b, const std::vector<float>& energyB,
	             const DetailPair& pair, int w, int h);
	void prepare(const std::int16_t* a, const std::vector<float>& energyA, const std::int16_t* b, const std::vector<float>& energyB, int w, int h);
	// Sets the weight w (0 … 1) of the frames drawn next (the blocks' k).
	void setWeight(double w);
	// Row y of the dissolve at the weight set: adds (k − 1)·((1 − w)·H_A + w·H_B)·scale to row[0 … w), rounded
	// and clamped to [0, 255]. `channels` interleaved channels of a pixel get the same change (an RGB row:
	// scale converts luma levels to the channels' levels).
	void restoreRow(int y, std::uint8_t* row, int channels, float scale);
	// The rows [y0, y1) outside which the two details are the same (k = 1 there).
	int y0() const { return pair_ ? pair_->y0 : 0; }
	int y1() const { return pair_ ? pair_->y1 : 0; }

private:
	const std::int16_t *a_ = nullptr, *b_ = nullptr;
	const std::vector<float>*ea_ = nullptr, *eb_ = nullptr;
	int w_ = 0, gw_ = 0, gh_ = 0;
	float wa_ = 1, wb_ = 0;
	const DetailPair* pair_ = nullptr;
	DetailPair own_;
	std::vector<float> k_, kRow_;       // k per block; k − 1 of the row being drawn, per block column
	std::vector<int> bx0_, bx1_;        // per column (of w_): the block columns it lies between
	std::vector<float> fx_;             // and how far from the first
	std::vector<float> gain_;           // k − 1 of each pixel of the row being drawn
};

}  // namespace talkhead
