// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "model/face_model.h"
#include "model/model_file.h"
#include "render/frame_sink.h"
#include "render/matte.h"
#include "perform/performance.h"
#include "synth/synthesizer.h"

namespace talkhead {

// An output size whose aspect differs from the model's frame: the face keeps its proportions.
//  Face (default, issue 47): the whole face kept — scaled to cover the output as far as the face's area
//    (faceArea: every sample's points, a forehead, a margin) still fits inside it, cut around the face,
//    and where the face does not let the frame cover the output, the rest padded as Pad pads.
//  Crop: scaled to cover the output, the overflow cut evenly (the face is larger; a 4:3 face in 16:9
//    loses its chin and forehead).
//  Pad: scaled to fit inside, the rest filled by extending the frame's edge pixels outward.
//  Stretch: scaled separately in x and y (distorts the face).
enum class Fit { Face, Crop, Pad, Stretch };

// How to draw (everything but what: that is the Performance).
struct RenderOptions {
	SynthOptions synth;    // output size (0 = the model's), trajectory, dissolve, warp path; the emotion
	                       // comes from the Performance
	Fit fit = Fit::Face;   // when synth.width × height has another aspect than the model's frame
	unsigned threads = 0;  // drawing threads (0 = all cores)
	bool debugOverlay = false;  // draw the points, keyposes and active controls on every frame (overlay.h)
	MatteOptions matte;         // the face's matte, when a sink needs alpha (video with alpha)
};

// Where the model's frame lands in an output of `width` × `height` (crop or pad): drawn at inner size,
// its top-left corner at (x, y) in the output (negative when cropped). All even (4:2:0).
struct FitBox {
	int innerWidth = 0, innerHeight = 0, x = 0, y = 0;
};
// The part of the model's frame (model pixels) a face takes while it talks: the box around the mean shape
// and every sample's shape, a forehead above the brows where the scheme has no point there (half the
// brow-to-chin height, as the matte draws it), and a margin of a tenth of the box's larger side for the
// head's motion. Empty (x1 <= x0) for a model without points.
struct FaceArea {
	double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
	bool empty() const { return !(x1 > x0 && y1 > y0); }
};
FaceArea faceArea(const FaceModel& model);
// Fit::Face without a face area fits as Crop.
FitBox fitBox(int modelWidth, int modelHeight, int width, int height, Fit fit, const FaceArea& face = {});
// The synthesizer's drawing size for the output `so` asks for (render and live sessions alike): even sizes
// for 4:2:0 (a model with an odd side renders one pixel smaller), and another aspect than the model's frame
// drawn at the fitted size (`so` is set to it), then cropped or padded into the output when `place`.
struct OutputFit {
	FitBox box;
	int outWidth = 0, outHeight = 0;  // what was asked for (0: the model's size)
	bool place = false;               // the drawn frame is placed into an output of another size
};
OutputFit fitOutput(const FaceModel& model, SynthOptions& so, Fit fit);
// `inner` placed into `out` (resized to width × height) with its corner at (x, y): what overflows is cut,
// what is left is filled by repeating the nearest edge pixel.
void placeFitted(const YuvImage& inner, YuvImage& out, int width, int height, int x, int y);

// What a render did, for summaries and benchmarks (seconds are wall time unless said otherwise).
struct RenderStats {
	std::int64_t frames = 0;
	int width = 0, height = 0;
	std::size_t keyposes = 0;
	std::vector<std::string> substitutions;  // "emotion cdv -> emotion' cdv'" the model lacked
	double keyposeSeconds = 0;   // keypose appearances (all batches)
	double drawSeconds = 0;      // drawing frames (wall)
	double warpSeconds = 0;      // CPU seconds in warps and dissolves (summed over threads)
	double writeSeconds = 0;     // sinks on the writer thread (encoding, writing)
	double firstFrameSeconds = 0;  // from the start of renderPerformance to the first frame handed to the sinks
	double totalSeconds = 0;
};

// Progress of a render. All calls come from the thread that called renderPerformance.
class RenderProgress {
public:
	virtual ~RenderProgress() = default;
	// Before the first frame: the stream and the (emotion, viseme) entries the model lacks.
	virtual void started(const StreamInfo& info, const std::vector<std::string>& substitutions) {
		(void)info, (void)substitutions;
	}
	virtual void frames(std::int64_t done, std::int64_t total) { (void)done, (void)total; }
	virtual void finished(const RenderStats& stats) { (void)stats; }
};
// A one-line bar on stderr when it is a terminal.
std::unique_ptr<RenderProgress> makeTerminalProgress();
// JSON lines on `out`: {"type": "progress", "frame": N, "frames": T, "value": F} at each whole percent,
// {"type": "done", "frames": T, "seconds": S} at the end.
std::unique_ptr<RenderProgress> makeJsonProgress(std::FILE* out);

// The face model for rendering: `path`, or the default face when empty (throws Error when none is found).
// Loads only what rendering needs when the model has an appearance cache. `levels`: components kept per
// region (the thesis's Appendix C reductions; model/model_file.h).
FaceModel loadRenderModel(const std::string& path, const ComponentLevels& levels = {});

// Renders every frame of the performance and hands it to the sinks: keyposes made batch by batch as the
// timeline needs them (the first batch is small, so a stream starts after a frame or two), frames drawn in
// parallel straight into YUV (and RGB only when a sink needs it), an in-order writer thread feeding the
// sinks, then finish() and commit() on every sink. On any error nothing is committed (the sinks remove
// their temporaries) and the error propagates. The same inputs give byte-identical frames.
RenderStats renderPerformance(const Face& face, const Performance& performance, const RenderOptions& options,
                              const std::vector<FrameSink*>& sinks, RenderProgress* progress = nullptr);
// The same for a model alone (a face of its own: its parts loaded for this render).
RenderStats renderPerformance(const FaceModel& model, const Performance& performance, const RenderOptions& options,
                              const std::vector<FrameSink*>& sinks, RenderProgress* progress = nullptr);

}  // namespace talkhead
