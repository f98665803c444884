// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

#include "geometry/shape.h"
#include "image/image.h"
#include "image/yuv.h"

namespace talkhead {

// --debug-overlay: what a person checking timing needs on each frame: the feature points, and text lines
// (time, the bracketing keyposes with their emotion and the position between them, the active controls)
// at the top left. Drawn into the frame (white with a dark outline; in YUV on the luma plane).
void drawDebugOverlay(YuvImage& frame, const Points& points, const std::vector<std::string>& lines);
void drawDebugOverlay(Image8& rgb, const Points& points, const std::vector<std::string>& lines);

}  // namespace talkhead
