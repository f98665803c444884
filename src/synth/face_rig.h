// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "geometry/shape.h"
#include "image/yuv.h"
#include "model/face_model.h"
#include "synth/action_units.h"
#include "synth/au_appearance.h"
#include "synth/synthesizer.h"

namespace talkhead {

// Blinks (D42): one eye's closed lid drawn in the mean-shape frame (a box inside the face box, model
// pixels, soft alpha), as RGB, luma and interleaved chroma; dissolved in as the lids close.
struct ClosedLidPatch {
	int x0 = 0, y0 = 0, w = 0, h = 0;  // even corners and size
	std::vector<float> alpha, alphaC;  // luma-resolution and chroma-resolution weights
	double from = 0;  // 0: dissolved in at min(1, 1.6 × closure) (D42); else from this closure to shut (D50)
	std::vector<std::uint8_t> rgb, y, uv;
};

// What the synthesizer draws on, made once per model, output size and options (issue 30: the first of the
// synthesizer's three parts) and never changed after: the face box, the scheme's eyes and brows, the
// static anchors around the face and the warp meshes (D41), the background, the baseface in YUV, the
// action-unit templates and their indices (D48), the closed lids (D42, D50), and what the head's motion
// was sized for (Synthesizer::setModulator's limits).
struct FaceRig {
	FaceRig(const Face& face, const SynthOptions& options);
	FaceRig(const FaceRig&) = delete;
	FaceRig& operator=(const FaceRig&) = delete;

	int width = 0, height = 0;    // output size
	double scaleX = 1, scaleY = 1;  // model → output pixels
	int roiX0 = 0, roiY0 = 0, roiX1 = 0, roiY1 = 0;  // face box in the model frame (even corners)
	// D41: static anchors around the face (model pixels; in output luma and chroma pixels) and the warp
	// meshes over face points + anchors + frame border: every triangle, and the moving ones (those with a
	// face vertex). The others never change, so the frame outside the moving triangles is the background,
	// drawn once, and a frame costs a warp of the moving part only.
	Points anchors, anchorsOut, anchorsOutChroma;
	TriangleMesh mesh, movingMesh;
	Points meanSource, meanSourceChroma;   // s̄ + anchors + frame border, in luma and chroma pixels
	YuvImage backgroundYuv;                // Direct path: the static frame at the output size
	std::vector<std::uint8_t> baseY, baseUV;  // the baseface in YUV 4:2:0
	// Direct path: the prefilter's strength for this output scale (0: none; warp/prefilter.h, D84) and the
	// baseface as the frame warp samples it (prefiltered with it).
	float prefilter = 0;
	// At the model's own size, how much of it per model-frame pixel (row-major; empty: all of it): what
	// never moves is never resampled, so it is left as it is (D84).
	std::vector<float> prefilterMask;
	Image8 baseface;
	std::vector<EyeSpec> eyes;
	std::vector<BrowSpec> brows;
	double eyeDistance = 0;  // between the eyes' centres on the mean shape, model pixels (brow motion's unit)
	const AuTemplates* auTemplates = nullptr;  // the face's (D48), when action units are asked for
	EyeFrame auFrame;                        // the mean shape's eye frame
	std::vector<int> auEventIndex;           // per modulator AU event: its template
	std::vector<int> auCurveIndex;           // per modulator AU curve: its template
	// D61: the skin of those events' and curves' action units (issue 31), mapped into the face box once;
	// null when none is installed, the scheme has no eyes and brows, or options().auAppearance is off.
	std::unique_ptr<MappedAuAppearance> auSkin;
	std::vector<int> auEventSkin, auCurveSkin;  // per AU event / curve: its map in auSkin, or −1
	std::vector<ClosedLidPatch> eyePatches;
	// Issue 47 (D86): a face with its own shut eyes closes them as a lid comes down over the eye. Per eye, per
	// mean-frame column x0 + i (luma pixels), the open lids' rows: a blink frame's eye between them is
	// drawn from the open eye's rows that the lowered lid leaves visible, so that the frame's warp, which
	// squeezes that band into the narrowed slit, shows them at their own size (half the iris under a lid
	// at half closure, not the whole eye squashed under a drawn line).
	struct EyeSlit {
		int x0 = 0;
		std::vector<float> upper, lower;
	};
	std::vector<EyeSlit> eyeSlits;
	Eigen::RowVector2d centre{0, 0};  // the mean shape's centre (head rotation), model pixels
	Eigen::RowVector2d eyeMid{0, 0};  // between the eyes on the mean shape (a tracked head's pivot, D55)
	bool stabilise = false;           // a tracked head (D55): keypose shapes aligned on their eye corners to s̄
	Eigen::VectorXd stabiliseWeights;
	double faceSize = 1;              // the mean shape's larger side, model pixels
	bool sizedForHead = false, sizedForBlinks = false;
	double headAngle = 0, headShift = 0;

	Points anchored(const Points& face, bool chroma) const;  // output-pixel face points + anchors + border
	const Image8& backgroundRgb() const;                     // the background in RGB (made on first use)

private:
	const FaceModel& model_;
	mutable std::once_flag backgroundRgbOnce_;
	void placeFace(const FaceModel& model, const SynthOptions& o);
	void placeAnchors(const FaceModel& model, const SynthOptions& o);
	void loadAuSkin(const Face& face, const SynthOptions& o);
	void loadActionUnits(const Face& face, const SynthOptions& o);
	void makeMeshes(const FaceModel& model, const SynthOptions& o);
	void makePrefilterMask(const FaceModel& model, const SynthOptions& o);
	void makeClosedLids(const Face& face, const SynthOptions& o);
	mutable Image8 backgroundRgb_;
};

// Face points, then the static anchors (D41), then the frame border: the vertices of the synthesizer's mesh.
Points withAnchors(const Points& face, const Points& anchors, int width, int height);
// Luma pixel coordinates → 4:2:0 chroma sample coordinates (a chroma sample is centred on its 2×2 block).
Points toChroma(const Points& p);
// y of a polyline (points in order of x, as lids run corner to corner) at x; NaN outside its x range.
double polylineY(const std::vector<Eigen::RowVector2d>& line, double x);
// An eye's upper or lower lid, corner to corner.
std::vector<Eigen::RowVector2d> lidLine(const Points& p, const EyeSpec& e, bool upper);

}  // namespace talkhead
