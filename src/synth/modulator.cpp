// SPDX-License-Identifier: GPL-3.0-or-later
#include "synth/modulator.h"

#include <algorithm>
#include <cmath>

#include "base/hash.h"
#include "phonetics/labels.h"

namespace talkhead {

namespace {

// SplitMix64: a small, portable generator (the standard library's distributions differ between
// implementations; these numbers must not).
struct Random {
	std::uint64_t state;
	std::uint64_t next() {
		const std::uint64_t z = splitmix64(state);
		state += 0x9E3779B97F4A7C15ull;
		return z;
	}
	double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)
};

double smoothstep(double u) {
	u = std::clamp(u, 0.0, 1.0);
	return u * u * (3 - 2 * u);
}

constexpr double kPi = 3.14159265358979323846;
// Blink phases (Evinger, Manning & Sibony 1991, IOVS 32: the lid comes down about twice as fast as it
// goes up; spontaneous blinks last 100–400 ms).
constexpr double kClosing = 0.075, kClosed = 0.025, kOpening = 0.150;
// Head motion, peak values at full speaking activity: rotation 1.5°, translation 1.2 % / 0.8 % of the
// face's size horizontally / vertically (a judgement: visible, never a nod).
constexpr double kPeakAngle = 1.5 * kPi / 180, kPeakDx = 0.012, kPeakDy = 0.008;
constexpr double kGrid = 0.01;
// Gestures' peak shifts, in face sizes: a nod 3.5 % down, a shake 2.5 % sideways, a turn 4 % with a 3°
// tilt the same way.
constexpr double kNod = 0.035, kShake = 0.025, kTurn = 0.04, kTurnTilt = 3 * kPi / 180;

// A blink starting at t with the standard phases.
BlinkEvent blinkAt(Ticks t) {
	BlinkEvent b;
	b.start = t;
	b.closing = ticksFromSeconds(kClosing);
	b.closed = ticksFromSeconds(kClosed);
	b.opening = ticksFromSeconds(kOpening);
	return b;
}

// An emotion's value at an intensity: neutral's at 0, the emotion's at 1, on the line beyond; at least `least`.
double scaledByIntensity(double emotional, double neutral, double intensity, double least) {
	return std::max(least, neutral + intensity * (emotional - neutral));
}

}  // namespace

double ShapeModulator::blinkRateFor(Emotion emotion) {
	// Spontaneous blinking at rest: 17 per minute on average (Bentivoglio et al. 1997, Movement Disorders
	// 12: 17 at rest, 26 in conversation, 4.5 reading). Per emotion a judgement, no source: wide-eyed
	// fear and surprise blink less, distress and shame more. Canonical labels, checked (Emotion::in).
	if (emotion.in({"fear", "fears-confirmed"})) return 10;
	if (emotion.in({"anger", "hate"})) return 14;
	if (emotion.in({"distress", "shame", "remorse", "disappointment"})) return 22;
	return 17;
}

double ShapeModulator::headFactorFor(Emotion emotion) {
	// Amplitude of head motion per emotion (a judgement): lively for joy and anger, subdued for distress
	// and fear.
	if (emotion.in({"joy", "happy-for", "gloating", "pride", "gratification"})) return 1.25;
	if (emotion.in({"anger", "hate", "reproach"})) return 1.2;
	if (emotion.in({"distress", "fear", "shame", "remorse", "pity"})) return 0.6;
	return 1.0;
}

void TimedEvents::shift(Ticks by) {
	for (Ticks& t : blinks) t += by;
	for (HeadGesture& g : gestures) g.time += by;
	for (BrowEvent& b : brows) b.time += by;
	for (AuEvent& a : actionUnits) a.time += by;
	curves.start += by;
}

namespace {
// Removes the events of every kind whose start `gone` says goes.
template <class Gone>
void dropStarting(TimedEvents& e, Gone gone) {
	e.blinks.erase(std::remove_if(e.blinks.begin(), e.blinks.end(), [&](Ticks t) { return gone(t); }), e.blinks.end());
	e.gestures.erase(std::remove_if(e.gestures.begin(), e.gestures.end(), [&](const HeadGesture& g) { return gone(g.time); }), e.gestures.end());
	e.brows.erase(std::remove_if(e.brows.begin(), e.brows.end(), [&](const BrowEvent& b) { return gone(b.time); }), e.brows.end());
	e.actionUnits.erase(std::remove_if(e.actionUnits.begin(), e.actionUnits.end(), [&](const AuEvent& a) { return gone(a.time); }), e.actionUnits.end());
}
}  // namespace

void TimedEvents::clip(Ticks end) {
	dropStarting(*this, [&](Ticks t) { return t > end; });
}

void TimedEvents::cut(Ticks from) {
	dropStarting(*this, [&](Ticks t) { return t >= from; });
}

void TimedEvents::dropEndedBefore(Ticks t) {
	blinks.erase(std::remove_if(blinks.begin(), blinks.end(), [&](Ticks b) { return b < t; }), blinks.end());
	gestures.erase(std::remove_if(gestures.begin(), gestures.end(), [&](const HeadGesture& g) { return g.time + g.duration < t; }), gestures.end());
	brows.erase(std::remove_if(brows.begin(), brows.end(), [&](const BrowEvent& b) { return b.time + b.duration < t; }), brows.end());
	actionUnits.erase(std::remove_if(actionUnits.begin(), actionUnits.end(), [&](const AuEvent& a) { return a.time + a.onset + a.apex + a.offset < t; }),
	                  actionUnits.end());
}

void TimedEvents::splice(const TimedEvents& other, Ticks at) {
	for (Ticks t : other.blinks) blinks.push_back(t + at);
	for (HeadGesture g : other.gestures) g.time += at, gestures.push_back(g);
	for (BrowEvent b : other.brows) b.time += at, brows.push_back(b);
	for (AuEvent a : other.actionUnits) a.time += at, actionUnits.push_back(std::move(a));
	if (curves.empty() && !other.curves.empty()) {
		curves = other.curves;
		curves.start += at;
	}
}

ShapeModulator::ShapeModulator(const ModulatorOptions& o, Emotion emotion, Ticks duration, const std::vector<Keypose>& keys, const TimedEvents& events)
    : ShapeModulator(o, events, emotion, duration, keys, Ticks(0)) {}

ShapeModulator::ShapeModulator(const ModulatorOptions& o, const TimedEvents& events, Emotion emotion, Ticks duration, const std::vector<Keypose>& keys,
                               Ticks activityFrom)
    : o_(o), e_(events) {
	// Speech runs: consecutive keyposes that are phones (not silence, not the in-breath).
	for (std::size_t i = 0; i < keys.size();) {
		if (keys[i].cdv.isSilence() || keys[i].breath) {
			++i;
			continue;
		}
		std::size_t j = i;
		while (j + 1 < keys.size() && !keys[j + 1].cdv.isSilence() && !keys[j + 1].breath) ++j;
		speech_.emplace_back(keys[i].time, keys[j].time);
		i = j + 1;
	}
	Random rng{o.seed * 0x2545F4914F6CDD1Dull + 1};
	const double length = std::max(0.0, toSeconds(duration));
	if (o.blinks) {
		const double rate = o.blinkRate > 0 ? o.blinkRate : scaledByIntensity(blinkRateFor(emotion), blinkRateFor(Emotion()), o.intensity, 3);
		const double mean = 60.0 / rate;
		drawBlinks(rng.state, mean, 0.3 + rng.uniform() * mean, -1e9, length);
	}
	// Blinks a control track asks for: at their times, the drawn ones within 0.8 s of them dropped.
	for (Ticks t : events.blinks) {
		const double at = toSeconds(t);
		blinks_.erase(std::remove_if(blinks_.begin(), blinks_.end(),
		                             [&](const BlinkEvent& b) { return std::abs(toSeconds(b.start) - at) < 0.8; }),
		              blinks_.end());
	}
	for (Ticks t : events.blinks) blinks_.push_back(blinkAt(t));
	std::sort(blinks_.begin(), blinks_.end(), [](const BlinkEvent& a, const BlinkEvent& b) { return a.start < b.start; });
	// Head motion: per channel three sinusoids of slowly rising frequency and decreasing weight, seeded
	// phases and frequencies; the sum stays within ±1.
	for (int c = 0; c < 3; ++c) {
		const double base[3] = {0.15, 0.37, 0.8};
		for (int k = 0; k < 3; ++k) {
			freq_[c][k] = base[k] * (0.8 + 0.4 * rng.uniform());
			phase_[c][k] = 2 * kPi * rng.uniform();
		}
	}
	// A tracked head (curves) replaces the drawn motion.
	factor_ = o.headMotion && !events.curves.hasHead() ? std::max(0.0, o.headAmplitude) * scaledByIntensity(headFactorFor(emotion), headFactorFor(Emotion()), o.intensity, 0) : 0.0;
	double gestureAngle = 0;
	const double gesture = gestureShift(events, gestureAngle);
	maxAngle_ = kPeakAngle * factor_ + gestureAngle;
	maxShift_ = std::hypot(kPeakDx, kPeakDy) * factor_ + gesture;
	sizeCurves();
	// Speaking activity: 1 in speech, 0 in pauses, smoothed over ±0.4 s (the head settles in a pause). From
	// grid index activityFirst_ on (0; a continued plan starts 0.4 s before its splice, so a live session's
	// replan costs the same after hours as after seconds).
	const long w = long(0.4 / kGrid);
	const std::size_t total = std::size_t(length / kGrid) + 2;
	activityFirst_ = std::min(total - 1, std::size_t(std::max(0L, long(toSeconds(activityFrom) / kGrid) - w)));
	const std::size_t n = total - activityFirst_;
	std::vector<double> raw(n), prefix(n + 1, 0.0);
	for (std::size_t i = 0; i < n; ++i) raw[i] = speaking(ticksFromSeconds(double(activityFirst_ + i) * kGrid)) ? 1.0 : 0.0;
	for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + raw[i];
	activity_.resize(n);
	for (std::size_t i = 0; i < n; ++i) {
		const long a = std::max(0L, long(i) - w), b = std::min(long(n), long(i) + w + 1);
		activity_[i] = float((prefix[std::size_t(b)] - prefix[std::size_t(a)]) / double(b - a));
	}
}

void ShapeModulator::drawBlinks(std::uint64_t& state, double mean, double t, double lastEnd, double length) {
	Random rng{state};
	const double total = kClosing + kClosed + kOpening;
	while (t + total < length - 0.1) {
		// During speech a blink moves to the nearest pause within a second, if there is one (speakers
		// blink at phrase boundaries), but never closer than 0.8 s to the one before.
		if (speaking(ticksFromSeconds(t))) {
			double best = t, bestDistance = 1.0;
			for (const auto& [a, b] : speech_) {
				for (double c : {toSeconds(a) - total - 0.05, toSeconds(b) + 0.05})
					if (std::abs(c - t) < bestDistance && c > lastEnd + 0.8 && c > 0.1 && c + total < length - 0.1 &&
					    !speaking(ticksFromSeconds(c)) && !speaking(ticksFromSeconds(c + total)))
						best = c, bestDistance = std::abs(c - t);
			}
			t = best;
		}
		blinks_.push_back(blinkAt(ticksFromSeconds(t)));
		lastEnd = t + total;
		t = lastEnd + std::max(0.8, -std::log(1 - rng.uniform()) * mean - total);
	}
	state = rng.state;
}

double ShapeModulator::gestureShift(const TimedEvents& e, double& gestureAngle) {
	double gesture = 0;
	gestureAngle = 0;
	for (const HeadGesture& g : e.gestures) {
		const double shift = g.kind == HeadGesture::Kind::Nod ? kNod : (g.kind == HeadGesture::Kind::Shake ? kShake : kTurn);
		gesture = std::max(gesture, std::abs(g.amount) * shift);
		if (g.kind == HeadGesture::Kind::Turn) gestureAngle = std::max(gestureAngle, std::abs(g.amount) * kTurnTilt);
	}
	return gesture;
}

namespace {
ModulatorOptions withoutBlinks(ModulatorOptions o) {
	o.blinks = false;
	return o;
}
TimedEvents withoutBlinks(TimedEvents e) {
	e.blinks.clear();
	return e;
}
}  // namespace

ShapeModulator::ShapeModulator(const ShapeModulator& previous, Ticks from, const ModulatorOptions& o, Emotion emotion, Ticks duration,
                               const std::vector<Keypose>& keys, const TimedEvents& events)
    : ShapeModulator(withoutBlinks(o), withoutBlinks(events), emotion, duration, keys, from) {
	o_ = o;
	e_ = events;
	std::copy(&previous.freq_[0][0], &previous.freq_[0][0] + 9, &freq_[0][0]);
	std::copy(&previous.phase_[0][0], &previous.phase_[0][0] + 9, &phase_[0][0]);
	const double length = std::max(0.0, toSeconds(duration)), at = toSeconds(from);
	// Blinks: previous's up to `from` (one under way finishes), then new ones.
	double lastEnd = -1e9;
	for (const BlinkEvent& b : previous.blinks_)
		if (b.start < from) {
			blinks_.push_back(b);
			lastEnd = std::max(lastEnd, toSeconds(b.end()));
		}
	if (o.blinks) {
		const double rate = o.blinkRate > 0 ? o.blinkRate : scaledByIntensity(blinkRateFor(emotion), blinkRateFor(Emotion()), o.intensity, 3);
		const double mean = 60.0 / rate;
		Random rng{splitmix64(o.seed * 0x2545F4914F6CDD1Dull + std::uint64_t(from.count()))};
		drawBlinks(rng.state, mean, std::max(at + rng.uniform() * mean, lastEnd + 0.8), lastEnd, length);
	}
	for (Ticks t : events.blinks) {
		const double ft = toSeconds(t);
		blinks_.erase(std::remove_if(blinks_.begin(), blinks_.end(),
		                             [&](const BlinkEvent& b) { return b.start >= from && std::abs(toSeconds(b.start) - ft) < 0.8; }),
		              blinks_.end());
		blinks_.push_back(blinkAt(t));
	}
	std::sort(blinks_.begin(), blinks_.end(), [](const BlinkEvent& a, const BlinkEvent& b) { return a.start < b.start; });
	// The amplitude from `from` on: previous's, moved to this plan's over 0.4 s.
	ampFirst_ = std::size_t(std::max(0.0, at / kGrid));
	const std::size_t last = std::size_t(length / kGrid) + 2;
	std::vector<float> amp(last > ampFirst_ ? last - ampFirst_ : 1);  // amplitude() reads this plan's activity while amp_ is empty
	for (std::size_t i = 0; i < amp.size(); ++i) {
		const Ticks t = ticksFromSeconds(double(ampFirst_ + i) * kGrid);
		const double w = smoothstep((toSeconds(t) - at) / 0.4);
		amp[i] = float((1 - w) * previous.amplitude(t) + w * amplitude(t));
	}
	amp_ = std::move(amp);
	activity_.clear();
	double gestureAngle = 0;
	const double gesture = gestureShift(events, gestureAngle);
	double peak = 0;
	for (float a : amp_) peak = std::max(peak, double(a));
	maxAngle_ = kPeakAngle * peak + gestureAngle;
	maxShift_ = std::hypot(kPeakDx, kPeakDy) * peak + gesture;
	sizeCurves();
}

void ShapeModulator::sizeCurves() {
	const ControlCurves& c = e_.curves;
	maxCurveShift_ = maxCurveScale_ = 0;
	if (!c.hasHead()) return;
	double roll = 0;
	for (float v : c.roll) roll = std::max(roll, double(std::abs(v)));
	maxAngle_ += roll;
	for (std::size_t i = 0; i < std::max(c.x.size(), c.y.size()); ++i)
		maxCurveShift_ = std::max(maxCurveShift_, std::hypot(i < c.x.size() ? double(c.x[i]) : 0.0, i < c.y.size() ? double(c.y[i]) : 0.0));
	for (float v : c.scale) maxCurveScale_ = std::max(maxCurveScale_, std::abs(double(v) - 1));
}

Ticks ControlCurves::end() const {
	std::size_t n = std::max({roll.size(), x.size(), y.size(), scale.size()});
	for (const Au& a : aus) n = std::max(n, a.weight.size());
	return rate > 0 && n > 1 ? start + ticksFromSeconds(double(n - 1) / rate) : start;
}

double ControlCurves::at(const std::vector<float>& c, Ticks t, double fallback) const {
	if (c.empty() || !(rate > 0)) return fallback;
	const double g = std::clamp(toSeconds(t - start) * rate, 0.0, double(c.size() - 1));
	const std::size_t i = std::min(c.size() - 1, std::size_t(g));
	const std::size_t j = std::min(c.size() - 1, i + 1);
	return double(c[i]) + (g - double(i)) * (double(c[j]) - double(c[i]));
}

std::vector<std::pair<std::size_t, double>> ShapeModulator::curveActionUnits(Ticks t) const {
	std::vector<std::pair<std::size_t, double>> out;
	for (std::size_t k = 0; k < e_.curves.aus.size(); ++k) {
		const double w = e_.curves.at(e_.curves.aus[k].weight, t);
		if (w > 0) out.emplace_back(k, w);
	}
	return out;
}

double ShapeModulator::amplitude(Ticks t) const {
	const double s = toSeconds(t);
	if (!amp_.empty()) {
		const double g = std::clamp(s / kGrid - double(ampFirst_), 0.0, double(amp_.size() - 1));
		const std::size_t i = std::min(amp_.size() - 1, std::size_t(g));
		const std::size_t j = std::min(amp_.size() - 1, i + 1);
		return amp_[i] + (g - double(i)) * (amp_[j] - amp_[i]);
	}
	if (factor_ <= 0) return 0;
	double act = 0;
	if (!activity_.empty()) {
		const double g = std::clamp(s / kGrid - double(activityFirst_), 0.0, double(activity_.size() - 1));
		const std::size_t i = std::min(activity_.size() - 1, std::size_t(g));
		const std::size_t j = std::min(activity_.size() - 1, i + 1);
		act = activity_[i] + (g - double(i)) * (activity_[j] - activity_[i]);
	}
	return factor_ * (0.5 + 0.5 * act);  // half the amplitude at rest
}

bool ShapeModulator::speaking(Ticks t) const {
	auto it = std::upper_bound(speech_.begin(), speech_.end(), t, [](Ticks v, const std::pair<Ticks, Ticks>& r) { return v < r.first; });
	if (it == speech_.begin()) return false;
	--it;
	return t <= it->second;
}

double ShapeModulator::eyeClosure(Ticks t) const {
	auto it = std::upper_bound(blinks_.begin(), blinks_.end(), t, [](Ticks v, const BlinkEvent& b) { return v < b.start; });
	if (it == blinks_.begin()) return 0;
	const BlinkEvent& b = *(it - 1);
	const double s = toSeconds(t - b.start), c = toSeconds(b.closing), h = toSeconds(b.closed), op = toSeconds(b.opening);
	if (s < c) return smoothstep(s / c);
	if (s < c + h) return 1;
	if (s < c + h + op) return smoothstep(1 - (s - c - h) / op);
	return 0;
}

std::pair<double, double> ShapeModulator::brows(Ticks t) const {
	double raise = 0, frown = 0;
	const double s = toSeconds(t);
	for (const BrowEvent& b : e_.brows) {
		const double a = s - toSeconds(b.time), d = toSeconds(b.duration);
		if (a <= 0 || a >= d) continue;
		const double envelope = std::min(smoothstep(a / std::min(0.15, d / 2)), smoothstep((d - a) / std::min(0.25, d / 2)));
		raise = std::max(raise, b.raise * envelope);
		frown = std::max(frown, b.frown * envelope);
	}
	return {raise, frown};
}

std::vector<std::pair<const AuEvent*, double>> ShapeModulator::actionUnits(Ticks t) const {
	std::vector<std::pair<const AuEvent*, double>> out;
	const double s = toSeconds(t);
	for (const AuEvent& e : e_.actionUnits) {
		const double a = s - toSeconds(e.time), on = toSeconds(e.onset), top = toSeconds(e.apex), off = toSeconds(e.offset);
		if (a <= 0 || a >= on + top + off) continue;
		const double envelope = a < on ? smoothstep(a / on) : (a < on + top ? 1.0 : smoothstep(1 - (a - on - top) / off));
		if (envelope > 0) out.emplace_back(&e, e.intensity * envelope);
	}
	return out;
}

HeadMotion ShapeModulator::head(Ticks t) const {
	HeadMotion p;
	const double s = toSeconds(t);
	// Gestures from a control track: a nod goes down and back up; a shake sways twice each way.
	for (const HeadGesture& g : e_.gestures) {
		const double u = (s - toSeconds(g.time)) / std::max(1e-6, toSeconds(g.duration));
		if (u <= 0 || u >= 1) continue;
		if (g.kind == HeadGesture::Kind::Nod) {
			p.dy += g.amount * kNod * std::sin(kPi * u);
		} else if (g.kind == HeadGesture::Kind::Shake) {
			p.dx += g.amount * kShake * std::sin(4 * kPi * u) * std::sin(kPi * u);
		} else {  // Turn: toward the direction and held, with a little tilt the same way
			const double e = std::min(smoothstep(u / 0.25), smoothstep((1 - u) / 0.25));
			p.dx += g.amount * kTurn * g.directionX * e;
			p.dy += g.amount * kTurn * 0.6 * g.directionY * e;
			p.angle += g.amount * kTurnTilt * g.directionX * e;
		}
	}
	if (e_.curves.hasHead()) {  // a tracked head
		const ControlCurves& c = e_.curves;
		p.roll = c.at(c.roll, t);
		p.x = c.at(c.x, t);
		p.y = c.at(c.y, t);
		p.scale = c.at(c.scale, t, 1.0);
	}
	if (amp_.empty() && factor_ <= 0) return p;
	const double m = amplitude(t);
	if (m <= 0) return p;
	auto channel = [&](int c) {
		const double w[3] = {0.5, 0.3, 0.2};
		double v = 0;
		for (int k = 0; k < 3; ++k) v += w[k] * std::sin(2 * kPi * freq_[c][k] * s + phase_[c][k]);
		return v;
	};
	p.angle += kPeakAngle * m * channel(0);
	p.dx += kPeakDx * m * channel(1);
	p.dy += kPeakDy * m * channel(2);
	return p;
}

std::vector<BrowEvent> speechBrows(const std::vector<PhoneSegment>& phones, double amount) {
	std::vector<BrowEvent> out;
	if (!(amount > 0)) return out;
	auto isVowel = [](const PhoneSegment& p) {
		return p.cdv.info().kind == "vowel";
	};
	auto isPause = [](const PhoneSegment& p) { return p.phone == "_" || p.phone.empty(); };
	const Ticks minPause = ticksFromSeconds(0.15), minGap = ticksFromSeconds(1.2);
	auto raiseAt = [&](const PhoneSegment& v) {
		BrowEvent b;
		b.time = std::max(Ticks(0), v.start - ticksFromSeconds(0.08));
		b.duration = std::max(ticksFromSeconds(0.45), (v.end - v.start) + ticksFromSeconds(0.35));
		b.raise = std::min(1.5, 0.5 * amount);
		if (!out.empty() && b.time < out.back().time + minGap) return;
		out.push_back(b);
	};
	std::size_t i = 0;
	while (i < phones.size()) {
		// One phrase: phones up to the next pause of at least 150 ms.
		std::size_t j = i;
		while (j < phones.size() && !(isPause(phones[j]) && phones[j].end - phones[j].start >= minPause)) ++j;
		std::vector<const PhoneSegment*> vowels;
		for (std::size_t k = i; k < j; ++k)
			if (isVowel(phones[k])) vowels.push_back(&phones[k]);
		if (vowels.size() >= 2) {
			auto longest = [&](std::size_t a, std::size_t b) {  // ties: the later one
				const PhoneSegment* best = vowels[a];
				for (std::size_t k = a; k < b; ++k)
					if (vowels[k]->end - vowels[k]->start >= best->end - best->start) best = vowels[k];
				return best;
			};
			const Ticks start = phones[i].start, end = phones[j - 1].end;
			const PhoneSegment* nuclear = longest(0, vowels.size());
			const PhoneSegment* early = nullptr;
			if (end - start > ticksFromSeconds(2.4)) {
				const Ticks half = start + (end - start) / 2;
				std::size_t n = 0;
				while (n < vowels.size() && vowels[n]->start < half) ++n;
				if (n > 0) early = longest(0, n);
				if (early == nuclear) early = nullptr;
			}
			if (early) raiseAt(*early);
			raiseAt(*nuclear);
		}
		i = j + 1;
	}
	return out;
}

}  // namespace talkhead
