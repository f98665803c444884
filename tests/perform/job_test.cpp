// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"
#include "perform/job.h"
#include "perform/speech_source.h"

using namespace talkhead;

TEST(Job, itsJsonReadsBackFieldForFieldWithSwitchesAndRepeatsInOrder) {
	Job j{"render", {{"transcript", "a \"b\".TextGrid"}, {"no-audio", std::nullopt}, {"components", "mouth=4"}, {"emotion", "joy:0.5"}, {"components", "eyes=2"}}};
	const std::string json = jobJson(j);
	EXPECT_EQ(json, R"({"command": "render", "fields": {"transcript": "a \"b\".TextGrid", "no-audio": true, "components": ["mouth=4", "eyes=2"], "emotion": "joy:0.5"}})");
	const Job back = parseJob(json, "j.json");
	EXPECT_EQ(back.command, "render");
	// A repeated field comes back at its first place, its values in order.
	EXPECT_EQ(back.fields, (std::vector<JobField>{{"transcript", "a \"b\".TextGrid"}, {"no-audio", std::nullopt}, {"components", "mouth=4"},
	                                             {"components", "eyes=2"}, {"emotion", "joy:0.5"}}));
	EXPECT_EQ(jobValue(back.fields, "components"), "eyes=2");  // the last, as an option given twice
	EXPECT_EQ(jobValue(back.fields, "no-audio"), "");
	EXPECT_EQ(jobValue(back.fields, "audio"), std::nullopt);
}

TEST(Job, numbersAreWrittenAsGivenAndFalseOrNullLeaveAFieldOut) {
	const Job j = parseJob(R"({"command": "say", "fields": {"fps": 25, "intensity": 0.75, "blinks": false, "seed": null, "quiet": true}})", "x");
	EXPECT_EQ(j.fields, (std::vector<JobField>{{"fps", "25"}, {"intensity", "0.75"}, {"quiet", std::nullopt}}));
}

TEST(Job, aMalformedJobIsRefusedNamingWhatIsWrong) {
	auto message = [](const std::string& text) {
		try {
			parseJob(text, "job.json");
		} catch (const Error& e) {
			return std::string(e.what());
		}
		return std::string("accepted");
	};
	EXPECT_NE(message("[1, 2]").find("job.json: a job is a JSON object"), std::string::npos);
	EXPECT_NE(message(R"({"fields": {}})").find("'command' must name the command"), std::string::npos);
	EXPECT_NE(message(R"({"command": "render", "flags": []})").find("unknown member 'flags'"), std::string::npos);
	EXPECT_NE(message(R"({"command": "render", "fields": {"--emotion": "joy"}})").find("'--emotion' is not a field name"), std::string::npos);
	EXPECT_NE(message(R"({"command": "render", "fields": {"size": {"w": 3}}})").find("'size' must be a string"), std::string::npos);
	EXPECT_NE(message(R"({"command": "render", "fields": {"size": [[1]]}})").find("array inside an array"), std::string::npos);
	EXPECT_NE(message(R"({"command": "render", )").find("job.json"), std::string::npos);
}

TEST(SpeechSource, eachKindReadsAsItsOwnFunctionAndAMissingPartIsNamedAsAField) {
	const Language& pt = Language::get("pt-BR");
	EXPECT_TRUE(loadSpeech(SpeechSource{}, pt).phones.empty());  // none: a driven mouth
	SpeechSource t;
	t.kind = SpeechSource::Kind::Transcript;
	t.transcript = std::string(TALKHEAD_TEST_DATA_DIR) + "/transcripts/que_noticia.TextGrid";
	const TimedSpeech s = loadSpeech(t, pt);
	const TimedSpeech direct = speechFromTranscript(t.transcript, ReadOptions{}, pt, UnknownPhone::Error, Notation::Auto, std::nullopt, false);
	ASSERT_FALSE(s.phones.empty());
	ASSERT_EQ(s.phones.size(), direct.phones.size());
	for (std::size_t i = 0; i < s.phones.size(); ++i) EXPECT_TRUE(s.phones[i].cdv == direct.phones[i].cdv && s.phones[i].start == direct.phones[i].start);
	SpeechSource a;
	a.kind = SpeechSource::Kind::AlignedText, a.text = "que notícia";
	try {
		loadSpeech(a, pt);
		FAIL() << "aligned text without its sound was accepted";
	} catch (const FieldError& e) {
		EXPECT_EQ(e.field(), "audio");
	}
	SpeechSource noTranscript;
	noTranscript.kind = SpeechSource::Kind::Transcript;
	EXPECT_THROW(loadSpeech(noTranscript, pt), FieldError);
}
