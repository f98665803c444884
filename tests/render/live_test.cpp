// SPDX-License-Identifier: GPL-3.0-or-later
// Live sessions (issue 16): splicing, barge-in, emotions on the fly, determinism, and the shape
// modulator's continued plans.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "base/error.h"
#include "phonetics/language.h"
#include "render/live.h"
#include "render/render.h"
#include "synth/modulator.h"
#include "test_support.h"

using namespace talkhead;
using talkhead::test::errorOf;

namespace {

const FaceModel* defaultFace() {
	static std::unique_ptr<FaceModel> m = [] {
		try {
			return std::make_unique<FaceModel>(loadRenderModel(""));
		} catch (const std::exception&) {
			return std::unique_ptr<FaceModel>();
		}
	}();
	return m.get();
}

#define NEED_DEFAULT_FACE()                                                                     \
	const FaceModel* face = defaultFace();                                                      \
	if (!face) GTEST_SKIP() << "no default face (configure with TALKHEAD_BUILD_DEFAULT_MODEL=ON)"

LiveOptions smallOptions(std::uint64_t seed = 7) {
	LiveOptions o;
	o.render.synth.width = 320;
	o.render.synth.height = 180;
	o.rate = FrameRate{30, 1};
	o.modulation.seed = seed;
	return o;
}

// The inner lips' opening (CILM below CIUM), output pixels.
double opening(const FaceModel& m, const Points& p) {
	const auto& n = m.scheme.pointNames;
	const auto at = [&](const char* name) { return long(std::find(n.begin(), n.end(), name) - n.begin()); };
	const long up = at("CIUM"), low = at("CILM");
	if (up >= long(n.size()) || low >= long(n.size())) return NAN;
	return p(low, 1) - p(up, 1);
}

Utterance sentence(const std::string& text, const std::string& id, int rate = 22050) {
	Utterance u = speakText(text, Language::get("en-US"), "", rate);
	u.id = id;
	return u;
}

}  // namespace

TEST(ShapeModulator, aContinuedPlanGoesOnWithoutAJump) {
	ModulatorOptions o;
	o.seed = 3;
	std::vector<Keypose> idle(1);
	idle[0].cdv = "sil";
	const ShapeModulator before(o, Emotion::of("neutral"), ticksFromSeconds(60), idle);
	// Speech from 2.05 s and a livelier emotion: the plan changes at 2 s.
	std::vector<Keypose> keys = idle;
	for (int i = 0; i < 20; ++i) {
		Keypose k;
		k.time = ticksFromSeconds(2.05 + 0.08 * i);
		k.cdv = i % 2 ? Cdv("a") : Cdv("p1");
		keys.push_back(k);
	}
	Keypose rest;
	rest.time = ticksFromSeconds(3.8);
	rest.cdv = "sil";
	keys.push_back(rest);
	const Ticks from = ticksFromSeconds(2);
	const ShapeModulator after(before, from, o, Emotion::of("joy"), ticksFromSeconds(70), keys);
	// At the splice the head is where it was; after it, it moves no faster than the old plan ever did.
	const HeadMotion a = before.head(from), b = after.head(from);
	EXPECT_NEAR(a.angle, b.angle, 1e-12);
	EXPECT_NEAR(a.dx, b.dx, 1e-12);
	EXPECT_NEAR(a.dy, b.dy, 1e-12);
	// ... and after it no faster than a plan that knew the speech from the start.
	const ShapeModulator known(o, Emotion::of("joy"), ticksFromSeconds(70), keys);
	double fastest = 0, fastestAfter = 0;
	const Ticks frame = ticksFromSeconds(1.0 / 30);
	for (Ticks t{0}; t < ticksFromSeconds(8); t += frame) {
		fastest = std::max(fastest, std::abs(known.head(t + frame).angle - known.head(t).angle));
		if (t >= from) fastestAfter = std::max(fastestAfter, std::abs(after.head(t + frame).angle - after.head(t).angle));
	}
	EXPECT_LE(fastestAfter, 1.5 * fastest);
	// Speech raises the amplitude (joy is livelier, and speaking moves the head more) once blended in.
	EXPECT_GT(after.amplitude(ticksFromSeconds(3)), before.amplitude(ticksFromSeconds(3)) * 1.2);
	// Blinks that started before the splice are kept as they were; none of the new ones starts before it.
	for (const BlinkEvent& bl : before.blinks())
		if (bl.start < from) {
			bool kept = false;
			for (const BlinkEvent& x : after.blinks()) kept |= x.start == bl.start;
			EXPECT_TRUE(kept) << toSeconds(bl.start);
		}
	for (const BlinkEvent& x : after.blinks()) {
		bool old = false;
		for (const BlinkEvent& bl : before.blinks()) old |= bl.start == x.start && bl.start < from;
		if (!old) EXPECT_GE(x.start, from);
	}
	// Within the face box the synthesizer was sized for.
	EXPECT_LE(after.maxAngle(), ShapeModulator(o, Emotion::of("joy"), ticksFromSeconds(60), idle).maxAngle() + 1e-12);
}

TEST(LiveSession, sameRequestsAtTheSameFramesGiveTheSameFramesAndSound) {
	NEED_DEFAULT_FACE();
	// One synthesis for every run: libespeak-ng's output depends on what it said before in the process (D51).
	const Utterance said = sentence("Good morning.", "a");
	auto run = [&](std::uint64_t seed) {
		LiveSession s(*face, smallOptions(seed));
		std::vector<std::uint8_t> all;
		std::vector<float> sound(735 * 60);
		YuvImage f;
		Points p;
		std::vector<LiveEvent> ev;
		for (int n = 0; n < 60; ++n) {
			if (n == 3) s.enqueue(said);
			if (n == 20) s.setEmotion(Expression(Emotion::of("joy")), ticksFromSeconds(0.3));
			if (n == 40) s.stop();
			s.drawNext(f, p, ev);
			all.insert(all.end(), f.y.begin(), f.y.end());
			all.insert(all.end(), f.u.begin(), f.u.end());
			s.audio().read(sound.data() + 735 * n, 735);  // 22050 / 30 per frame
		}
		return std::make_pair(all, sound);
	};
	const auto a = run(7), b = run(7), c = run(8);
	EXPECT_TRUE(a.first == b.first);
	EXPECT_TRUE(a.second == b.second);
	EXPECT_FALSE(a.first == c.first);  // the seed moves the head and the blinks
	EXPECT_TRUE(a.second == c.second);  // not the sound
}

TEST(LiveSession, backToBackUtterancesAreSplicedWithoutAGapAndTheSoundIsTheirs) {
	NEED_DEFAULT_FACE();
	LiveSession s(*face, smallOptions());
	YuvImage f;
	Points p;
	std::vector<LiveEvent> ev;
	for (int n = 0; n < 5; ++n) s.drawNext(f, p, ev);
	Utterance a = sentence("Hello there.", "a"), b = sentence("How are you?", "b");
	const std::vector<float> pa = a.audio.samples, pb = b.audio.samples;
	const Ticks ta = s.enqueue(std::move(a));
	const Ticks tb = s.enqueue(std::move(b));
	EXPECT_EQ(ta, s.nextTime());
	EXPECT_EQ(tb, ta + Ticks(std::int64_t(pa.size()) * (kTicksPerSecond / 22050)));
	EXPECT_TRUE(s.speaking());
	// The sound: silence, then a's samples, then b's, exactly where they were placed.
	const std::size_t total = std::size_t(std::llround(toSeconds(tb) * 22050)) + pb.size() + 2000;
	std::vector<float> sound(total);
	std::size_t read = 0;
	std::vector<std::string> order;
	Ticks endA{-1}, startB{-1};
	double previous = NAN, biggestJump = 0;
	std::vector<std::uint8_t> last;
	int identical = 0;
	for (int n = 5; read < total; ++n) {
		ev.clear();
		s.drawNext(f, p, ev);
		for (const LiveEvent& e : ev) {
			if (e.kind == LiveEvent::Kind::UtteranceStarted || e.kind == LiveEvent::Kind::UtteranceEnded)
				order.push_back(std::string(liveEventName(e.kind)) + " " + e.id);
			if (e.kind == LiveEvent::Kind::UtteranceEnded && e.id == "a") endA = e.time;
			if (e.kind == LiveEvent::Kind::UtteranceStarted && e.id == "b") startB = e.time;
		}
		// No frozen frame while speaking, and the mouth never jumps.
		if (s.speaking() && f.y == last) ++identical;
		last = f.y;
		const double o = opening(*face, p);
		if (!std::isnan(previous)) biggestJump = std::max(biggestJump, std::abs(o - previous));
		previous = o;
		const std::size_t k = std::min<std::size_t>(735, total - read);
		s.audio().read(sound.data() + read, k);
		read += k;
	}
	EXPECT_EQ((std::vector<std::string>{"utterance_started a", "utterance_ended a", "utterance_started b", "utterance_ended b"}), order);
	EXPECT_EQ(endA, startB);
	EXPECT_EQ(identical, 0);
	EXPECT_LT(biggestJump, 12.0);  // 320×180: the lips open by ~10 px at most
	const std::size_t a0 = std::size_t(std::llround(toSeconds(ta) * 22050)), b0 = a0 + pa.size();
	for (std::size_t i = 0; i < a0; ++i) ASSERT_EQ(sound[i], 0.f) << i;
	for (std::size_t i = 0; i < pa.size(); ++i) ASSERT_EQ(sound[a0 + i], pa[i]) << i;
	for (std::size_t i = 0; i < pb.size(); ++i) ASSERT_EQ(sound[b0 + i], pb[i]) << i;
}

// Issue 45: a live AAC encoder reads its priming (1024 samples, 46 ms at 22 050 Hz) before the first frame;
// a say that came then started at frame 0 and lost its first 46 ms of sound.
TEST(LiveSession, theFirstSayKeepsAllItsSoundAfterTheEncodersPriming) {
	NEED_DEFAULT_FACE();
	LiveSession s(*face, smallOptions());
	std::vector<float> priming(1024);
	s.audio().read(priming.data(), priming.size());  // as Mp4LiveWriter does when it opens
	Utterance u = sentence("Hello.", "first");
	const std::vector<float> pcm = u.audio.samples;
	const Ticks start = s.enqueue(std::move(u));
	// It starts at the first frame whose sound is still to be read (frame 2 at 30 fps: 66.7 ms ≥ 46.4 ms).
	EXPECT_EQ(start, (FrameRate{30, 1}.time(2)));
	YuvImage f;
	Points p;
	std::vector<LiveEvent> ev;
	const std::size_t total = pcm.size() + 4000;
	std::vector<float> sound(1024 + total);
	std::size_t read = 1024;
	Ticks started{-1};
	for (int n = 0; read < sound.size(); ++n) {
		ev.clear();
		s.drawNext(f, p, ev);
		for (const LiveEvent& e : ev)
			if (e.kind == LiveEvent::Kind::UtteranceStarted) started = e.time;
		const std::size_t until = std::min(sound.size(), std::size_t(std::llround(toSeconds(FrameRate{30, 1}.time(n + 1)) * 22050)));
		if (until > read) s.audio().read(sound.data() + read, until - read), read = until;
	}
	EXPECT_EQ(started, start);  // the mouth and the sound together
	const std::size_t s0 = std::size_t(std::llround(toSeconds(start) * 22050));
	for (std::size_t i = 0; i < pcm.size(); ++i) ASSERT_EQ(sound[s0 + i], pcm[i]) << "sample " << i << " of the say";
}

TEST(LiveSession, stopClosesTheMouthWithin150msAndSilencesTheSound) {
	NEED_DEFAULT_FACE();
	LiveSession s(*face, smallOptions());
	YuvImage f;
	Points p;
	std::vector<LiveEvent> ev;
	std::vector<float> block(735);
	s.drawNext(f, p, ev);
	s.audio().read(block.data(), 735);  // the sound as an encoder pulls it: up to the end of each frame
	const double rest = opening(*face, p);
	ASSERT_FALSE(std::isnan(rest));
	s.enqueue(sentence("Now I am going to talk for quite a long time about many things.", "long"));
	s.enqueue(sentence("And this is never said.", "never"));
	// Into the speech until the mouth is well open.
	int n = 1;
	for (; n < 90; ++n) {
		s.drawNext(f, p, ev);
		s.audio().read(block.data(), 735);
		if (n > 20 && opening(*face, p) > rest + 4) break;
	}
	ASSERT_LT(n, 90) << "the mouth never opened";
	s.stop();
	ev.clear();
	const int within = int(std::ceil(0.150 * 30));  // frames
	double after = 0;
	bool silent = true;
	for (int k = 1; k <= 30; ++k) {
		s.drawNext(f, p, ev);
		s.audio().read(block.data(), 735);
		if (k == within) after = opening(*face, p);
		if (k > 1)  // past the 10 ms fade
			for (float v : block) {
				if (v != 0.f && silent) ADD_FAILURE() << "sound " << v << " in frame " << k << " after the stop";
				silent = silent && v == 0.f;
			}
		if (k >= within) EXPECT_LE(opening(*face, p), rest + 0.5) << "frame " << k << " after the stop";
	}
	EXPECT_LE(after, rest + 0.5);
	EXPECT_TRUE(silent);
	EXPECT_FALSE(s.speaking());
	// Each utterance ends, interrupted; the second never starts.
	int ended = 0, started = 0, stopped = 0;
	for (const LiveEvent& e : ev) {
		if (e.kind == LiveEvent::Kind::UtteranceEnded) {
			++ended;
			EXPECT_TRUE(e.interrupted);
		}
		if (e.kind == LiveEvent::Kind::UtteranceStarted) ++started;
		if (e.kind == LiveEvent::Kind::Stopped) ++stopped;
	}
	EXPECT_EQ(ended, 2);
	EXPECT_EQ(started, 0);
	EXPECT_EQ(stopped, 1);
}

TEST(LiveSession, anEmotionChangesGraduallyWhileIdleAndBadOnesAreErrors) {
	NEED_DEFAULT_FACE();
	LiveOptions o = smallOptions();
	o.modulation.blinks = false;
	o.modulation.headMotion = false;
	LiveSession s(*face, o);
	YuvImage f;
	Points p;
	std::vector<LiveEvent> ev;
	s.drawNext(f, p, ev);
	const std::vector<std::uint8_t> first = f.y;
	EXPECT_NE(errorOf([&] { s.setEmotion(Expression(Emotion::of("joy"), 2), Ticks(0)); }).find("intensity"), std::string::npos);
	s.setEmotion(Expression(Emotion::of("joy")), ticksFromSeconds(0.5));
	double largest = 0, total = 0;
	std::vector<std::uint8_t> last = first;
	for (int n = 0; n < 25; ++n) {
		s.drawNext(f, p, ev);
		double d = 0;
		for (std::size_t i = 0; i < f.y.size(); ++i) d += std::abs(int(f.y[i]) - int(last[i]));
		d /= double(f.y.size());
		largest = std::max(largest, d);
		last = f.y;
	}
	for (std::size_t i = 0; i < f.y.size(); ++i) total += std::abs(int(f.y[i]) - int(first[i]));
	total /= double(f.y.size());
	std::printf("emotion: mean |Δ| %.3f from the start, at most %.3f per frame\n", total, largest);
	EXPECT_GT(total, 0.2);            // the face is joyful now
	EXPECT_LT(largest, total / 4.0);  // over 15 frames, not in one
}

// Issue 46: an utterance is planned once (LiveSession::plan, on a server's speech thread); queued after the
// session's emotion changed, its keys take the session's expression — the frames are those of planning it
// at the queueing, as before.
TEST(LiveSession, anUtterancePlannedAheadDrawsAsOnePlannedWhenQueued) {
	NEED_DEFAULT_FACE();
	const Utterance u = sentence("Good news, everyone.", "a");
	const Expression joy(Emotion::of("joy")), anger(Emotion::of("anger"), 0.7);
	// 45 frames' luma of a session that turns angry and then speaks `u`: planned ahead in `plannedIn`, or
	// at the queueing (nullopt); or not at all (`speak` false).
	auto frames = [&](std::optional<Expression> plannedIn, bool speak = true) {
		LiveSession s(*face, smallOptions());
		std::optional<PlannedUtterance> ahead;
		if (plannedIn) ahead = s.plan(u, *plannedIn);
		s.setEmotion(anger, Ticks(0));
		if (ahead) {
			EXPECT_EQ(ahead->timeline.keys.at(1).emotion, plannedIn->emotion());
			s.enqueue(std::move(*ahead));
		} else if (speak) {
			s.enqueue(u);
		}
		std::vector<std::uint8_t> all;
		YuvImage f;
		Points p;
		std::vector<LiveEvent> ev;
		for (int n = 0; n < 45; ++n) {
			s.drawNext(f, p, ev);
			all.insert(all.end(), f.y.begin(), f.y.end());
		}
		return all;
	};
	const std::vector<std::uint8_t> atQueueing = frames(std::nullopt);
	EXPECT_TRUE(frames(joy) == atQueueing);    // planned in another expression: restamped
	EXPECT_TRUE(frames(anger) == atQueueing);  // planned in the session's: queued as planned
	EXPECT_FALSE(frames(std::nullopt, false) == atQueueing);  // the utterance is drawn at all
}
