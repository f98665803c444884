// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "model/face_model.h"
#include "phonetics/language.h"
#include "warp/piecewise_affine.h"

namespace talkhead {

enum class Trajectory { Hermite, Linear };

struct SynthOptions {
	std::string emotion = "neutral";  // canonical label
	int width = 0, height = 0;        // output size; 0 = the model's frame size
	Trajectory trajectory = Trajectory::Hermite;  // feature points between keyposes (spec §5.5)
	Trajectory dissolve = Trajectory::Linear;     // cross-dissolve weight: t (thesis) or the Hermite ease
};

// A keypose ready to morph: its image (model frame, 8-bit RGB) and its shape (model pixels).
struct KeyposeImage {
	Image8 image;
	Points shape;
	std::string usedEmotion, usedCdv;  // the model entry it came from (after fallbacks)
};

// The synthesizer of Costa (2015) §5: keypose appearances composited coarse to fine into the baseface and
// warped to their shapes (cached per CDV), then frames by Hermite point trajectories, forward and
// backward piecewise-affine warps and a cross-dissolve. Thread-safe: renderFrame may be called from
// several threads (each with its own FrameWorkspace).
class Synthesizer {
public:
	Synthesizer(const FaceModel& model, const SynthOptions& options);
	int width() const { return width_; }
	int height() const { return height_; }

	// The keypose image of a CDV for the emotion (computed once). Missing (emotion, CDV) entries fall back
	// to neutral for that CDV, then to the other CDVs of the same homorganic group.
	const KeyposeImage& keypose(const std::string& cdv);
	// Substitutions made so far: "emotion cdv → emotion' cdv'".
	std::vector<std::string> substitutions() const;
	// Computes every keypose of a timeline up front (so frames can then be drawn in parallel).
	void prepare(const std::vector<Keypose>& keys);

	struct Workspace {
		std::unique_ptr<PiecewiseAffineWarp> warp;
		double warpSeconds = 0;  // time spent in the warp+dissolve pass, for benchmarks
	};
	// Draws the frame at time τ (keyposes must be prepared) into `out` (output size) and its feature
	// points (output pixels) into `points`.
	void renderFrame(Ticks tau, const std::vector<Keypose>& keys, Workspace& ws, Image8& out, Points& points) const;

	// Spec §5.5: the point-set at normalised time t between S and T.
	static Points trajectory(const Points& s, const Points& t, double u, Trajectory kind);

private:
	const FaceModel& model_;
	SynthOptions o_;
	int width_, height_;
	double scaleX_, scaleY_;
	mutable std::mutex mutex_;
	std::map<std::string, std::unique_ptr<KeyposeImage>> cache_;
	std::vector<std::string> substitutions_;
	const KeyposeImage& cached(const std::string& cdv) const;
	long resolve(const std::string& cdv) const;  // the model sample used for a CDV
};

}  // namespace talkhead
