// SPDX-License-Identifier: GPL-3.0-or-later
#include "image/image.h"

#include <cmath>
#include <limits>

namespace talkhead {

Image toFloat(const Image8& in) {
	Image out(in.width, in.height, in.channels);
	for (std::size_t i = 0; i < in.data.size(); ++i) out.data[i] = in.data[i];
	return out;
}

Image8 toU8(const Image& in) {
	Image8 out(in.width, in.height, in.channels);
	for (std::size_t i = 0; i < in.data.size(); ++i) {
		float v = in.data[i] + 0.5f;
		out.data[i] = static_cast<std::uint8_t>(v <= 0.f ? 0.f : (v >= 255.f ? 255.f : v));
	}
	return out;
}

double psnrFromMse(double mse) {
	if (mse <= 0) return std::numeric_limits<double>::infinity();
	return 10.0 * std::log10(255.0 * 255.0 / mse);
}

double psnr(const Image& a, const Image& b, const std::vector<std::uint8_t>& mask) {
	if (a.width != b.width || a.height != b.height || a.channels != b.channels)
		throw std::logic_error("psnr: image sizes differ");
	if (!mask.empty() && mask.size() != a.pixelCount()) throw std::logic_error("psnr: mask size differs");
	double sum = 0;
	std::size_t n = 0;
	const int c = a.channels;
	for (std::size_t p = 0; p < a.pixelCount(); ++p) {
		if (!mask.empty() && !mask[p]) continue;
		for (int k = 0; k < c; ++k) {
			double d = double(a.data[p * c + k]) - b.data[p * c + k];
			sum += d * d;
		}
		n += c;
	}
	return psnrFromMse(n ? sum / n : 0);
}

}  // namespace talkhead
