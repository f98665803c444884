// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"
#include "render/controls.h"

using namespace talkhead;

namespace {
std::string failure(const std::string& text) {
	try {
		parseControls(text, "c.json");
	} catch (const Error& e) {
		return e.what();
	}
	return "no error";
}

Ticks ms(long v) { return Ticks(v * (kTicksPerSecond / 1000)); }

Performance fourSeconds() {
	Performance p;
	p.rate = FrameRate{30, 1};
	p.duration = ms(4000);
	p.emotion = "joy";
	for (long t = 100; t < 4000; t += 200) p.keys.push_back(Keypose{ms(t), "a", 0, 0});
	return p;
}
}  // namespace

TEST(Controls, eventsAreReadAndBadOnesNamed) {
	const ControlTrack t = parseControls(R"({"events": [
		{"type": "emotion", "time": 2, "emotion": "sadness", "intensity": 0.5, "ramp": 0.4},
		{"type": "blink", "time": 1.25},
		{"type": "nod", "time": 3, "duration": 0.5},
		{"type": "shake", "time": 0.5, "amount": 2}]})",
	                                     "c.json");
	ASSERT_EQ(t.emotions.size(), 1u);
	EXPECT_EQ(t.emotions[0].emotion, "distress");  // the alias, canonical
	EXPECT_EQ(t.emotions[0].intensity, 0.5);
	EXPECT_EQ(t.emotions[0].ramp, ms(400));
	ASSERT_EQ(t.blinks.size(), 1u);
	EXPECT_EQ(t.blinks[0], ms(1250));
	ASSERT_EQ(t.gestures.size(), 2u);
	EXPECT_EQ(t.gestures[1].kind, HeadGesture::Kind::Shake);
	EXPECT_EQ(t.gestures[1].amount, 2);
	EXPECT_EQ(parseControls(R"([{"type": "blink", "time": 1}])", "c.json").blinks.size(), 1u);  // a bare array
	EXPECT_EQ(failure(R"({"events": [{"type": "wink", "time": 1}]})"), "c.json: event 1: unknown type 'wink' (known: emotion, blink, nod, shake, brows)");
	EXPECT_EQ(failure(R"([{"type": "blink"}])"), "c.json: event 1: missing \"time\"");
	EXPECT_EQ(failure(R"([{"type": "blink", "time": 1}, {"type": "emotion", "time": 1, "emotion": "glee"}])").substr(0, 36),
	          "c.json: event 2: unknown emotion 'gl");
	EXPECT_EQ(failure(R"([{"type": "nod", "time": -1}])"), "c.json: event 1: \"time\" -1 is outside 0–86400");
	EXPECT_EQ(failure(R"([{"type": "blink", "time": 1, "colour": 3}])"), "c.json: event 1: unknown field \"colour\" for a \"blink\" event");
	EXPECT_EQ(failure("{\"events\": [\n{\"type\": \"blink\", \"time\": 1,}]}"), "c.json:2: malformed JSON: expected a member name");
	// Past the end of the video: named when applied.
	Performance p = fourSeconds();
	try {
		applyControls(p, parseControls(R"([{"type": "blink", "time": 5}])", "c.json"));
		ADD_FAILURE() << "no error";
	} catch (const Error& e) {
		EXPECT_STREQ(e.what(), "c.json: a blink at 5 s is past the end of the video (4 s)");
	}
}

TEST(Controls, anEmotionChangeRampsThroughNeutralBetweenTheTwoEmotions) {
	Performance p = fourSeconds();
	applyControls(p, parseControls(R"([{"type": "emotion", "time": 1.5, "emotion": "anger", "intensity": 0.8, "ramp": 1.0},
	                                    {"type": "blink", "time": 3.5}, {"type": "nod", "time": 0.2}])",
	                               "c.json"));
	for (const Keypose& k : p.keys) {
		const double t = toSeconds(k.time);
		if (t < 1.5) {  // before the change: the performance's own (or unset, which means the same)
			EXPECT_TRUE(k.emotion.empty() || (k.emotion == "joy" && k.intensity == 1)) << t;
		} else if (t < 2.0) {  // the first half of the ramp: joy fading out
			EXPECT_EQ(k.emotion, "joy") << t;
			EXPECT_NEAR(k.intensity, 1 - 2 * (t - 1.5), 1e-9) << t;
		} else if (t < 2.5) {  // the second half: anger fading in
			EXPECT_EQ(k.emotion, "anger") << t;
			EXPECT_NEAR(k.intensity, 0.8 * (2 * (t - 1.5) - 1), 1e-9) << t;
		} else {
			EXPECT_EQ(k.emotion, "anger") << t;
			EXPECT_EQ(k.intensity, 0.8) << t;
		}
	}
	EXPECT_EQ(p.modulation.forcedBlinks, std::vector<Ticks>{ms(3500)});
	ASSERT_EQ(p.modulation.gestures.size(), 1u);
	// The modulator blinks there even with its own blinks off, and nods (down, then back).
	p.modulation.blinks = false;
	p.modulation.headMotion = false;
	const ShapeModulator m(p.modulation, p.emotion, p.duration, p.keys);
	ASSERT_EQ(m.blinks().size(), 1u);
	EXPECT_EQ(m.blinks()[0].start, ms(3500));
	EXPECT_EQ(m.eyeClosure(ms(3500 + 85)), 1.0);
	EXPECT_NEAR(m.head(ms(500)).dy, 0.035, 1e-3);  // the middle of a 0.6-s nod from 0.2 s: the lowest point
	EXPECT_EQ(m.head(ms(900)).dy, 0.0);
}
