// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"
#include "phonetics/espeak.h"
#include "phonetics/ssml.h"

using namespace talkhead;

namespace {
std::string failure(const std::string& text) {
	try {
		parseSsml(text, "t");
	} catch (const Error& e) {
		return e.what();
	}
	return "no error";
}
}  // namespace

TEST(Ssml, theSubsetIsReadAndBadMarkupNamedWithItsPosition) {
	EXPECT_TRUE(looksLikeSsml("Hello <break time=\"1s\"/> world"));
	EXPECT_FALSE(looksLikeSsml("a < b and c > d"));
	const SsmlText t = parseSsml("<speak>Bom dia &amp; <mark name=\"x\"/>boa <break time=\"250ms\"/>noite <emotion name=\"joy\" intensity=\"0.5\">e <blink/>tchau</emotion></speak>", "t");
	ASSERT_EQ(t.segments.size(), 2u);
	EXPECT_EQ(t.segments[0].text, "Bom dia & boa ");
	EXPECT_EQ(t.segments[0].pauseAfter, ticksFromSeconds(0.25));
	EXPECT_EQ(t.segments[1].text, "noite e tchau");
	ASSERT_EQ(t.events.size(), 4u);
	EXPECT_EQ(t.events[0].kind, SsmlText::Event::Kind::Mark);
	EXPECT_EQ(t.events[0].offset, 10u);  // before "boa"
	EXPECT_EQ(t.events[1].kind, SsmlText::Event::Kind::EmotionStart);
	EXPECT_EQ(t.events[1].name, "joy");
	EXPECT_EQ(t.events[1].intensity, 0.5);
	EXPECT_EQ(t.events[2].kind, SsmlText::Event::Kind::Blink);
	EXPECT_EQ(t.events[2].segment, 1u);
	EXPECT_EQ(t.events[2].offset, 8u);  // before "tchau"
	EXPECT_EQ(t.events[3].kind, SsmlText::Event::Kind::EmotionEnd);
	EXPECT_EQ(failure("Bom\n dia <emotion name=\"joy\">x"), "t:2: column 6: <emotion> is not closed");
	EXPECT_EQ(failure("a <break time=\"soon\"/>"), "t:1: column 3: <break> time must be like 300ms or 1.5s, at most 60 s");
	EXPECT_EQ(failure("a <pause/>"), "t:1: column 3: unknown tag <pause> (known: speak, emotion, break, mark, blink, brows)");
	EXPECT_EQ(failure("a <mark nome=\"x\"/>"), "t:1: column 3: <mark> has no attribute 'nome'");
	EXPECT_EQ(failure("<speak>a</emotion>"), "t:1: column 9: </emotion> closes nothing open (open: <speak>)");
	const SsmlText b = parseSsml("a <brows up=\"0.8\"/>b <brows down=\"0.5\"/>c", "t");
	ASSERT_EQ(b.events.size(), 2u);
	EXPECT_EQ(b.events[0].kind, SsmlText::Event::Kind::Brows);
	EXPECT_EQ(b.events[0].intensity, 0.8);
	EXPECT_EQ(b.events[1].frown, 0.5);
	EXPECT_EQ(failure("a <brows/>"), "t:1: column 3: <brows> needs up=\"…\" or down=\"…\" (0–1.5)");
	EXPECT_EQ(failure("<speak>a &nbsp; b</speak>"), "t:1: column 10: unknown entity (use &amp; &lt; &gt; &quot; &apos;)");
}

TEST(Ssml, aBreakIsAPauseOfItsLengthAndAMarkFallsOnItsWord) {
	const SsmlText t = parseSsml("Bom dia. <break time=\"700ms\"/><mark name=\"m\"/>Vamos ver.", "t");
	std::vector<Ticks> times;
	const Speech s = espeakSpeakSsml(t, "pt-br", times);
	// The words: Bom, dia, Vamos, ver. The silence between "dia" and "Vamos" is the break (the next word's
	// event may precede its first phone by a closure, a few ms).
	ASSERT_EQ(s.words.intervals.size(), 4u);
	const Ticks gap = s.words.intervals[2].start - s.words.intervals[1].end;
	EXPECT_NEAR(toSeconds(gap), 0.7, 0.02);
	ASSERT_EQ(times.size(), 1u);
	EXPECT_EQ(times[0], s.words.intervals[2].start);
	// The PCM is exactly as long as the phone timeline, which is contiguous.
	EXPECT_NEAR(double(s.pcm.size()) / s.sampleRate, toSeconds(s.phones.intervals.back().end), 1e-3);
	for (std::size_t i = 1; i < s.phones.intervals.size(); ++i) EXPECT_EQ(s.phones.intervals[i].start, s.phones.intervals[i - 1].end);
}
