// SPDX-License-Identifier: GPL-3.0-or-later
#include "image/yuv.h"

#include <algorithm>

#include "base/memory.h"

namespace talkhead {

void YuvImage::resize(int w, int h) {
	width = w;
	height = h;
	const std::size_t c = std::size_t((w + 1) / 2) * std::size_t((h + 1) / 2);
	resizePrefaulted(y, std::size_t(w) * h);
	resizePrefaulted(u, c);
	resizePrefaulted(v, c);
}

void rgbToYuv420(const std::uint8_t* rgb, std::size_t rgbStride, int w, int h, YuvRange range, std::uint8_t* yp, std::size_t yStride,
                 std::uint8_t* up, std::uint8_t* vp, std::size_t chromaStride, int chromaStep) {
	// BT.601 in 8.8 fixed point. Limited: Y = 16 + (66R + 129G + 25B)/256, U = 128 + (−38R − 74G + 112B)/256,
	// V = 128 + (112R − 94G − 18B)/256. Full: Y = (77R + 150G + 29B)/256, U = 128 + (−43R − 85G + 128B)/256,
	// V = 128 + (128R − 107G − 21B)/256.
	const bool full = range == YuvRange::Full;
	const int yr = full ? 77 : 66, yg = full ? 150 : 129, yb = full ? 29 : 25, y0 = full ? 0 : 16;
	const int ur = full ? -43 : -38, ug = full ? -85 : -74, ub = full ? 128 : 112;
	const int vr = full ? 128 : 112, vg = full ? -107 : -94, vb = full ? -21 : -18;
	for (int y = 0; y < h; ++y) {
		const std::uint8_t* p = rgb + std::size_t(y) * rgbStride;
		std::uint8_t* out = yp + std::size_t(y) * yStride;
		for (int x = 0; x < w; ++x, p += 3) out[x] = std::uint8_t(std::min(255, (yr * p[0] + yg * p[1] + yb * p[2] + 128 + (y0 << 8)) >> 8));
	}
	const int cw = (w + 1) / 2, ch = (h + 1) / 2;
	for (int y = 0; y < ch; ++y) {
		const std::uint8_t* r0 = rgb + std::size_t(2 * y) * rgbStride;
		const std::uint8_t* r1 = rgb + std::size_t(std::min(2 * y + 1, h - 1)) * rgbStride;
		std::uint8_t* u = up + std::size_t(y) * chromaStride;
		std::uint8_t* v = vp + std::size_t(y) * chromaStride;
		for (int x = 0; x < cw; ++x, u += chromaStep, v += chromaStep) {
			const int x0 = 2 * x * 3, x1 = std::min(2 * x + 1, w - 1) * 3;
			const int r = r0[x0] + r0[x1] + r1[x0] + r1[x1], g = r0[x0 + 1] + r0[x1 + 1] + r1[x0 + 1] + r1[x1 + 1],
			          b = r0[x0 + 2] + r0[x1 + 2] + r1[x0 + 2] + r1[x1 + 2];
			*u = std::uint8_t(std::clamp((ur * r + ug * g + ub * b + 512 + (128 << 10)) >> 10, 0, 255));
			*v = std::uint8_t(std::clamp((vr * r + vg * g + vb * b + 512 + (128 << 10)) >> 10, 0, 255));
		}
	}
}

void rgbToYuv420(const Image8& rgb, YuvImage& yuv, YuvRange range) {
	if (rgb.channels != 3) throw std::logic_error("rgbToYuv420: RGB input expected");
	yuv.resize(rgb.width, rgb.height);
	const std::size_t cw = std::size_t(yuv.chromaWidth());
	rgbToYuv420(rgb.data.data(), std::size_t(rgb.width) * 3, rgb.width, rgb.height, range, yuv.y.data(), std::size_t(rgb.width), yuv.u.data(),
	            yuv.v.data(), cw, 1);
}

}  // namespace talkhead
