// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead serve's requests (issue 16): parsing, and timing from Azure viseme events and ElevenLabs
// character timestamps.
#include <gtest/gtest.h>

#include "base/error.h"
#include "serve/server.h"
#include "test_support.h"

using namespace talkhead;
using talkhead::test::errorOf;

TEST(LiveRequest, parsesEachTypeAndRefusesWhatIsWrong) {
	const LiveRequest say = parseLiveRequest(R"({"type": "say", "id": 7, "text": "Olá", "lang": "pt-BR", "emotion": "happy", "intensity": 0.5})");
	EXPECT_EQ(say.kind, LiveRequest::Kind::Say);
	EXPECT_EQ(say.id, "7");
	EXPECT_EQ(say.emotion.value_or(""), "joy");  // an alias
	EXPECT_DOUBLE_EQ(say.intensity, 0.5);
	EXPECT_EQ(parseLiveRequest(R"({"type": "stop"})").kind, LiveRequest::Kind::Stop);
	const LiveRequest e = parseLiveRequest(R"({"type": "emotion", "emotion": "anger", "ramp": 1.5})");
	EXPECT_EQ(e.ramp, ticksFromSeconds(1.5));
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "emotion"})"); }).find("'emotion' is missing"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "emotion", "emotion": "grumpy"})"); }).find("unknown emotion 'grumpy'"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "say", "text": "x", "rate": 9000})"); }).find("'rate' must be from 80 to 450"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"([1, 2])"); }).find("a JSON object"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "!!!", "transcript": ""})"); }).find("not base64"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "AAAA"})"); }).find("one of 'transcript', 'visemes'"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "AAAA", "visemes": [{"id": 22, "offset_ms": 0}]})"); }).find("id 22 is not 0-21"),
	          std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "AAAA", "visemes": [{"id": 1, "offset_ms": 90}, {"id": 2, "offset_ms": 10}]})"); })
	              .find("comes before"),
	          std::string::npos);
}

TEST(LiveRequest, azureVisemesAndElevenLabsCharactersBecomeTimings) {
	// Azure: offsets in ms, or the SDK's AudioOffset in 100 ns; each viseme lasts until the next.
	const LiveRequest az = parseLiveRequest(
	    R"({"type": "speak", "audio": "AAAA", "visemes": [{"id": 0, "offset_ms": 0}, {"VisemeId": 21, "AudioOffset": 500000}, {"id": 2, "offset_ms": 120}]})");
	ASSERT_TRUE(az.timing);
	EXPECT_EQ(az.timing->level, LabelLevel::Viseme);
	EXPECT_EQ(az.timing->visemeScheme, "azure");
	ASSERT_EQ(az.timing->intervals.size(), 3u);
	EXPECT_EQ(az.timing->intervals[1].label, "21");
	EXPECT_EQ(az.timing->intervals[1].start, ticksFromSeconds(0.05));
	EXPECT_EQ(az.timing->intervals[1].end, ticksFromSeconds(0.12));
	// Their CDVs through phonetics/viseme-input.tsv.
	Transcript t = *az.timing;
	t.intervals.back().end = ticksFromSeconds(0.3);
	const auto phones = phoneSegments(t, Language::get("en-US"));
	ASSERT_EQ(phones.size(), 3u);
	EXPECT_EQ(phones[0].cdv, "sil");
	EXPECT_EQ(phones[1].cdv, "p1");
	EXPECT_EQ(phones[2].cdv, "a");
	// ElevenLabs: characters grouped into words at spaces.
	const LiveRequest el = parseLiveRequest(
	    R"({"type": "speak", "audio": "AAAA", "alignment": {"characters": ["H", "i", " ", "y", "o", "u"],
	        "character_start_times_seconds": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6], "character_end_times_seconds": [0.2, 0.3, 0.4, 0.5, 0.6, 0.7]}})");
	ASSERT_TRUE(el.timing);
	EXPECT_EQ(el.timing->level, LabelLevel::Word);
	ASSERT_EQ(el.timing->intervals.size(), 2u);
	EXPECT_EQ(el.timing->intervals[0].label, "Hi");
	EXPECT_EQ(el.timing->intervals[0].start, ticksFromSeconds(0.1));
	EXPECT_EQ(el.timing->intervals[0].end, ticksFromSeconds(0.3));
	EXPECT_EQ(el.timing->intervals[1].label, "you");
	EXPECT_EQ(el.timing->intervals[1].start, ticksFromSeconds(0.4));
}
