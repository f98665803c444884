// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace talkhead {

// A packed, row-major, channel-interleaved image (RGB unless stated). T = std::uint8_t for frames and
// files, float (0–255 scale) for model arithmetic.
template <class T>
struct ImageT {
	int width = 0, height = 0, channels = 3;
	std::vector<T> data;

	ImageT() = default;
	ImageT(int w, int h, int c = 3, T fill = T()) : width(w), height(h), channels(c), data(std::size_t(w) * h * c, fill) {
		if (w < 0 || h < 0 || c <= 0) throw std::logic_error("ImageT: bad size");
	}
	bool empty() const { return data.empty(); }
	std::size_t pixelCount() const { return std::size_t(width) * height; }
	T* row(int y) { return data.data() + std::size_t(y) * width * channels; }
	const T* row(int y) const { return data.data() + std::size_t(y) * width * channels; }
	T& at(int x, int y, int c) { return data[(std::size_t(y) * width + x) * channels + c]; }
	const T& at(int x, int y, int c) const { return data[(std::size_t(y) * width + x) * channels + c]; }
};

using Image = ImageT<float>;
using Image8 = ImageT<std::uint8_t>;

Image toFloat(const Image8& in);
// Rounds to nearest and clamps to [0, 255].
Image8 toU8(const Image& in);

// Peak signal-to-noise ratio (peak 255) over the pixels where mask (one byte per pixel, may be empty =
// all pixels) is non-zero; +inf for identical inputs.
double psnr(const Image& a, const Image& b, const std::vector<std::uint8_t>& mask = {});
double psnrFromMse(double mse);

}  // namespace talkhead

namespace talkhead {
// Mean structural similarity (Wang et al. 2004: 11×11 Gaussian window, σ = 1.5, K1 = 0.01, K2 = 0.03,
// peak 255), averaged over channels and over the pixels where mask is non-zero (empty = all).
double ssim(const Image& a, const Image& b, const std::vector<std::uint8_t>& mask = {});
}  // namespace talkhead
