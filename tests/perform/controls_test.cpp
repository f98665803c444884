// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"
#include "perform/controls.h"

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
	p.expression = Expression(Emotion::of("joy"));
	for (long t = 100; t < 4000; t += 200) p.timeline.keys.push_back(Keypose{ms(t), "a", 0, 0});
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
	EXPECT_EQ(t.emotions[0].expression.emotion().label(), "distress");  // the alias, canonical
	EXPECT_EQ(t.emotions[0].expression.intensity(), 0.5);
	EXPECT_EQ(t.emotions[0].ramp, ms(400));
	ASSERT_EQ(t.blinks.size(), 1u);
	EXPECT_EQ(t.blinks[0], ms(1250));
	ASSERT_EQ(t.gestures.size(), 2u);
	EXPECT_EQ(t.gestures[1].kind, HeadGesture::Kind::Shake);
	EXPECT_EQ(t.gestures[1].amount, 2);
	EXPECT_EQ(parseControls(R"([{"type": "blink", "time": 1}])", "c.json").blinks.size(), 1u);  // a bare array
	EXPECT_EQ(failure(R"({"events": [{"type": "wink", "time": 1}]})"), "c.json: event 1: unknown type 'wink' (known: emotion, blink, nod, shake, turn, brows, au)");
	EXPECT_EQ(failure(R"([{"type": "blink"}])"), "c.json: event 1: missing \"time\"");
	EXPECT_EQ(failure(R"([{"type": "blink", "time": 1}, {"type": "emotion", "time": 1, "emotion": "glee"}])").substr(0, 36),
	          "c.json: event 2: unknown emotion 'gl");
	EXPECT_EQ(failure(R"([{"type": "nod", "time": -1}])"), "c.json: event 1: \"time\" -1 is outside 0–86400");
	EXPECT_EQ(failure(R"([{"type": "blink", "time": 1, "colour": 3}])"), "c.json: event 1: unknown field \"colour\" for a \"blink\" event");
	EXPECT_EQ(failure("{\"events\": [\n{\"type\": \"blink\", \"time\": 1,}]}"), "c.json:2: malformed JSON: column 29: syntax error while parsing object key - unexpected '}'; expected string literal");
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
	for (const Keypose& k : p.timeline.keys) {
		const double t = toSeconds(k.time);
		if (t < 1.5) {  // before the change: the performance's own (or unset, which means the same)
			EXPECT_TRUE(!k.emotion || (k.emotion == Emotion::of("joy") && k.intensity == 1.0)) << t;
		} else if (t < 2.0) {  // the first half of the ramp: joy fading out
			EXPECT_EQ(k.emotion, Emotion::of("joy")) << t;
			EXPECT_NEAR(*k.intensity, 1 - 2 * (t - 1.5), 1e-9) << t;
		} else if (t < 2.5) {  // the second half: anger fading in
			EXPECT_EQ(k.emotion, Emotion::of("anger")) << t;
			EXPECT_NEAR(*k.intensity, 0.8 * (2 * (t - 1.5) - 1), 1e-9) << t;
		} else {
			EXPECT_EQ(k.emotion, Emotion::of("anger")) << t;
			EXPECT_EQ(k.intensity, 0.8) << t;
		}
	}
	EXPECT_EQ(p.timeline.events.blinks, std::vector<Ticks>{ms(3500)});
	ASSERT_EQ(p.timeline.events.gestures.size(), 1u);
	// The modulator blinks there even with its own blinks off, and nods (down, then back).
	p.modulation.blinks = false;
	p.modulation.headMotion = false;
	const ShapeModulator m(p.modulation, p.expression.emotion(), p.duration, p.timeline.keys, p.timeline.events);
	ASSERT_EQ(m.blinks().size(), 1u);
	EXPECT_EQ(m.blinks()[0].start, ms(3500));
	EXPECT_EQ(m.eyeClosure(ms(3500 + 85)), 1.0);
	EXPECT_NEAR(m.head(ms(500)).dy, 0.035, 1e-3);  // the middle of a 0.6-s nod from 0.2 s: the lowest point
	EXPECT_EQ(m.head(ms(900)).dy, 0.0);
}

TEST(Controls, actionUnitsAndTurnsAreReadAndBadOnesNamed) {
	const ControlTrack t = parseControls(R"([
		{"type": "au", "time": 1, "au": "12", "intensity": 0.7, "side": "left", "onset": 0.1, "apex": 0.4, "offset": 0.2},
		{"type": "au", "time": 2, "au": "AU4"},
		{"type": "au", "time": 3, "au": "au45"},
		{"type": "turn", "time": 0.5, "direction": "left", "duration": 2}])",
	                                     "c.json");
	ASSERT_EQ(t.actionUnits.size(), 2u);
	EXPECT_EQ(t.actionUnits[0].au, "AU12");
	EXPECT_EQ(t.actionUnits[0].side, 1);  // the subject's left: the image's right half
	EXPECT_EQ(t.actionUnits[0].intensity, 0.7);
	EXPECT_EQ(t.actionUnits[0].onset, ms(100));
	EXPECT_EQ(t.actionUnits[0].apex, ms(400));
	EXPECT_EQ(t.actionUnits[0].offset, ms(200));
	EXPECT_EQ(t.actionUnits[1].side, 0);
	EXPECT_EQ(t.actionUnits[1].onset, ms(200));  // defaults 0.2 / 0.5 / 0.3 s
	ASSERT_EQ(t.blinks.size(), 1u);              // AU45 is a blink
	EXPECT_EQ(t.blinks[0], ms(3000));
	ASSERT_EQ(t.gestures.size(), 1u);
	EXPECT_EQ(t.gestures[0].kind, HeadGesture::Kind::Turn);
	EXPECT_EQ(t.gestures[0].directionX, 1);
	EXPECT_EQ(failure(R"([{"type": "au", "time": 1, "au": "AU99"}])").substr(0, 47), "c.json: event 1: unknown action unit 'AU99' (kn");
	EXPECT_EQ(failure(R"([{"type": "au", "time": 1, "au": "AU12", "side": "top"}])"), "c.json: event 1: \"side\" 'top' is not left, right or both");
	EXPECT_EQ(failure(R"([{"type": "turn", "time": 1}])"), "c.json: event 1: missing \"direction\"");
	EXPECT_EQ(failure(R"([{"type": "turn", "time": 1, "direction": "back"}])"), "c.json: event 1: \"direction\" 'back' is not left, right, up or down");
	// Applied: the AU events reach the modulator.
	Performance p = fourSeconds();
	applyControls(p, t);
	EXPECT_EQ(p.timeline.events.actionUnits.size(), 2u);
	EXPECT_EQ(p.timeline.events.gestures.size(), 1u);
}

namespace {
std::string textGrid(const std::string& tierClass, const std::string& items) {
	return "File type = \"ooTextFile\"\nObject class = \"TextGrid\"\nxmin = 0\nxmax = 4\ntiers? <exists>\nsize = 2\nitem []:\n"
	       "item [1]:\nclass = \"IntervalTier\"\nname = \"phones\"\nxmin = 0\nxmax = 4\nintervals: size = 1\n"
	       "intervals [1]:\nxmin = 0\nxmax = 4\ntext = \"a\"\n"
	       "item [2]:\nclass = \"" + tierClass + "\"\nname = \"controls\"\nxmin = 0\nxmax = 4\n" + items;
}
std::string tierFailure(const std::string& text, const std::string& tier = "controls") {
	try {
		parseControlTier(text, "c.TextGrid", tier);
	} catch (const Error& e) {
		return e.what();
	}
	return "no error";
}
}  // namespace

TEST(Controls, aTextGridTierIsAControlTrack) {
	// Interval tier: labels are events at their interval's start, its length their duration.
	const std::string intervals = textGrid("IntervalTier",
	                                       "intervals: size = 5\n"
	                                       "intervals [1]:\nxmin = 0\nxmax = 0.5\ntext = \"\"\n"
	                                       "intervals [2]:\nxmin = 0.5\nxmax = 1.5\ntext = \"brows raise 0.6\"\n"
	                                       "intervals [3]:\nxmin = 1.5\nxmax = 2.5\ntext = \"au AU12 0.8 left\"\n"
	                                       "intervals [4]:\nxmin = 2.5\nxmax = 3\ntext = \"emotion anger 0.9 ramp=0.2\"\n"
	                                       "intervals [5]:\nxmin = 3\nxmax = 4\ntext = \"nod amount=0.5\"\n");
	const ControlTrack t = parseControlTier(intervals, "c.TextGrid", "controls");
	ASSERT_EQ(t.brows.size(), 1u);
	EXPECT_EQ(t.brows[0].time, ms(500));
	EXPECT_EQ(t.brows[0].duration, ms(1000));
	EXPECT_EQ(t.brows[0].raise, 0.6);
	ASSERT_EQ(t.actionUnits.size(), 1u);
	EXPECT_EQ(t.actionUnits[0].au, "AU12");
	EXPECT_EQ(t.actionUnits[0].side, 1);
	EXPECT_EQ(t.actionUnits[0].onset + t.actionUnits[0].apex + t.actionUnits[0].offset, ms(1000));  // the interval
	ASSERT_EQ(t.emotions.size(), 1u);
	EXPECT_EQ(t.emotions[0].expression.emotion().label(), "anger");
	EXPECT_EQ(t.emotions[0].ramp, ms(200));
	ASSERT_EQ(t.gestures.size(), 1u);
	EXPECT_EQ(t.gestures[0].amount, 0.5);
	EXPECT_EQ(t.gestures[0].duration, ms(1000));
	// Point tier: events at the points.
	const std::string points = textGrid("TextTier", "points: size = 2\npoints [1]:\nnumber = 1.25\nmark = \"blink\"\n"
	                                                "points [2]:\nnumber = 2\nmark = \"turn right\"\n");
	const ControlTrack p = parseControlTier(points, "c.TextGrid", "controls");
	ASSERT_EQ(p.blinks.size(), 1u);
	EXPECT_EQ(p.blinks[0], ms(1250));
	ASSERT_EQ(p.gestures.size(), 1u);
	EXPECT_EQ(p.gestures[0].directionX, -1);
	// Errors name the file and the label's line.
	EXPECT_EQ(tierFailure(points, "gestures"), "c.TextGrid: no tier named 'gestures' (tiers: 'phones', 'controls')");
	const std::string bad = textGrid("TextTier", "points: size = 1\npoints [1]:\nnumber = 1\nmark = \"wink\"\n");
	EXPECT_EQ(tierFailure(bad), "c.TextGrid:25: unknown type 'wink' (known: emotion, blink, nod, shake, turn, brows, au)");
	const std::string many = textGrid("TextTier", "points: size = 1\npoints [1]:\nnumber = 1\nmark = \"nod 1 2\"\n");
	EXPECT_EQ(tierFailure(many), "c.TextGrid:25: too many values in 'nod 1 2' (write key=value for the others)");
}

TEST(Controls, curvesAreReadWrittenAndDriveTheHead) {
	// D55: sampled head pose and action units (talkhead track writes them).
	const std::string text = R"({"drawn_blinks": false, "events": [{"type": "blink", "time": 1.5}],
		"curves": {"rate": 10, "start": 0.5,
		  "head": {"roll": [0, 2, 4], "x": [0, 0.1, -0.1], "y": [0, 0, 0.05], "scale": [1, 1.02, 1], "yaw": [0, 5, 10]},
		  "au": [{"au": "au1", "side": "right", "weight": [0, 0.5, 1]}, {"au": "AU4", "weight": [0.2, 0.2, 0.2]}]}})";
	const ControlTrack t = parseControls(text, "c.json");
	EXPECT_FALSE(t.drawnBlinks);
	const ControlCurves& c = t.curves;
	EXPECT_EQ(c.rate, 10);
	EXPECT_EQ(c.start, ms(500));
	EXPECT_EQ(c.end(), ms(700));
	ASSERT_EQ(c.roll.size(), 3u);
	EXPECT_NEAR(c.roll[1], 2 * 3.14159265 / 180, 1e-6);  // degrees in the file, radians inside
	ASSERT_EQ(c.aus.size(), 2u);
	EXPECT_EQ(c.aus[0].au, "AU1");
	EXPECT_EQ(c.aus[0].side, -1);
	EXPECT_EQ(c.aus[1].side, 0);
	// Interpolated linearly, held at the ends.
	EXPECT_NEAR(c.at(c.x, ms(550)), 0.05, 1e-6);
	EXPECT_NEAR(c.at(c.x, ms(0)), 0, 1e-9);
	EXPECT_NEAR(c.at(c.x, ms(5000)), -0.1, 1e-6);
	EXPECT_EQ(c.at({}, ms(600), 1.0), 1.0);
	// Written and read back: the same samples (to 4 decimals).
	const ControlTrack back = parseControls(controlTrackJson(t, "driver.mp4", "a note"), "back.json");
	EXPECT_FALSE(back.drawnBlinks);
	ASSERT_EQ(back.blinks.size(), 1u);
	EXPECT_EQ(back.blinks[0], ms(1500));
	EXPECT_EQ(back.curves.rate, 10);
	EXPECT_EQ(back.curves.start, ms(500));
	for (std::size_t i = 0; i < 3; ++i) {
		EXPECT_NEAR(back.curves.roll[i], c.roll[i], 1e-5);
		EXPECT_NEAR(back.curves.x[i], c.x[i], 1e-5);
		EXPECT_NEAR(back.curves.scale[i], c.scale[i], 1e-5);
		EXPECT_NEAR(back.curves.aus[0].weight[i], c.aus[0].weight[i], 1e-5);
	}
	EXPECT_EQ(back.curves.aus[0].side, -1);
	// The modulator: curves replace the drawn head motion; drawn blinks off, the track's blink kept.
	Performance p = fourSeconds();
	applyControls(p, t);
	EXPECT_FALSE(p.modulation.blinks);
	const ShapeModulator m(p.modulation, p.expression.emotion(), p.duration, p.timeline.keys, p.timeline.events);
	EXPECT_NEAR(m.head(ms(600)).roll, c.roll[1], 1e-6);
	EXPECT_EQ(m.head(ms(600)).angle, 0);  // no drawn sinusoids
	EXPECT_NEAR(m.head(ms(650)).scale, 1.01, 1e-6);
	EXPECT_NEAR(m.maxAngle(), 4 * 3.14159265 / 180, 1e-6);
	EXPECT_NEAR(m.maxCurveShift(), std::hypot(0.1, 0.05), 1e-6);
	ASSERT_EQ(m.blinks().size(), 1u);
	const auto aus = m.curveActionUnits(ms(700));
	ASSERT_EQ(aus.size(), 2u);
	EXPECT_NEAR(aus[0].second, 1.0, 1e-6);
	// A lead-in (issue 14) moves the curves with the speech.
	addLeadInAndTail(p, ms(1000), ms(0));
	EXPECT_EQ(p.timeline.events.curves.start, ms(1500));
	// Bad curves are named.
	EXPECT_EQ(failure(R"({"curves": {"rate": 10, "head": {"roll": [0, 1], "x": [0]}}})"), "c.json: curves: \"head.x\" has 1 samples, the curves before it 2");
	EXPECT_EQ(failure(R"({"curves": {"rate": 10, "head": {"pan": [0]}}})"), "c.json: curves: unknown head channel \"pan\" (known: roll, x, y, scale, yaw, pitch)");
	EXPECT_EQ(failure(R"({"curves": {"head": {"roll": [0]}}})"), "c.json: curves: missing \"rate\"");
	EXPECT_EQ(failure(R"({"curves": {"rate": 10, "head": {"scale": [1, 7]}}})"), "c.json: curves: \"head.scale\" sample 2 (7) is outside 0.5–2");
	EXPECT_EQ(failure(R"({"curves": {"rate": 10, "au": [{"au": "AU45", "weight": [1]}]}})"),
	          "c.json: curves: au curve 1: unknown action unit 'AU45' (AU45 blinks are events)");
	EXPECT_EQ(failure(R"({"curves": {"rate": 10}})"), "c.json: curves: no samples (give head channels or au curves)");
	EXPECT_EQ(failure(R"({"events": [], "drawn_blinks": 0})"), "c.json: \"drawn_blinks\" must be true or false");
	EXPECT_EQ(failure(R"({"event": []})"), "c.json: unknown field \"event\" (known: events, curves, drawn_blinks, source, note)");
}
