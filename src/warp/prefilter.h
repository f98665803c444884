// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace talkhead {

// The render's bilinear warp is a tent kernel: it keeps a frequency at half the Nyquist rate at 0.81 of its
// amplitude (sinc² ¼) and the Nyquist rate at 0.41, whatever the scale, so a face loses a third of its fine
// detail in the one resampling to the frame (issue 47, D84). Prefiltering the image it samples with the
// separable 3-tap [−a, 1 + 2a, −a] lifts those by 1 + 2a and 1 + 4a: a = 1/8 brings the half-Nyquist
// response back to 1.01 and the Nyquist one to 0.61 (a Catmull-Rom kernel's is 0.5 there), at no cost per
// frame when the images sampled are made once (the keyposes' appearances, the baseface).
//
// The strength for a face drawn at `scale` times its model's size: 1/8 from scale 1 up (enlarged or the
// same size), none at ½ and below (a bilinear reduction aliases already: sharpening would add to it), linear
// between.
double prefilterStrength(double scale);

// In place, a `width` × `height` image of `channels` interleaved floats (row stride width·channels): the
// 3-tap prefilter along rows, then columns, the image's edge repeated. Deterministic (plain float
// arithmetic, no contraction: D74). a = 0 leaves the image as it is.
void prefilterForBilinear(float* data, int width, int height, int channels, float a);

// The same for an 8-bit image, rounded and clamped to [0, 255]. With `mask` (width × height, row-major), pixel
// p becomes x + mask[p]·(prefiltered − x): 0 keeps it as it is (a part of the face that is never resampled).
Image8 prefilteredForBilinear(const Image8& image, float a, const std::vector<float>* mask = nullptr);

}  // namespace talkhead
