// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <array>
#include <map>
#include <mutex>
#include <memory>
#include <string>
#include <vector>

#include "image/yuv.h"
#include "model/face_model.h"
#include "synth/face.h"
#include "phonetics/language.h"
#include "synth/action_units.h"
#include "synth/modulator.h"

namespace talkhead {

// Feature points between keyposes (spec §5.5, D56). Hermite: the thesis's cubic with zero tangents, a full
// stop at every keypose. Linear: straight lines (MikeTalk-style). Monotone: a cubic Hermite spline through
// the same keyposes whose tangents (per coordinate, Fritsch–Carlson, from the neighbouring keyposes) are
// zero where the motion turns (a local extremum, as the thesis's curve) and carry the motion through a
// keypose it passes on the way, without overshoot; C¹ everywhere.
enum class Trajectory { Hermite, Linear, Monotone };

// How a frame between keyposes is warped. Direct (default): each keypose's composited appearance is kept
// in the mean-shape frame, the two are cross-dissolved there (they differ only inside the face regions)
// and the result is warped once, s̄ → P(t). Keypose (the thesis's literal order, Eq. 5.4): each keypose
// image is first warped s̄ → its shape S, then forward S → P(t) and backward T → P(t), and dissolved. A
// piecewise-affine warp composed over one mesh is the same map (s̄ → S → P(t) = s̄ → P(t)), so both draw
// the same frame up to resampling: Direct resamples once (sharper) and costs one warp instead of three.
enum class WarpPath { Direct, Keypose };

// How the direct path's one resampling keeps detail (issue 47, D84). Sharp (default): the images the frame
// warp samples (the keyposes' appearances and the baseface, each made once) are prefiltered so that the
// bilinear warp's loss of fine detail is made good (warp/prefilter.h); Linear: plain bilinear, as before.
// The thesis's order (WarpPath::Keypose) is always Linear.
enum class Resampling { Sharp, Linear };

// Where an emotion's keyposes come from (D48). Corpus: the model's samples of the emotion (a missing one
// falls back to neutral, and says so). ActionUnits: the neutral samples, their shapes moved by the
// emotion's action units (corpus-tools/data/expression-aus.tsv) through the scheme's AU templates — the
// appearance stays neutral, so wrinkles do not come. Auto: the corpus where the model has the emotion,
// else action units.
enum class EmotionSource { Corpus, ActionUnits, Auto };

struct SynthOptions {
	Expression expression;            // of keyposes without their own (default neutral; intensity: D43)
	int width = 0, height = 0;        // output size; 0 = the model's frame size
	Trajectory trajectory = Trajectory::Hermite;  // feature points between keyposes (spec §5.5)
	Trajectory dissolve = Trajectory::Linear;     // cross-dissolve weight: t (thesis) or the Hermite ease
	WarpPath warpPath = WarpPath::Direct;
	Resampling resampling = Resampling::Sharp;
	YuvRange yuvRange = YuvRange::Limited;         // of renderFrameYuv's output
	// Blinks and head motion (D42); none when null. Blinks need the scheme's eyes ('eye' lines).
	std::shared_ptr<const ShapeModulator> modulator;
	EmotionSource emotionSource = EmotionSource::Auto;  // issue 31: an emotion the model lacks from its action units
	// With action units: the skin's appearance changes too (furrows, wrinkles; issue 31 route 2) where the
	// appearance maps are installed (models/au-appearance.bin). false: the shape alone, as before.
	bool auAppearance = true;
	// D85: on a face other than the one the maps were learned from, the learned lines become the face's own
	// detail deepened (false: the learned maps as they are, the learning face's drawn lines).
	bool auOwnSkin = true;
	// Issue 47: a cross-dissolve between two keyposes keeps the fine detail's energy where their textures
	// differ (warp/dissolve_detail.h) — with Resampling::Sharp at a scale that prefilters; false: the plain
	// blend of Eq. 5.4.
	bool dissolveDetail = true;
};

// A keypose ready to morph: its shape (model pixels) and its appearance: composited in the mean-shape frame
// over the face's bounding box (Direct), or the whole model frame warped to its shape (Keypose path).
struct KeyposeImage {
	Image8 image;                    // WarpPath::Keypose: model frame, warped to `shape`
	std::vector<std::uint8_t> rgb;   // WarpPath::Direct: mean-frame RGB of the face box
	std::vector<std::uint8_t> y, uv; // the same as luma and interleaved chroma (4:2:0) in the synthesizer's range
	std::vector<std::int16_t> detail; // y's fine detail (fineDetail) when dissolves restore it; else empty
	std::vector<float> detailEnergy;  // and its energy per 4 × 4 block (detailEnergy)
	Points shape;
	std::string usedEmotion, usedCdv;  // the model entry it came from (after fallbacks)
	// A keypose from action units whose mouth they open: the neutral sample whose mouth skin it shows (D71),
	// else −1 (its own).
	long mouthSample = -1;
};

// The synthesizer of Costa (2015) §5: keypose appearances composited coarse to fine into the baseface and
// warped to their shapes (cached per CDV), then frames by Hermite point trajectories, forward and
// backward piecewise-affine warps and a cross-dissolve. Thread-safe: renderFrame may be called from
// several threads (each with its own FrameWorkspace).
struct FaceRig;
class KeyposeCache;
class PiecewiseAffineWarp;
class DetailDissolve;
struct DetailPair;

struct KeyposeSource {
	enum class Kind { Own, Borrowed, ActionUnits } kind = Kind::Own;
	std::string emotion, cdv;  // the sample used (ActionUnits: the neutral one moved)
};

class Synthesizer {
public:
	// Draws `face` (its parts loaded once, shared with other synthesizers: synth/face.h).
	Synthesizer(const Face& face, const SynthOptions& options);
	// Draws `model` with a face of its own (no coarticulation model).
	Synthesizer(const FaceModel& model, const SynthOptions& options);
	~Synthesizer();
	Synthesizer(const Synthesizer&) = delete;
	Synthesizer& operator=(const Synthesizer&) = delete;
	int width() const;
	int height() const;

	// The keypose of a CDV for the emotion (computed once; the corpus's first sample of it when it has
	// several: a timeline's keyposes pick theirs by phone context). Missing (emotion, CDV) entries fall back
	// to neutral for that CDV, then to the other CDVs of the same homorganic group. On the Direct path it
	// holds the face box's appearance in the mean-shape frame (no `image`): renderFrame at the keypose's
	// time draws it.
	const KeyposeImage& keypose(Cdv cdv);
	// Substitutions made so far: "emotion cdv → emotion' cdv'".
	std::vector<std::string> substitutions() const;
	// Where the keypose of a CDV in an emotion comes from (issue 47), without drawing it: the emotion's own
	// sample, another sample (the fallbacks: neutral's, the group's, the nearest mouth), or the neutral
	// sample moved by the emotion's action units.
	KeyposeSource keyposeSource(Cdv cdv, Emotion emotion) const;
	// Computes every keypose of a timeline up front (so frames can then be drawn in parallel).
	void prepare(const std::vector<Keypose>& keys);

	// Per-thread scratch: warps and mean-frame buffers, reused from frame to frame (no allocation).
	struct Workspace {
		Workspace();
		~Workspace();
		Workspace(Workspace&&) noexcept;
		Workspace& operator=(Workspace&&) noexcept;
		std::unique_ptr<PiecewiseAffineWarp> warp, chromaWarp;  // the warp stays inside synth/
		Image8 meanRgb, rgb;                     // mean-frame RGB (baseface outside the face box); RGB frame
		std::vector<std::uint8_t> meanY, meanUV;  // the same in YUV 4:2:0 (chroma interleaved)
		std::unique_ptr<DetailDissolve> detail;   // the dissolve's detail for the pair (detailA, detailB)
		const KeyposeImage *detailA = nullptr, *detailB = nullptr;
		std::shared_ptr<const DetailPair> detailPair;
		double warpSeconds = 0;  // CPU time spent in the dissolve and warp passes, for benchmarks
	};
	// Draws the frame at time τ (keyposes must be prepared) into `out` (output size) and its feature
	// points (output pixels) into `points`. `outHoldsFrame`: out holds a frame this synthesizer drew
	// earlier (same call, same size) and nothing has written to it since, so its static background (D41)
	// is already in place and only the moving part is drawn.
	void renderFrame(Ticks tau, const std::vector<Keypose>& keys, Workspace& ws, Image8& out, Points& points,
	                 bool outHoldsFrame = false) const;
	// The same frame as YUV 4:2:0 in options().yuvRange, drawn in YUV (no RGB frame, no conversion pass).
	void renderFrameYuv(Ticks tau, const std::vector<Keypose>& keys, Workspace& ws, YuvImage& out, Points& points,
	                    bool outHoldsFrame = false) const;
	// The keyposes that frames in [from, to] need (the ones bracketing those times, and `margin` more on each
	// side: 1 for Trajectory::Monotone, whose tangents look at the neighbours; see margin()).
	static std::vector<Keypose> keyposesBetween(const std::vector<Keypose>& keys, Ticks from, Ticks to, int margin = 0);
	int margin() const { return o_.trajectory == Trajectory::Monotone ? 1 : 0; }
	// The substitutions a timeline will need, without computing any keypose.
	std::vector<std::string> substitutionsFor(const std::vector<Keypose>& keys) const;
	const SynthOptions& options() const { return o_; }
	// Replaces the shape modulator (a live stream's next plan, render/live.h). Not while frames are being
	// drawn. The face box was sized for the modulator given at construction: a plan that could move the head
	// further, or that has blinks when that one had none, or action-unit events, is a logic_error.
	void setModulator(std::shared_ptr<const ShapeModulator> modulator);

	// Spec §5.5: the point-set at normalised time t between S and T.
	static Points trajectory(const Points& s, const Points& t, double u, Trajectory kind);
	// Trajectory::Monotone between keys[i] and keys[i + 1] (times in any unit) at normalised time u: the
	// keyposes' shapes `shapes[0..3]` = keys i − 1, i, i + 1, i + 2 (null where there is none: the face
	// holds there, tangent 0).
	static Points monotoneTrajectory(const std::array<const Points*, 4>& shapes, const std::array<double, 4>& times, double u);

private:
	Synthesizer(std::unique_ptr<Face> own, const Face* face, const SynthOptions& options);
	std::unique_ptr<Face> ownFace_;        // made for a model alone (the FaceModel constructor)
	const Face& face_;
	const FaceModel& model_;
	SynthOptions o_;
	std::unique_ptr<FaceRig> rig_;         // what frames are drawn on (synth/face_rig.h)
	std::unique_ptr<KeyposeCache> cache_;  // the keyposes' images (synth/keypose_cache.h)
	// The dissolves' pairs (DetailPair), made once by whichever thread draws a pair's first frame.
	mutable std::mutex pairsMutex_;
	mutable std::map<std::pair<const KeyposeImage*, const KeyposeImage*>, std::shared_ptr<const DetailPair>> pairs_;
	void closeEyes(Points& points, double closure) const;
	void drawClosedLids(std::uint8_t* meanY, std::uint8_t* meanUV, std::uint8_t* meanRgb, double closure) const;
	// A frame's place in the timeline: the bracketing keyposes of τ, the morph position u ∈ [0, 1] and the
	// dissolve weight (Eq. 5.4: t or the Hermite ease) as a double and in 1/256.
	struct Between {
		const KeyposeImage *src, *dst;
		double u, w;
		int w256;
		double closure = 0;  // the lids (0 open … 1 shut)
		// D61: the weights of the skin's maps (FaceRig::auSkin) at τ, on both halves of the face, on the
		// image-left and on the image-right half; `skin` lists the maps with any weight.
		static constexpr int kMaxSkin = 32;
		std::array<float, kMaxSkin> both{}, left{}, right{};
		std::array<int, kMaxSkin> skin{};
		int skinCount = 0;
	};
	// Multiplies the mean frame's face box (a plane of `channels` interleaved, `black` its zero) by the
	// skin's gain of f's action units (issue 31).
	void applySkin(const Between& f, std::uint8_t* plane, std::size_t stride, int channels, int black) const;
	// The dissolve's lost fine detail put back into the mean frame's face box (SynthOptions::dissolveDetail):
	// a plane of `channels` interleaved (luma; RGB, each channel alike, `scale` levels per luma level).
	void restoreDetail(const Between& f, Workspace& ws, std::uint8_t* plane, std::size_t stride, int channels, float scale) const;
	// Adds an action unit's weight on one side (−1 image left, +1 image right, 0 both) to its map's.
	static void addSkin(Between& f, int map, double weight, int side);
	// Also sets `points`: the feature points at τ in output pixels.
	Between locate(Ticks tau, const std::vector<Keypose>& keys, Points& points) const;
};

}  // namespace talkhead
