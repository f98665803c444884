// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "geometry/shape.h"
#include "image/image.h"

namespace talkhead {

// Articulatory parameters of a viseme (corpus-tools/data/viseme-articulation.tsv).
struct Articulation {
	double jaw = 0;     // jaw opening 0..1
	double width = 0;   // mouth-corner spread −1..1
	double round = 0;   // lip rounding / protrusion 0..1
	double upper = 0;   // upper-lip raise 0..1
	double tuck = 0;    // lower lip under the upper teeth 0..1
	double closed = 0;  // lips pressed together 0..1
	double tongue = 0;  // tongue tip raised 0..1
	double teeth = 0;   // teeth shown close together 0..1
};

// Facial action units with intensities 0..1 (corpus-tools/data/expression-aus.tsv).
struct ActionUnits {
	double au1 = 0, au2 = 0, au4 = 0, au5 = 0, au6 = 0, au7 = 0, au9 = 0, au10 = 0, au12 = 0, au15 = 0, au16 = 0, au17 = 0,
	       au20 = 0, au23 = 0, au24 = 0, au25 = 0, au43 = 0, au26 = 0;
};

// Small rigid head motion of one image: rotation (degrees), scale, translation (pixels).
struct HeadPose {
	double angleDeg = 0, scale = 1, dx = 0, dy = 0;
};

struct SynthFace {
	Image8 image;  // RGB
	Points points; // the 56 ch-unicamp-56 points, exact, in image pixels
};

// Draws the parametric face: a shaded, antialiased 2D face (skin, hair, ears, eyes with lids, brows,
// nose, lips, mouth cavity, teeth, tongue) whose feature points are computed from the same parameters
// that draw it. Deterministic: the same inputs give the same bytes.
class FaceRenderer {
public:
	FaceRenderer(int width, int height);
	SynthFace render(const Articulation& a, const ActionUnits& au, const HeadPose& pose) const;
	// The feature points alone (what render() returns in .points), without drawing.
	Points points(const Articulation& a, const ActionUnits& au, const HeadPose& pose) const;
	int width() const { return width_; }
	int height() const { return height_; }

private:
	int width_, height_;
	Image backdrop_;  // background, hair behind the head, neck and shoulders (shared by every image)
};

}  // namespace talkhead
