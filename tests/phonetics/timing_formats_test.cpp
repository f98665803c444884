// SPDX-License-Identifier: GPL-3.0-or-later
// Timing files of today's speech pipelines (issue 29): one small file written for each format
// (tests/data/timing/), read to known intervals, levels and labels; their errors.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "base/error.h"
#include "phonetics/language.h"
#include "phonetics/timing_formats.h"
#include "phonetics/transcript.h"
#include "test_support.h"

namespace talkhead {
namespace {

using talkhead::test::errorOf;

std::string dataFile(const std::string& name) { return std::string(TALKHEAD_TEST_DATA_DIR) + "/timing/" + name; }

Transcript read(const std::string& name, ReadOptions o = {}) { return readTranscript(dataFile(name), o); }

// "label@start-end" per interval (pauses included), seconds to the millisecond.
std::string shape(const Transcript& t) {
	std::string s;
	for (const Interval& i : t.intervals) {
		char b[160];
		std::snprintf(b, sizeof b, "%s%s@%.3f-%.3f", s.empty() ? "" : " ", i.label.c_str(), toSeconds(i.start), toSeconds(i.end));
		s += b;
	}
	return s;
}

TEST(TimingFormats, whisperFamilyOpenAiAndDeepgramAreWords) {
	const Transcript wx = read("whisperx.json");
	EXPECT_EQ(wx.format, "whisper");
	EXPECT_EQ(wx.level, LabelLevel::Word);
	EXPECT_EQ(shape(wx), "Hello@0.100-0.500 @0.500-0.550 world,@0.550-1.000");  // "42." has no times (WhisperX)
	ASSERT_EQ(wx.warnings.size(), 1u);
	EXPECT_NE(wx.warnings[0].find("1 word has no times"), std::string::npos);
	EXPECT_EQ(shape(read("faster_whisper.json")), "Good@0.000-0.400 day@0.400-0.900");
	const Transcript oa = read("openai_words.json");
	EXPECT_EQ(oa.format, "openai");
	EXPECT_EQ(shape(oa), "Thank@0.000-0.300 you@0.300-0.620");
	const Transcript dg = read("deepgram.json");
	EXPECT_EQ(dg.format, "deepgram");
	EXPECT_EQ(shape(dg), "hi@0.080-0.400 there@0.400-0.900");
	// The languages they name.
	auto text = [](const std::string& n) {
		std::ifstream f(dataFile(n));
		std::stringstream b;
		b << f.rdbuf();
		return b.str();
	};
	EXPECT_EQ(timingFileLanguage(text("whisperx.json")).value_or(""), "en-US");
	EXPECT_EQ(timingFileLanguage(text("faster_whisper.json")).value_or(""), "en-US");
	EXPECT_EQ(timingFileLanguage(text("aeneas.json")).value_or(""), "en-US");
	EXPECT_FALSE(timingFileLanguage(text("deepgram.json")));
	// Words become phones through espeak-ng.
	const auto phones = phoneSegments(oa, Language::get("en-US"));
	std::string p;
	for (const auto& s : phones) p += s.phone + " ";
	EXPECT_EQ(p, "θ æ ŋ k j u ");
}

TEST(TimingFormats, gentleMfaAndFestivalArePhones) {
	const Transcript g = read("gentle.json");
	EXPECT_EQ(g.format, "gentle");
	EXPECT_EQ(g.level, LabelLevel::Phone);
	EXPECT_EQ(shape(g), "DH@0.100-0.150 AH@0.150-0.250 @0.250-0.600 S@0.600-0.700 AE@0.700-0.800 T@0.800-0.900");
	ASSERT_EQ(g.warnings.size(), 1u);
	EXPECT_NE(g.warnings[0].find("1 word of the transcript Gentle did not find in the audio"), std::string::npos);
	const Transcript m = read("mfa.json");
	EXPECT_EQ(m.format, "mfa-json");
	EXPECT_EQ(m.tier, "phones");
	EXPECT_EQ(shape(m), "B@0.100-0.200 AA1@0.200-0.400 B@0.400-0.500");
	const Transcript f = read("festival.utt");
	EXPECT_EQ(f.format, "festival");
	EXPECT_EQ(shape(f), "pau@0.000-0.100 hh@0.100-0.180 ay@0.180-0.400 pau@0.400-0.500");
}

TEST(TimingFormats, aeneasAzureAndElevenLabs) {
	const Transcript a = read("aeneas.json");
	EXPECT_EQ(a.format, "aeneas");
	EXPECT_EQ(shape(a), "Good morning.@0.000-1.500 @1.500-2.000");
	const Transcript v = read("azure_visemes.json");
	EXPECT_EQ(v.level, LabelLevel::Viseme);
	EXPECT_EQ(shape(v), "0@0.000-0.050 21@0.050-0.150 5@0.150-0.250 0@0.250-0.300");
	// Azure's viseme 5 (ɝ) gets the mouth the phone path gives ɝ.
	const auto vis = phoneSegments(v, Language::get("en-US"));
	Transcript er;
	er.path = "er";
	er.intervals = {{Ticks(0), ticksFromSeconds(0.1), "ɝ", 1}};
	EXPECT_EQ(vis[2].cdv, phoneSegments(er, Language::get("en-US"))[0].cdv);
	EXPECT_EQ(shape(read("azure_words.json")), "Hello@0.050-0.350 @0.350-0.400 there@0.400-0.700");
	EXPECT_EQ(shape(read("elevenlabs.json")), "Hi@0.000-0.200 @0.200-0.250 you@0.250-0.500");
}

// Timing files that refer to their text (aeneas SMIL and TSV, Google timepoints) read with it (--timing-text).
TEST(TimingFormats, smilTsvAndGoogleWithTheirText) {
	auto with = [](const std::string& text) {
		ReadOptions o;
		o.timingText = dataFile(text);
		return o;
	};
	const std::string want = "Good morning.@0.000-1.500 Fish & chips!@1.500-2.800";
	const Transcript smil = read("aeneas.smil", with("aeneas.xhtml"));
	EXPECT_EQ(smil.format, "smil");
	EXPECT_EQ(smil.level, LabelLevel::Word);
	EXPECT_EQ(shape(smil), want);
	ASSERT_EQ(smil.warnings.size(), 1u);
	EXPECT_NE(smil.warnings[0].find("times sentences, not words"), std::string::npos);
	EXPECT_EQ(shape(read("aeneas.smil", with("aeneas_plain.txt"))), want);
	EXPECT_EQ(shape(read("aeneas.tsv", with("aeneas_parsed.txt"))), want);
	EXPECT_EQ(shape(read("aeneas.tsv", with("aeneas_plain.txt"))), want);
	EXPECT_EQ(read("aeneas.tsv", with("aeneas_plain.txt")).level, LabelLevel::Word);
	// A fragment the text lacks, and no text at all: errors that say what to give.
	const std::string missing = errorOf([&] { parseTranscript("0.0\t1.0\tf000009\n", "m.tsv", with("aeneas_parsed.txt")); });
	EXPECT_NE(missing.find("m.tsv:1: the fragment 'f000009' is not in " + dataFile("aeneas_parsed.txt") + " (read as parsed (id|text) text)"), std::string::npos) << missing;
	EXPECT_NE(errorOf([] { read("aeneas.smil"); }).find("or give the text it refers to ({{timing-text}} FILE"), std::string::npos);
	EXPECT_NE(errorOf([] { read("aeneas.tsv"); }).find("{{timing-text}} FILE"), std::string::npos);

	const Transcript g = read("google_timepoints.json", with("google.ssml"));
	EXPECT_EQ(g.format, "google");
	EXPECT_EQ(shape(g), "Hello@0.050-0.420 world@0.420-0.900");
	EXPECT_TRUE(g.warnings.empty());
	// No mark after the last word: it lasts as long as espeak-ng says it, with a warning.
	const Transcript open = read("google_timepoints.json", with("google_open_end.ssml"));
	ASSERT_EQ(open.intervals.size(), 2u);
	const double last = toSeconds(open.intervals[1].end - open.intervals[1].start);
	EXPECT_GT(last, 0.2);
	EXPECT_LT(last, 1.0);
	ASSERT_EQ(open.warnings.size(), 1u);
	EXPECT_NE(open.warnings[0].find("no end time"), std::string::npos);
	const std::string noMark = errorOf([&] {
		parseTranscript(R"({"timepoints": [{"markName": "zz", "timeSeconds": 0.1}]})", "g.json", with("google.ssml"));
	});
	EXPECT_NE(noMark.find("<mark name=\"w0\"/> has no timepoint in g.json"), std::string::npos) << noMark;
}

TEST(TimingFormats, subtitlesAndCtm) {
	const Transcript srt = read("words.srt");
	EXPECT_EQ(srt.format, "srt");
	EXPECT_EQ(srt.level, LabelLevel::Word);
	EXPECT_EQ(shape(srt), "Hello@0.100-0.500 world@0.500-1.000");
	EXPECT_TRUE(srt.warnings.empty());
	const Transcript vtt = read("words.vtt");
	EXPECT_EQ(vtt.format, "vtt");
	EXPECT_EQ(shape(vtt), "Hello@0.100-0.500 world@0.500-1.000");
	const Transcript w = read("words.ctm");
	EXPECT_EQ(w.format, "ctm");
	EXPECT_EQ(w.level, LabelLevel::Word);
	EXPECT_EQ(shape(w), "hello@0.100-0.500 world@0.500-1.000");
	ReadOptions en;
	en.knownPhone = [](const std::string& l) { return Language::get("en-US").normalize(l).has_value(); };
	const Transcript p = read("phones.ctm", en);
	EXPECT_EQ(p.level, LabelLevel::Phone);
	EXPECT_EQ(shape(p), "HH@0.100-0.200 AH0@0.200-0.400 L@0.400-0.500 OW1@0.500-0.700");
	// Two recordings (or channels) are two speakers to choose from (issue 50).
	EXPECT_NE(errorOf([] { read("two_utterances.ctm"); }).find("two_utterances.ctm: words of 2 recording and channels (utt1 1, utt2 1)"), std::string::npos);
	ReadOptions second;
	second.tier = "utt2 1";
	EXPECT_EQ(shape(read("two_utterances.ctm", second)), "world@0.500-1.000");
	// Never read as MBROLA .pho (issue 29 item 3), never with the utterance id as a word.
	EXPECT_EQ(detectTranscriptFormat("utt1 1 0.10 0.40 hello\n").value_or(""), "ctm");
	EXPECT_EQ(detectTranscriptFormat("a 100 50 120\n").value_or(""), "pho");
}

TEST(TimingFormats, errorsSayWhatToGiveInstead) {
	auto err = [](const std::string& text, const std::string& name) { return errorOf([&] { parseTranscript(text, name); }); };
	EXPECT_NE(err(R"({"timepoints": [{"markName": "a", "timeSeconds": 0.1}]})", "g.json").find("Google Text-to-Speech timepoints hold only the times of your SSML <mark>s, not the words: give the SSML they came from ({{timing-text}} FILE)"),
	          std::string::npos);
	const std::string unknown = err(R"({"foo": 1})", "x.json");
	EXPECT_NE(unknown.find("no timing format talkhead reads matches this file (JSON whose members are 'foo'); formats read: textgrid"), std::string::npos) << unknown;
	EXPECT_EQ(unknown.find("integer"), std::string::npos);
	EXPECT_NE(err(R"({"segments": [{"text": "hi"}]})", "w.json").find("without word timestamps"), std::string::npos);
	EXPECT_NE(err("WEBVTT\n\n00:01.000 --> 00:00.500\nx\n", "b.vtt").find("b.vtt:3: the cue ends before it starts"), std::string::npos);
	EXPECT_NE(err("1\n00:00:01,000 --> 00:00:03,000\nA\n\n2\n00:00:02,000 --> 00:00:04,000\nB\n", "o.srt").find("overlaps the one before"), std::string::npos);
	EXPECT_NE(err(R"([{"VisemeId": 22, "AudioOffset": 0}])", "v.json").find("viseme id 22 is not 0-21"), std::string::npos);
	const std::string many = errorOf([] { parseTranscript("x", "f.xyz", [] { ReadOptions o; o.format = "nope"; return o; }()); });
	EXPECT_NE(many.find("known: textgrid"), std::string::npos);
	EXPECT_NE(many.find("whisper"), std::string::npos);
}

}  // namespace
}  // namespace talkhead
