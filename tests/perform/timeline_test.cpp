// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "perform/timeline.h"

using namespace talkhead;

namespace {
Ticks ms(long v) { return Ticks(v * (kTicksPerSecond / 1000)); }

Timeline keysAt(std::initializer_list<long> times, Cdv cdv) {
	Timeline t;
	for (long v : times) t.keys.push_back(Keypose{ms(v), cdv, 0, 0});
	return t;
}

std::vector<long> timesOf(const Timeline& t) {
	std::vector<long> v;
	for (const Keypose& k : t.keys) v.push_back(long(k.time.count() / (kTicksPerSecond / 1000)));
	return v;
}
}  // namespace

TEST(Timeline, shiftMovesKeysEventsMarksAndCurvesTogether) {
	Timeline t = keysAt({0, 100}, "a");
	t.events.blinks = {ms(50)};
	t.events.brows.push_back(BrowEvent{ms(20), ms(800), 0.5, 0});
	t.marks.push_back({"m", ms(70)});
	t.shift(ms(300));
	EXPECT_EQ(timesOf(t), (std::vector<long>{300, 400}));
	EXPECT_EQ(t.events.blinks, std::vector<Ticks>{ms(350)});
	EXPECT_EQ(t.events.brows[0].time, ms(320));
	EXPECT_EQ(t.marks[0].time, ms(370));
}

TEST(Timeline, spliceKeepsWhatDrawnFramesDependOnAndHoldsTheGap) {
	// Speaking: keys at 0, 100, 200, 300; frames drawn up to 150; the next utterance at 250.
	Timeline live = keysAt({0, 100, 200, 300}, "a");
	Timeline next = keysAt({0, 80}, "p1");
	next.events.blinks = {ms(40)};
	next.marks.push_back({"m", ms(10)});
	live.splice(next, ms(250), ms(150));
	// 0 and 100 (before 250), 200 (the first after the last drawn frame); 300 went; then b at 250, 330.
	EXPECT_EQ(timesOf(live), (std::vector<long>{0, 100, 200, 250, 330}));
	EXPECT_EQ(live.keys[3].cdv, "p1");
	EXPECT_EQ(live.events.blinks, std::vector<Ticks>{ms(290)});
	ASSERT_EQ(live.marks.size(), 1u);
	EXPECT_EQ(live.marks[0].time, ms(260));

	// Holding (no key after the last drawn frame): the pose held fills the gap until the utterance starts.
	Timeline idle = keysAt({0}, "sil");
	idle.keys[0].breath = true;
	idle.splice(keysAt({0, 50}, "p1"), ms(400), ms(200));
	EXPECT_EQ(timesOf(idle), (std::vector<long>{0, 400, 450}));
	EXPECT_EQ(idle.keys[1].cdv, "sil");  // the held pose
	EXPECT_FALSE(idle.keys[1].breath);
	// A key of the utterance at or before the last kept one is left out (never two keys at one time).
	EXPECT_EQ(idle.keys[2].cdv, "p1");
}

TEST(Timeline, cutAndDropBefore) {
	Timeline t = keysAt({0, 100, 200, 300}, "a");
	t.events.blinks = {ms(50), ms(250)};
	t.marks = {{"early", ms(50)}, {"late", ms(250)}};
	t.cut(ms(200));
	EXPECT_EQ(t.events.blinks, std::vector<Ticks>{ms(50)});
	ASSERT_EQ(t.marks.size(), 1u);
	EXPECT_EQ(t.marks[0].name, "early");
	EXPECT_EQ(timesOf(t), (std::vector<long>{0, 100, 200, 300}));  // the keys are the caller's
	t.dropBefore(ms(250));
	EXPECT_EQ(timesOf(t), (std::vector<long>{200, 300}));  // the last key before 250 stays: frames there need it
	EXPECT_TRUE(t.marks.empty());
	EXPECT_EQ(t.firstAfter(ms(200)), 1u);
	EXPECT_EQ(t.firstAfter(ms(400)), 2u);
}
