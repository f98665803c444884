// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/live.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "phonetics/espeak.h"
#include "phonetics/labels.h"
#include "phonetics/ssml.h"
#include "perform/plan.h"
#include "phonetics/transcript.h"

namespace talkhead {

namespace {

constexpr double kStopClose = 0.12;     // s: a barge-in's silence keypose after the next frame (D54)
constexpr double kStopFade = 0.010;     // s: the sound's fade-out at a barge-in
constexpr double kPlanAhead = 60;       // s: the blink and head plan reaches this far past the queued speech
constexpr double kReplanMargin = 20;    // s: replanned when the frames come this close to its end
constexpr double kKeepBehind = 2;       // s: keyposes kept behind the last drawn frame

}  // namespace

const char* liveEventName(LiveEvent::Kind kind) {
	switch (kind) {
	case LiveEvent::Kind::UtteranceStarted: return "utterance_started";
	case LiveEvent::Kind::UtteranceEnded: return "utterance_ended";
	case LiveEvent::Kind::Mark: return "mark";
	case LiveEvent::Kind::Viseme: return "viseme";
	case LiveEvent::Kind::Stopped: return "stopped";
	case LiveEvent::Kind::Emotion: return "emotion";
	}
	return "?";
}

std::string liveEventJson(const LiveEvent& e, std::optional<double> latencyMs) {
	JsonObject j;
	j.add("type", liveEventName(e.kind)).add("frame", static_cast<long long>(e.frame)).add("time", toSeconds(e.time), "%.3f");
	if (!e.id.empty()) j.raw("id", e.id);  // JSON text already (the client's, as written)
	if (!e.name.empty()) j.add(e.kind == LiveEvent::Kind::Viseme ? "viseme" : e.kind == LiveEvent::Kind::Emotion ? "emotion" : "name", e.name);
	if (e.kind == LiveEvent::Kind::UtteranceEnded) j.add("interrupted", e.interrupted);
	if (latencyMs) j.add("latency_ms", *latencyMs, "%.1f");
	return j.str();
}

// The session's sound: utterances placed at sample positions, silence between; read in order.
class LiveSession::Sound : public AudioSource {
public:
	explicit Sound(int rate) : rate_(rate) {}
	int sampleRate() const override { return rate_; }
	int channels() const override { return 1; }
	std::size_t read(float* out, std::size_t n) override {
		std::fill(out, out + n, 0.f);
		const std::int64_t a = pos_, b = pos_ + std::int64_t(n);
		for (const Segment& s : segments_) {
			const std::int64_t s0 = std::max(a, s.start), s1 = std::min(b, s.start + std::int64_t(s.pcm.size()));
			for (std::int64_t i = s0; i < s1; ++i) out[i - a] += s.pcm[std::size_t(i - s.start)];
		}
		pos_ = b;
		while (!segments_.empty() && segments_.front().start + std::int64_t(segments_.front().pcm.size()) <= pos_) segments_.pop_front();
		return n;
	}
	void add(std::int64_t start, std::vector<float> pcm) {
		if (start < pos_) {  // read already (an encoder ran ahead): the start is lost
			std::fprintf(stderr, "talkhead: live: %.3f s of speech were late for the sound and are dropped\n", double(pos_ - start) / rate_);
			const std::size_t drop = std::min(pcm.size(), std::size_t(pos_ - start));
			pcm.erase(pcm.begin(), pcm.begin() + std::ptrdiff_t(drop));
			start = pos_;
		}
		if (!pcm.empty()) segments_.push_back({start, std::move(pcm)});
	}
	// Everything from `at` on goes, faded out over `fade` samples.
	void cut(std::int64_t at, std::int64_t fade) {
		at = std::max(at, pos_);
		for (auto it = segments_.begin(); it != segments_.end();) {
			Segment& s = *it;
			if (s.start >= at) {
				it = segments_.erase(it);
				continue;
			}
			const std::int64_t end = s.start + std::int64_t(s.pcm.size());
			if (end > at) {
				const std::int64_t keep = std::min(end, at + fade) - s.start;
				for (std::int64_t i = at - s.start; i < keep; ++i) s.pcm[std::size_t(i)] *= float(1.0 - double(i - (at - s.start) + 1) / double(fade + 1));
				s.pcm.resize(std::size_t(keep));
			}
			++it;
		}
	}
	std::int64_t position() const { return pos_; }  // the next sample to be read

private:
	struct Segment {
		std::int64_t start;
		std::vector<float> pcm;
	};
	int rate_;
	std::int64_t pos_ = 0;
	std::deque<Segment> segments_;
};

LiveSession::LiveSession(const FaceModel& model, const LiveOptions& options) : LiveSession(std::make_unique<Face>(model), nullptr, options) {}
LiveSession::LiveSession(const Face& face, const LiveOptions& options) : LiveSession(nullptr, &face, options) {}

LiveSession::LiveSession(std::unique_ptr<Face> own, const Face* face, const LiveOptions& options)
    : ownFace_(std::move(own)), face_(face ? *face : *ownFace_), o_(options) {
	const FaceModel& model = face_.model();
	if (o_.rate.num < 1 || o_.rate.den < 1) throw Error("invalid frame rate " + o_.rate.str());
	if (o_.sampleRate < 8000 || o_.sampleRate > 192000 || kTicksPerSecond % o_.sampleRate != 0)
		throw Error("live: sample rate " + std::to_string(o_.sampleRate) + " Hz is not one of the rates a sample lasts a whole number of ticks at (8000, 11025, 16000, 22050, 24000, 32000, 44100, 48000, 96000, …)");
	expression_ = o_.expression;
	RenderOptions ro = o_.render;
	ro.synth.expression = expression_;
	timeline_.keys.push_back(rest(Ticks(0)));
	modOptions_ = o_.modulation;
	// The face box is sized once, for the liveliest head any emotion gets (head motion's largest factor).
	ModulatorOptions envelope = o_.modulation;
	envelope.intensity = 1.5;  // the strongest an emotion gets (its head motion scales with the intensity)
	double factor = 0;
	for (std::size_t i = 0; i < Emotion::count(); ++i) factor = std::max(factor, ShapeModulator::headFactorFor(Emotion::at(i)));
	ro.synth.modulator = std::make_shared<ShapeModulator>(envelope, Emotion::of("joy"), ticksFromSeconds(kPlanAhead), timeline_.keys);
	if (ShapeModulator::headFactorFor(Emotion::of("joy")) < factor) throw std::logic_error("LiveSession: the envelope's emotion is not the liveliest");
	player_ = std::make_unique<FramePlayer>(face_, ro);
	info_.width = player_->width();
	info_.height = player_->height();
	info_.rate = o_.rate;
	info_.frames = 0;
	info_.range = YuvRange::Limited;
	info_.pointNames = model.scheme.pointNames;
	sound_ = std::make_unique<Sound>(o_.sampleRate);
	replan();
}

LiveSession::~LiveSession() = default;

AudioSource& LiveSession::audio() { return *sound_; }

Ticks LiveSession::lastDrawn() const { return next_ > 0 ? o_.rate.time(next_ - 1) : Ticks(-1); }

Keypose LiveSession::rest(Ticks t) const {
	Keypose k;
	k.time = t;
	k.cdv = Cdv();  // silence
	k.emotion = expression_.emotion();
	k.intensity = expression_.intensity();
	if (const auto& m = face_.coarticulation(); m && m->restOpening) {
		std::vector<Keypose> one{k};
		one[0].mouthOpening = *m->restOpening, one[0].mouthWidth = m->restWidth.value_or(1.0);
		chooseMouthExemplars(face_.model(), expression_.emotion(), one);
		return one[0];
	}
	return k;
}

void LiveSession::addPending(Ticks t, LiveEvent e) {
	e.time = t;
	auto it = std::upper_bound(pending_.begin(), pending_.end(), t, [](Ticks v, const Pending& p) { return v < p.time; });
	pending_.insert(it, Pending{t, std::move(e)});
}

PlannedUtterance LiveSession::planned(Utterance u, const Expression& expression) const {
	PlannedUtterance p(std::move(u));
	p.planned = true;
	p.expression = expression;
	p.timeline.events.blinks = p.utterance.blinks;  // the text's blinks, brows and marks (SSML); speech brows go before its brows
	p.timeline.events.brows = p.utterance.brows;
	p.timeline.marks = p.utterance.marks;
	if (p.utterance.phones.empty()) return p;
	PerformanceSpec spec;
	spec.phones = p.utterance.phones;
	spec.rate = o_.rate;
	spec.pauses = o_.pauses;
	spec.speechBrows = o_.speechBrows;
	spec.coarticulation = face_.coarticulation();
	spec.timing = p.utterance.timing;
	spec.expression = expression;
	if (spec.coarticulation) spec.face = &face_.model();  // D62: bound to the face's exemplars in `expression`
	Performance perf = planPerformance(spec);
	std::vector<Keypose>& keys = p.timeline.keys;
	keys = std::move(perf.timeline.keys);
	std::vector<BrowEvent>& brows = p.timeline.events.brows;
	brows.insert(brows.begin(), perf.timeline.events.brows.begin(), perf.timeline.events.brows.end());  // speech brows (D49)
	p.stamped.assign(keys.size(), 0);
	for (std::size_t i = 0; i < keys.size(); ++i) {
		Keypose& k = keys[i];
		if (!k.emotion) k.emotion = expression.emotion(), p.stamped[i] |= 1;
		if (!k.intensity) k.intensity = expression.intensity(), p.stamped[i] |= 2;
	}
	return p;
}

PlannedUtterance LiveSession::plan(Utterance u, const Expression& expression) const {
	PlannedUtterance p = planned(std::move(u), expression);
	player_->synthesizer().prepare(p.timeline.keys);  // thread-safe; what is there already is skipped
	return p;
}

void LiveSession::chooseExemplars(std::vector<Keypose>& keys, Emotion fallback) const {
	if (face_.coarticulation()) chooseMouthExemplars(face_.model(), fallback, keys);  // each key by its own emotion, else `fallback`
}

Ticks LiveSession::enqueue(PlannedUtterance p) {
	if (!p.planned) {
		p = planned(std::move(p.utterance), expression_);
	} else if (p.expression != expression_) {  // planned in another expression: the keys that took it take the session's
		for (std::size_t i = 0; i < p.timeline.keys.size(); ++i) {
			Keypose& k = p.timeline.keys[i];
			if (p.stamped[i] & 1) k.emotion = expression_.emotion();
			if (p.stamped[i] & 2) k.intensity = expression_.intensity();
			if (p.stamped[i] && k.mouthOpening) k.sample = -1;  // chosen again, among the emotion's exemplars
		}
		chooseExemplars(p.timeline.keys, expression_.emotion());
	}
	Utterance& u = p.utterance;
	// Not before the sound read already: an encoder reads its priming ahead of the first frame (a live AAC
	// stream skips the session's first 1024 samples, D54), so the first say of a session starts at the
	// first frame whose sound is still to be read, its mouth and its sound together (issue 45: it lost 46 ms).
	std::int64_t f = next_;
	while (std::llround(toSeconds(o_.rate.time(f)) * o_.sampleRate) < sound_->position()) ++f;
	const Ticks start = std::max(o_.rate.time(f), queueEnd_);
	// One splice: what frames already drawn depend on stays, the pose held fills the gap before it.
	timeline_.splice(p.timeline, start, lastDrawn());
	const Ticks end = start + u.duration();
	queueEnd_ = std::max(queueEnd_, end);
	sound_->add(std::llround(toSeconds(start) * o_.sampleRate), std::move(u.audio.samples));
	LiveEvent e;
	e.id = u.id;
	e.kind = LiveEvent::Kind::UtteranceStarted;
	if (u.opens) addPending(start, e);
	for (const auto& m : p.timeline.marks) {
		LiveEvent me = e;
		me.kind = LiveEvent::Kind::Mark;
		me.name = m.name;
		addPending(start + m.time, me);
	}
	e.kind = LiveEvent::Kind::UtteranceEnded;
	// A streamed utterance's end is known with its last part; until then a stop ends it.
	if (u.closes) {
		addPending(end, e);
		if (open_ && *open_ == u.id) open_.reset();
	} else {
		open_ = u.id;
	}
	replan();
	return start;
}

void LiveSession::setEmotion(const Expression& expression, Ticks ramp) {
	const Emotion e = expression.emotion();
	const double intensity = expression.intensity();
	const Ticks t = nextTime(), frame = o_.rate.frameLength();
	const std::size_t c = timeline_.firstAfter(lastDrawn());
	if (c + 1 < timeline_.keys.size()) {
		// Speaking: from the key after the one the face is moving to.
		for (std::size_t i = c + 1; i < timeline_.keys.size(); ++i) {
			timeline_.keys[i].emotion = e, timeline_.keys[i].intensity = intensity;
			if (timeline_.keys[i].mouthOpening) timeline_.keys[i].sample = -1;  // its exemplar is chosen again, among the new emotion's
		}
	} else {
		// Holding, or moving to the last key: the last pose again in the new emotion, `ramp` later.
		if (c >= timeline_.keys.size() && timeline_.keys.back().time < t) {
			Keypose hold = timeline_.keys.back();
			hold.time = t;
			hold.breath = false;
			timeline_.keys.push_back(hold);
		}
		Keypose k = timeline_.keys.back();
		k.time = std::max(k.time + frame, t + std::max(ramp, frame));
		k.emotion = e;
		k.intensity = intensity;
		k.breath = false;
		if (k.mouthOpening) k.sample = -1;
		timeline_.keys.push_back(k);
	}
	chooseExemplars(timeline_.keys, expression_.emotion());
	expression_ = expression;
	LiveEvent ev;
	ev.kind = LiveEvent::Kind::Emotion;
	ev.name = e.label();
	addPending(t, ev);
	replan();
}

void LiveSession::stop(const std::string& id, const std::vector<std::string>& unstarted) {
	const Ticks t = nextTime(), frame = o_.rate.frameLength();
	if (queueEnd_ > t) {
		const Ticks closeAt = t + ticksFromSeconds(kStopClose);
		const std::size_t c = timeline_.firstAfter(lastDrawn());
		std::vector<Keypose> kept(timeline_.keys.begin(), timeline_.keys.begin() + std::ptrdiff_t(c));
		Ticks silAt = closeAt;
		if (c < timeline_.keys.size() && timeline_.keys[c].time < closeAt) {
			kept.push_back(timeline_.keys[c]);
			silAt = std::max(closeAt, timeline_.keys[c].time + frame);
		}
		if (kept.empty() || kept.back().time < silAt) kept.push_back(rest(silAt));
		timeline_.keys = std::move(kept);
		sound_->cut(std::llround(toSeconds(t) * o_.sampleRate), std::llround(kStopFade * o_.sampleRate));
		// Utterances cut or never started end now; their marks and starts still to come are dropped.
		std::deque<Pending> left;
		for (Pending& p : pending_) {
			if (p.time < t) {
				left.push_back(std::move(p));
			} else if (p.event.kind == LiveEvent::Kind::UtteranceEnded) {
				p.event.interrupted = true;
				p.time = p.event.time = t;
				left.push_back(std::move(p));
			} else if (p.event.kind != LiveEvent::Kind::UtteranceStarted && p.event.kind != LiveEvent::Kind::Mark) {
				left.push_back(std::move(p));
			}
		}
		pending_ = std::move(left);
		timeline_.cut(t);
		queueEnd_ = t;
	}
	if (open_) {  // a streamed utterance whose last part had not come: it ends here
		LiveEvent e;
		e.kind = LiveEvent::Kind::UtteranceEnded;
		e.id = *open_;
		e.interrupted = true;
		addPending(t, e);
		open_.reset();
	}
	for (const std::string& u : unstarted) {  // the caller's, never queued here: after the session's own
		LiveEvent e;
		e.kind = LiveEvent::Kind::UtteranceEnded;
		e.id = u;
		e.interrupted = true;
		addPending(t, e);
	}
	LiveEvent ev;
	ev.kind = LiveEvent::Kind::Stopped;
	ev.id = id;
	addPending(t, ev);
	replan();
}

void LiveSession::replan() {
	const Ticks t = nextTime(), behind = lastDrawn() - ticksFromSeconds(kKeepBehind);
	horizon_ = std::max(queueEnd_, t) + ticksFromSeconds(kPlanAhead);
	// Old keys go (all but the last before `behind`), and old timed events with them.
	timeline_.dropBefore(behind);
	modOptions_.intensity = expression_.intensity();
	if (modulator_) modulator_ = std::make_shared<ShapeModulator>(*modulator_, t, modOptions_, expression_.emotion(), horizon_, timeline_.keys, timeline_.events);
	else modulator_ = std::make_shared<ShapeModulator>(modOptions_, expression_.emotion(), horizon_, timeline_.keys, timeline_.events);
	player_->synthesizer().setModulator(modulator_);
}

void LiveSession::play(FrameSink& sink, std::vector<LiveEvent>& events) {
	const std::int64_t n = next_;
	const FrameSlot& slot = drawNext(events, sink.needsAlpha());
	RenderedFrame f;
	f.index = n, f.time = o_.rate.time(n), f.yuv = &slot.yuv, f.points = &slot.points;
	sink.frame(f);
}

void LiveSession::drawNext(YuvImage& out, Points& points, std::vector<LiveEvent>& events) {
	const FrameSlot& slot = drawNext(events);
	out = slot.yuv;
	points = slot.points;
}

const FrameSlot& LiveSession::drawNext(std::vector<LiveEvent>& events, bool alpha) {
	const Ticks t = nextTime();
	if (t + ticksFromSeconds(kReplanMargin) > horizon_) replan();
	while (!pending_.empty() && pending_.front().time <= t) {
		LiveEvent e = std::move(pending_.front().event);
		pending_.pop_front();
		e.frame = next_;
		events.push_back(std::move(e));
	}
	std::size_t i = 0;
	while (i + 1 < timeline_.keys.size() && timeline_.keys[i + 1].time <= t) ++i;
	if (timeline_.keys[i].cdv.label() != lastViseme_) {
		lastViseme_ = timeline_.keys[i].cdv.label();
		LiveEvent e;
		e.kind = LiveEvent::Kind::Viseme;
		e.frame = next_;
		e.time = timeline_.keys[i].time;
		e.name = lastViseme_;
		events.push_back(std::move(e));
	}
	player_->prepare(timeline_.keys, t, t);
	player_->draw(t, timeline_.keys, ws_, slot_, false, alpha);
	++next_;
	return slot_;
}

}  // namespace talkhead
