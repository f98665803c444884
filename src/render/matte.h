// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/scheme.h"
#include "geometry/shape.h"

namespace talkhead {

// Video with alpha (--background transparent, issue 33): which pixels of a frame are the face.
struct MatteOptions {
	double feather = 0;  // σ of the matte's edge in output pixels; 0: 2 % of the face's width (at least 1.5 px)
};

// The matte of a frame from its feature points (D65): the convex hull of the points — with a forehead
// added when the scheme has none (nothing above the brows, as dlib's 68 points: an arc rising half the
// brow-to-chin height above them) — pushed out by two σ so that the outline is opaque (≥ 97.7 %), then
// blurred by a Gaussian of σ: 255 on the face, 0 away from it, a soft edge between. Deterministic;
// thread-safe (scratch per thread, no allocation per frame once sized).
class FaceMatte {
public:
	explicit FaceMatte(const Scheme& scheme, MatteOptions options = {});
	// `alpha` becomes width × height (row-major) for `points` in the same pixels.
	void draw(const Points& points, int width, int height, std::vector<std::uint8_t>& alpha) const;
	// σ for a face whose points span `faceWidth` pixels.
	double feather(double faceWidth) const;

private:
	std::vector<int> brows_;  // the scheme's brow points (none: the topmost point stands for them)
	MatteOptions options_;
};

}  // namespace talkhead
