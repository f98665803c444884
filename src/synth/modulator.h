// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "base/ticks.h"
#include "phonetics/emotion.h"
#include "phonetics/language.h"

namespace talkhead {

// The shape modulator (Costa 2015 §5.4, left unimplemented there; braun-spec §10): what moves besides the
// mouth, applied at every output frame after the keypose trajectory, so it does not depend on phone
// timing. Decision D42.
// A head gesture asked for by a control track: a nod (down and back up) or a shake (two turns left and
// right, as a sideways sway in the picture plane), over `duration`, scaled by `amount` (1 = a clear one).
// A turn moves the head toward `direction` (in the picture: −1 image-left / +1 image-right in x, −1 up /
// +1 down in y), holds it there and brings it back: in over the first quarter of `duration`, back over the
// last. Control tracks name directions as the subject's: "left" is toward the image's right.
struct HeadGesture {
	enum class Kind { Nod, Shake, Turn } kind = Kind::Nod;
	Ticks time{0}, duration{0};
	double amount = 1;
	int directionX = 0, directionY = 0;  // Turn only
};

// An action unit asked for by a control track (D48): rises to `intensity` over `onset` (smoothstep), holds
// for `apex`, falls back over `offset`. `side`: 0 both, −1 the image-left half of the face (the subject's
// right, FACS R), +1 the image-right half (the subject's left, FACS L).
struct AuEvent {
	Ticks time{0}, onset{0}, apex{0}, offset{0};
	std::string au;  // canonical ("AU12")
	int side = 0;
	double intensity = 1;
};

// Brows asked for by a control track or SSML: raised (AU1+2) and/or lowered and drawn together (AU4), each
// 0–1.5, over `duration` (rising over the first 0.15 s, falling over the last 0.25 s).
struct BrowEvent {
	Ticks time{0}, duration{0};
	double raise = 0, frown = 0;
};

// Brows with speech (issue 13 §3, D49): a raise on each phrase's most prominent syllable — between pauses
// (≥ 150 ms), the longest vowel (stressed and pitch-accented vowels are the long ones: espeak-ng and real
// speech lengthen them), and in a phrase over 2.4 s also the longest vowel of its first half — never two
// within 1.2 s. Each rises 80 ms before its vowel, lasts the vowel + 350 ms, and raises by 0.5 × amount
// (5 % of the eye distance at amount 1). The phones' CDVs say which are vowels.
std::vector<BrowEvent> speechBrows(const std::vector<PhoneSegment>& phones, double amount = 1);

// Continuous controls (issue 17, D55: a performance tracked from a video by `talkhead track`): samples at
// `rate` per second from `start`, interpolated linearly between samples and held before the first and after
// the last. Head: roll in radians (positive turns the face clockwise on screen, as HeadMotion), translation
// x, y in inter-ocular distances of the rendered face (picture axes, y down), scale (1 = the neutral size).
// Action units: weights per AU (canonical) and side (0 both, −1 the image-left half, +1 the image-right
// half; applyActionUnits). Empty channels are absent. Head channels replace the drawn head motion;
// gestures, blinks, brows and AU events still add.
struct ControlCurves {
	double rate = 0;
	Ticks start{0};
	std::vector<float> roll, x, y, scale;
	struct Au {
		std::string au;
		int side = 0;
		std::vector<float> weight;
	};
	std::vector<Au> aus;
	bool hasHead() const { return rate > 0 && (!roll.empty() || !x.empty() || !y.empty() || !scale.empty()); }
	bool empty() const { return !hasHead() && (rate <= 0 || aus.empty()); }
	// The time of the last sample (start when there is none).
	Ticks end() const;
	// A channel at t (`fallback` when it is empty).
	double at(const std::vector<float>& channel, Ticks t, double fallback = 0) const;
};

// What the face is asked to do at given times besides speaking (issue 46): blinks, head gestures, brows and
// action units (a control track, SSML, a driving video) and continuous curves (a tracked video). Shifted,
// clipped and spliced as one value — a stimulus's lead-in, a video's end, an utterance spliced into a live
// stream — and handed to the shape modulator beside its knobs.
struct TimedEvents {
	std::vector<Ticks> blinks;            // blinks at these times, even with drawn blinks off
	std::vector<HeadGesture> gestures;    // nods, shakes and turns, even with head motion off
	std::vector<BrowEvent> brows;         // brow raises and frowns
	std::vector<AuEvent> actionUnits;     // need the scheme's AU templates
	ControlCurves curves;                 // continuous head pose and action units
	bool empty() const { return blinks.empty() && gestures.empty() && brows.empty() && actionUnits.empty() && curves.empty(); }
	// Every event and the curves' start `by` later.
	void shift(Ticks by);
	// The events that start after `end` go (a video's end; the curves stay: they hold their last sample).
	void clip(Ticks end);
	// The events that start at or after `t` go (a barge-in; the curves stay).
	void cut(Ticks t);
	// The events over before `t` go (the curves stay).
	void dropEndedBefore(Ticks t);
	// `other`'s events, `at` later, after this one's of each kind (the curves: other's when this has none).
	void splice(const TimedEvents& other, Ticks at);
};

// The modulator's knobs (what is drawn without being asked for at a time).
struct ModulatorOptions {
	bool blinks = true;
	double blinkRate = 0;       // blinks per minute at rest; 0 = the emotion's default (see blinkRateFor)
	double intensity = 1;       // the emotion's strength: its blink rate and head liveliness go from neutral's by it
	bool headMotion = true;
	double headAmplitude = 1;   // × the default amplitude (0 = a still head)
	std::uint64_t seed = 1;     // the same seed, inputs and options give the same blinks and head motion
	// Whether anything moves, with `events` asked for besides.
	bool any(const TimedEvents& events = {}) const { return blinks || (headMotion && headAmplitude > 0) || !events.empty(); }
};

// One blink: the lids close over `closing`, stay shut for `closed`, open over `opening` (closing faster
// than opening; 250 ms in all).
struct BlinkEvent {
	Ticks start{0}, closing{0}, closed{0}, opening{0};
	Ticks end() const { return start + closing + closed + opening; }
};

// A small similarity about the face's centre: rotation in radians (positive turns the face clockwise on
// screen), translation in units of the face's size (the mean shape's larger side).
// Curves (ControlCurves) add, after that, a rotation `roll` and a `scale` about the point between the eyes
// and a translation in inter-ocular distances (x, y).
struct HeadMotion {
	double angle = 0, dx = 0, dy = 0;
	double roll = 0, x = 0, y = 0, scale = 1;
};

// The modulator's plan for one utterance, fixed at construction (seeded), then a pure function of time:
// frames drawn in any order on any thread agree.
class ShapeModulator {
public:
	ShapeModulator(const ModulatorOptions& options, Emotion emotion, Ticks duration, const std::vector<Keypose>& keys, const TimedEvents& events = {});
	// A live stream's next plan (render/live.h: its timeline changed at `from`): `previous`'s up to `from`,
	// then a plan of the new timeline that goes on from it without a jump — the same head sinusoids, the
	// blinks that started before `from` kept (new ones drawn after them, seeded by options.seed and
	// `from`), and the head's amplitude (emotion × speaking activity) moved from previous's to the new one
	// over 0.4 s. Blinks, gestures, brow and AU events asked for are `events`.
	ShapeModulator(const ShapeModulator& previous, Ticks from, const ModulatorOptions& options, Emotion emotion, Ticks duration,
	               const std::vector<Keypose>& keys, const TimedEvents& events = {});

	// Lid closure at t: 0 open … 1 shut.
	double eyeClosure(Ticks t) const;
	// The brows at t: raise and frown amounts (0 = at rest).
	std::pair<double, double> brows(Ticks t) const;
	// The head's pose at t.
	HeadMotion head(Ticks t) const;
	// The action-unit events active at t and their weights (intensity × envelope), in event order.
	std::vector<std::pair<const AuEvent*, double>> actionUnits(Ticks t) const;
	const std::vector<AuEvent>& auEvents() const { return e_.actionUnits; }
	const std::vector<BlinkEvent>& blinks() const { return blinks_; }
	// The head motion's amplitude at t (× the peak values): the emotion's factor × (0.5 + 0.5 × speaking
	// activity).
	double amplitude(Ticks t) const;
	// Largest rotation (radians) and translation (face sizes) head() can return; from curves, the largest
	// translation in inter-ocular distances and the largest |scale − 1|.
	double maxAngle() const { return maxAngle_; }
	double maxShift() const { return maxShift_; }
	double maxCurveShift() const { return maxCurveShift_; }
	double maxCurveScale() const { return maxCurveScale_; }
	// The curves' action units at t: (index into options().curves.aus, weight), those with weight > 0.
	std::vector<std::pair<std::size_t, double>> curveActionUnits(Ticks t) const;
	const ControlCurves& curves() const { return e_.curves; }
	// Whether t falls in speech (between the first and last non-silent keypose of a run).
	bool speaking(Ticks t) const;

	// Defaults per emotion (canonical label): blinks per minute at rest and the head-motion amplitude factor.
	static double blinkRateFor(Emotion emotion);
	static double headFactorFor(Emotion emotion);

private:
	ModulatorOptions o_;
	TimedEvents e_;
	std::vector<BlinkEvent> blinks_;
	std::vector<std::pair<Ticks, Ticks>> speech_;  // speech runs
	std::vector<float> activity_;                  // smoothed speaking indicator, every 10 ms
	double phase_[3][3] = {}, freq_[3][3] = {};    // per channel (angle, dx, dy): three sinusoids
	double maxAngle_ = 0, maxShift_ = 0, factor_ = 1, maxCurveShift_ = 0, maxCurveScale_ = 0;
	void sizeCurves();
	// A continued plan: the amplitude itself every 10 ms from grid index ampFirst_ (replaces factor_ ×
	// activity_).
	std::vector<float> amp_;
	std::size_t ampFirst_ = 0;
	std::size_t activityFirst_ = 0;  // activity_[0] is grid index activityFirst_
	ShapeModulator(const ModulatorOptions& options, const TimedEvents& events, Emotion emotion, Ticks duration, const std::vector<Keypose>& keys,
	               Ticks activityFrom);
	// Draws blinks from `t` (seconds) to the end `length`, none within 0.8 s of `lastEnd`, moving those in
	// speech to a nearby pause; `state` is the generator's.
	void drawBlinks(std::uint64_t& state, double mean, double t, double lastEnd, double length);
	static double gestureShift(const TimedEvents& e, double& gestureAngle);
};

}  // namespace talkhead
