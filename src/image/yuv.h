// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace talkhead {

// BT.601 YUV ranges: limited (16–235 luma; what H.264 players and y4m readers assume) or full (0–255).
enum class YuvRange { Limited, Full };

// A frame in YUV 4:2:0 (BT.601), planes packed: y is width × height, u and v are ⌈w/2⌉ × ⌈h/2⌉. A chroma
// sample is the mean of its 2×2 luma block (centred between them).
struct YuvImage {
	int width = 0, height = 0;
	std::vector<std::uint8_t> y, u, v;
	std::vector<std::uint8_t> a;  // alpha, width × height (255 opaque), only in video with alpha; empty: opaque
	int chromaWidth() const { return (width + 1) / 2; }
	int chromaHeight() const { return (height + 1) / 2; }
	void resize(int w, int h);  // no allocation when the size is unchanged
};

// RGB → YUV 4:2:0 in 8.8 fixed point (chroma from the 2×2 sums). Thread-safe, no allocation once sized.
void rgbToYuv420(const Image8& rgb, YuvImage& yuv, YuvRange range = YuvRange::Limited);

// The same on raw buffers: a w × h RGB block (rgbStride bytes per row) → luma (yStride) and chroma
// planes; u and v advance by chromaStep bytes per sample (1: planar; 2: interleaved UV with v = u + 1).
void rgbToYuv420(const std::uint8_t* rgb, std::size_t rgbStride, int w, int h, YuvRange range, std::uint8_t* y, std::size_t yStride,
                 std::uint8_t* u, std::uint8_t* v, std::size_t chromaStride, int chromaStep);

}  // namespace talkhead
