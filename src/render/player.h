// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "base/ticks.h"
#include "geometry/shape.h"
#include "image/image.h"
#include "image/yuv.h"
#include "render/matte.h"
#include "render/render.h"
#include "synth/synthesizer.h"

namespace talkhead {

// One frame player (issue 46): how a frame of a timeline is drawn, for renderPerformance and live sessions
// alike — the keypose images the frames need made first, then per frame the synthesizer's frame at the
// fitted size (straight into YUV, or through RGB when asked), the debug overlay, the fit into the output
// frame (cropped or padded, the points moved with it) and the face's matte.

// A frame's buffers, reused frame after frame (no allocation once sized).
struct FrameSlot {
	YuvImage yuv;                    // the output frame (and its matte, `a`, when asked)
	Image8 rgb;                      // its RGB, when asked
	YuvImage innerYuv;               // the drawn frame before it is placed (only when the fit places it)
	Image8 innerRgb;
	Points points;                   // output pixels
	bool drawn = false;              // holds an earlier frame of this player, untouched since (D41)
};

class FramePlayer {
public:
	// `options.synth` holds the expression and the shape modulator the face box is sized for (a later
	// plan: synthesizer().setModulator); its size is the output's (0: the model's), fitted as `options.fit`
	// says. Frames are YUV 4:2:0 in limited range (what H.264 and y4m readers assume).
	FramePlayer(const Face& face, const RenderOptions& options);
	int width() const { return width_; }  // of the output frame
	int height() const { return height_; }
	bool places() const { return fit_.place; }  // the drawn frame is placed into an output of another size
	Synthesizer& synthesizer() { return *synth_; }
	const Synthesizer& synthesizer() const { return *synth_; }
	// The keypose images frames from `from` to `to` need, made now (thread-safe; what is made is kept).
	void prepare(const std::vector<Keypose>& keys, Ticks from, Ticks to);
	// Draws the frame at `t` of `keys` (prepared) into `slot`: `rgb` too when asked, the face's matte into
	// slot.yuv.a when `alpha`. Any thread, one workspace each.
	void draw(Ticks t, const std::vector<Keypose>& keys, Synthesizer::Workspace& ws, FrameSlot& slot, bool rgb, bool alpha) const;

private:
	// --debug-overlay: the time, the keyposes around it, the lids and the head.
	std::vector<std::string> overlayLines(Ticks t, const std::vector<Keypose>& keys) const;
	OutputFit fit_;
	int width_ = 0, height_ = 0;
	bool overlay_ = false;
	FaceMatte matte_;
	std::unique_ptr<Synthesizer> synth_;
};

}  // namespace talkhead
