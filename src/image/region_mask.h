// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <vector>

#include "geometry/shape.h"

namespace talkhead {

// Closed Catmull-Rom curve (centripetal-free, uniform) through the boundary points, `samplesPerSegment`
// points per segment, as a polygon.
Points closedCatmullRom(const Points& boundary, int samplesPerSegment = 12);

// Soft alpha mask (one float in [0, 1] per pixel, row-major) of a face region: the closed Catmull-Rom
// curve through `boundary` is scaled about its centroid by (1 + grow), filled, and feathered INWARD:
// alpha = smoothstep(d / featherPx) where d is the distance (px) to the curve, so alpha is 0 on the
// curve and 1 from featherPx inside it. featherPx ≤ 0 gives a hard mask.
std::vector<float> softRegionMask(const Points& boundary, double grow, double featherPx, int width, int height);

// Area (px²) of the grown curve polygon, used to turn a relative feather into pixels.
double regionArea(const Points& boundary, double grow);

}  // namespace talkhead
