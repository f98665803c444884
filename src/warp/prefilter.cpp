// SPDX-License-Identifier: GPL-3.0-or-later
#include "warp/prefilter.h"

#include <algorithm>

namespace talkhead {

double prefilterStrength(double scale) { return 0.125 * std::clamp((scale - 0.5) / 0.5, 0.0, 1.0); }

void prefilterForBilinear(float* data, int width, int height, int channels, float a) {
	if (a == 0.f || width < 1 || height < 1) return;
	const float c = 1.f + 2.f * a;
	const std::size_t stride = std::size_t(width) * std::size_t(channels);
	std::vector<float> line(std::max(stride, std::size_t(height) * std::size_t(channels)) + 2 * std::size_t(channels));
	for (int y = 0; y < height; ++y) {  // rows: the row with its edge pixels repeated, then the taps
		float* row = data + std::size_t(y) * stride;
		std::copy(row, row + channels, line.begin());
		std::copy(row, row + stride, line.begin() + channels);
		std::copy(row + stride - channels, row + stride, line.begin() + std::ptrdiff_t(channels + stride));
		const float* l = line.data() + channels;
		const float* left = line.data();
		const float* right = line.data() + 2 * channels;
		for (std::size_t i = 0; i < stride; ++i) row[i] = c * l[i] - a * (left[i] + right[i]);
	}
	std::vector<float> above(stride), here(stride);
	std::copy(data, data + stride, above.begin());
	for (int y = 0; y < height; ++y) {  // columns: rows y−1 (kept before it was overwritten), y, y+1
		float* row = data + std::size_t(y) * stride;
		const float* below = y + 1 < height ? row + stride : row;
		std::copy(row, row + stride, here.begin());
		for (std::size_t i = 0; i < stride; ++i) row[i] = c * here[i] - a * (above[i] + below[i]);
		above.swap(here);
	}
}

Image8 prefilteredForBilinear(const Image8& image, float a, const std::vector<float>* mask) {
	if (a == 0.f || image.empty()) return image;
	// Row by row through three filtered rows (the whole image in floats would cost more in fresh pages than
	// in arithmetic): the same operations in the same order as prefilterForBilinear, so the same values.
	const int w = image.width, h = image.height, ch = image.channels;
	const float c = 1.f + 2.f * a;
	const std::size_t stride = std::size_t(w) * std::size_t(ch);
	std::vector<float> line(stride + 2 * std::size_t(ch)), rows(3 * stride);
	auto filterRow = [&](int y, float* out) {
		const std::uint8_t* row = image.row(y);
		for (int k = 0; k < ch; ++k) line[std::size_t(k)] = row[k], line[stride + std::size_t(ch + k)] = row[stride - std::size_t(ch) + std::size_t(k)];
		for (std::size_t i = 0; i < stride; ++i) line[std::size_t(ch) + i] = row[i];
		const float *l = line.data() + ch, *left = line.data(), *right = line.data() + 2 * ch;
		for (std::size_t i = 0; i < stride; ++i) out[i] = c * l[i] - a * (left[i] + right[i]);
	};
	Image8 out(w, h, ch);
	float* slot[3] = {rows.data(), rows.data() + stride, rows.data() + 2 * stride};  // above, here, below
	filterRow(0, slot[1]);
	std::copy_n(slot[1], stride, slot[0]);
	for (int y = 0; y < h; ++y) {
		if (y + 1 < h) filterRow(y + 1, slot[2]);
		else std::copy_n(slot[1], stride, slot[2]);
		std::uint8_t* o = out.row(y);
		const std::uint8_t* x = image.row(y);
		const float* m = mask ? mask->data() + std::size_t(y) * std::size_t(w) : nullptr;
		for (std::size_t i = 0; i < stride; ++i) {
			float v = c * slot[1][i] - a * (slot[0][i] + slot[2][i]);
			if (m) v = float(x[i]) + m[i / std::size_t(ch)] * (v - float(x[i]));
			v += 0.5f;
			o[i] = std::uint8_t(v <= 0.f ? 0.f : (v >= 255.f ? 255.f : v));
		}
		std::rotate(slot, slot + 1, slot + 3);
	}
	return out;
}

}  // namespace talkhead
