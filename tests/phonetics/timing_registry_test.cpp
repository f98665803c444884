// SPDX-License-Identifier: GPL-3.0-or-later
// The registry of timing formats, the plausibility gate and the readers of issue 50: detection by positive
// signatures only, units named when wrong, labels that are not speech left unspoken, speakers chosen.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/plausibility.h"
#include "phonetics/timing_registry.h"
#include "phonetics/transcript.h"
#include "test_support.h"

namespace talkhead {
namespace {

using talkhead::test::errorOf;

std::string shape(const Transcript& t) {
	std::string s;
	for (const Interval& i : t.intervals) {
		char b[200];
		std::snprintf(b, sizeof b, "%s%s@%.3f-%.3f", s.empty() ? "" : " ", i.label.c_str(), toSeconds(i.start), toSeconds(i.end));
		s += b;
	}
	return s;
}

Transcript parse(const std::string& text, const std::string& name, ReadOptions o = {}) { return parseTranscript(text, name, o); }
std::string err(const std::string& text, const std::string& name, ReadOptions o = {}) {
	return errorOf([&] { parseTranscript(text, name, o); });
}

// Every file of the project's fixtures and of ../shared's real inputs that reads.
std::vector<std::string> timingFiles() {
	std::vector<std::string> out;
	namespace fs = std::filesystem;
	std::vector<std::string> dirs = {std::string(TALKHEAD_TEST_DATA_DIR) + "/timing"};
	for (const char* d : {"real-inputs/in", "real-inputs-3/in", "real-inputs-4/in"}) dirs.push_back(std::string(TALKHEAD_SHARED_DATA) + "/" + d);
	for (const std::string& d : dirs) {
		std::error_code ec;
		for (const auto& e : fs::directory_iterator(d, ec))
			if (e.is_regular_file()) out.push_back(e.path().string());
	}
	std::sort(out.begin(), out.end());
	return out;
}

// Whether ../shared's real inputs are there (CI has them beside the clone; a lone clone does not).
bool sharedInputs() { return std::filesystem::is_directory(std::string(TALKHEAD_SHARED_DATA) + "/real-inputs-4/in"); }

TEST(TimingRegistry, namesAreUniqueAndEveryFormatSaysWhatItIs) {
	std::set<std::string> names;
	for (const TimingFormat& f : timingFormats()) {
		EXPECT_TRUE(names.insert(f.name).second) << f.name;
		EXPECT_FALSE(f.title.empty()) << f.name;
		EXPECT_TRUE(f.signature) << f.name;
		if (f.read) EXPECT_FALSE(f.level.empty()) << f.name;
		else EXPECT_FALSE(f.refusal.empty()) << f.name;
	}
	EXPECT_GE(names.size(), 40u);
	// The table lists every one, one line each after the header.
	const std::string table = formatsTable(false);
	EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), long(timingFormats().size()) + 1);
}

// Every real file is detected as exactly one format (or refused with one message), and the format the reader
// reports is the one detected: no file falls through to another reader.
TEST(TimingRegistry, everyFileMatchesOneSignature) {
	int files = 0;
	for (const std::string& path : timingFiles()) {
		std::string text;
		try {
			text = readTextFile(path);
		} catch (const Error&) {
			continue;
		}
		const TimingSample s(text, path);
		std::string why;
		const auto f = detectTimingFormat(s, &why);
		if (!f) {
			EXPECT_EQ(why.find("ambiguous"), std::string::npos) << path << ": " << why;
			continue;
		}
		++files;
		ReadOptions o;
		o.tier = "";
		try {
			const Transcript tr = readTimingSample(s, o);
			EXPECT_EQ(tr.format, *f) << path;
		} catch (const Error&) {  // a speaker to choose, text to give: the reader's own clear error
		}
	}
	EXPECT_GE(files, sharedInputs() ? 50 : 15);
}

TEST(TimingRegistry, twoFormatsAtOnceIsAnErrorNamingBoth) {
	// A .lab file (HTK by its extension) whose first label is TIMIT's h#.
	const std::string e = err("0 3050 h#\n3050 4559 sh\n", "x.lab");
	EXPECT_NE(e.find("ambiguous: the file fits both HTK label file"), std::string::npos) << e;
	EXPECT_NE(e.find("{{format}} htk or {{format}} timit"), std::string::npos) << e;
	// Integer times nothing settles: refused, the unit never guessed.
	EXPECT_NE(err("0 100 a\n100 200 b\n", "x.txt").find("integer times have no unit of their own"), std::string::npos);
	// XML that is no format: what it looks like.
	EXPECT_NE(err("<?xml version=\"1.0\"?><root><a/></root>", "x.xml").find("XML whose root element is <root>"), std::string::npos);
	// Named and refused, with what to export instead.
	EXPECT_NE(err("[Script Info]\nTitle: x\n", "x.ass").find("export SRT or WebVTT"), std::string::npos);
}

// The gate: every reader's output with its times ×1000 or ÷1000 is refused, naming the unit they look like.
TEST(TimingGate, scaledTimesAreRefusedNamingTheUnit) {
	int checked = 0;
	for (const std::string& path : timingFiles()) {
		Transcript tr;
		try {
			ReadOptions o;
			tr = readTranscript(path, o);
		} catch (const Error&) {
			continue;
		}
		if (tr.intervals.size() < 4) continue;
		EXPECT_EQ(errorOf([&] { checkTimingPlausibility(tr); }), "no error") << path;
		for (const double factor : {1000.0, 0.001}) {
			const std::string unit = factor > 1 ? (tr.unit == "s" ? "milliseconds" : "1000 times too long for " + tr.unit)
			                                    : (tr.unit == "ms" ? "seconds" : "1000 times too short for ");
			Transcript scaled = tr;
			scaled.statedDuration.reset();
			for (Interval& iv : scaled.intervals) {
				iv.start = Ticks(std::llround(double(iv.start.count()) * factor));
				iv.end = Ticks(std::llround(double(iv.end.count()) * factor));
			}
			const std::string e = errorOf([&] { checkTimingPlausibility(scaled); });
			EXPECT_NE(e.find("they look like " + unit), std::string::npos) << path << " ×" << factor << ": " << e;
		}
		++checked;
	}
	EXPECT_GE(checked, sharedInputs() ? 30 : 4);
}

TEST(TimingGate, aFileInMillisecondsReadAsSecondsNamesMilliseconds) {
	// AssemblyAI's words read with the OpenAI reader (seconds): the gate refuses and names milliseconds.
	const std::string words = R"({"text": "a b", "words": [{"text": "This", "start": 1437, "end": 1597}, {"text": "is", "start": 1630, "end": 1822},
	   {"text": "an", "start": 1855, "end": 2047}, {"text": "test", "start": 2080, "end": 2592}]})";
	ReadOptions o;
	o.format = "openai";
	const std::string e = err(words, "a.json", o);
	EXPECT_NE(e.find("times read as seconds are not speech: the median word lasts"), std::string::npos) << e;
	EXPECT_NE(e.find("they look like milliseconds"), std::string::npos) << e;
	// Detected, it is AssemblyAI's only with its own members; without them it is refused the same way.
	EXPECT_NE(err(words, "a.json").find("they look like milliseconds"), std::string::npos);
	const Transcript a = parse(R"({"audio_duration": 3, "words": [{"text": "This", "start": 1437, "end": 1597}, {"text": "is", "start": 1630, "end": 1822}]})", "a.json");
	EXPECT_EQ(a.format, "assemblyai");
	EXPECT_EQ(shape(a), "This@1.437-1.597 @1.597-1.630 is@1.630-1.822");
	// Past the duration the file states.
	EXPECT_NE(err(R"({"audio_duration": 1, "words": [{"text": "This", "start": 1437, "end": 1597}, {"text": "is", "start": 1630, "end": 1822}]})", "a.json")
	              .find("past the 1 s file states"),
	          std::string::npos);
}

TEST(TimingGate, azureBatchWordsAreMillisecondsAndTheSdkTicks) {
	const Transcript batch = parse(R"([{"Text": "The", "AudioOffset": 38, "Duration": 100}, {"Text": "rainbow", "AudioOffset": 138, "Duration": 363}, {"Text": ",", "AudioOffset": 501, "Duration": 10}])", "w.json");
	EXPECT_EQ(batch.format, "azure-batch-words");
	EXPECT_EQ(shape(batch), "The@0.038-0.138 rainbow@0.138-0.501");
	const Transcript sdk = parse(R"([{"Text": "Hello", "AudioOffset": 500000, "Duration": "00:00:00.3000000", "BoundaryType": "WordBoundary"}])", "w.json");
	EXPECT_EQ(sdk.format, "azure-words");
	EXPECT_EQ(shape(sdk), "Hello@0.050-0.350");
}

TEST(TimingLabels, speakersSoundEventsAndToneNumbersAreNotSpoken) {
	const Transcript t = parse(
	    "1\n00:00:01,000 --> 00:00:03,000\nThe First Minister (Nicola Sturgeon): Thank you very much\n\n"
	    "2\n00:00:03,000 --> 00:00:04,000\n[Applause.]\n\n"
	    "3\n00:00:04,000 --> 00:00:06,000\nmy number is (444) 814\n\n"
	    "4\n00:00:06,000 --> 00:00:07,000\n{\\an8}- Yes, it is\n",
	    "s.srt");
	EXPECT_EQ(shape(t), "Thank you very much@1.000-3.000 @3.000-4.000 my number is 444 814@4.000-6.000 Yes, it is@6.000-7.000");
	ASSERT_GE(t.warnings.size(), 2u);
	EXPECT_NE(joined(t.warnings, "|").find("2 bracketed sound events"), std::string::npos) << joined(t.warnings, "|");
	EXPECT_NE(joined(t.warnings, "|").find("1 speaker label"), std::string::npos) << joined(t.warnings, "|");
	// ">> NAME:" (broadcast captions) is a label too.
	EXPECT_EQ(speakerLabelLength(">> ANNA: my number"), std::string(">> ANNA:").size());
	EXPECT_EQ(speakerLabelLength("what she said: go home"), 0u);
	// "Note: this" is a sentence, not a speaker, when nothing after the colon would be left… it is a label by
	// form; a lower-case start is never one.
	EXPECT_EQ(shape(parse("1\n00:00:01,000 --> 00:00:02,000\nwhat she said: go home\n", "n.srt")), "what she said: go home@1.000-2.000");
	const Transcript pinyin = parse("0.0\t0.3\tni3\n0.3\t0.6\thao3\n0.6\t0.9\tma5\n", "p.tsv", [] {
		ReadOptions o;
		o.level = LabelLevel::Word;
		return o;
	}());
	EXPECT_EQ(shape(pinyin), "ni@0.000-0.300 hao@0.300-0.600 ma@0.600-0.900");
}

TEST(TimingLanguage, namesAsFilesWriteThem) {
	EXPECT_EQ(languageTagOf("zho"), "zh");
	EXPECT_EQ(languageTagOf("en_us"), "en-US");
	EXPECT_EQ(languageTagOf("eng"), "en-US");
	EXPECT_EQ(languageTagOf("English"), "en-US");
	EXPECT_EQ(languageTagOf("en-GB"), "en-US");
	EXPECT_EQ(languageTagOf("pt"), "pt-BR");
	EXPECT_EQ(languageTagOf("fr-CA"), "fr");
	EXPECT_EQ(languageTagOf("deu"), "de");
	EXPECT_EQ(languageTagOf("vi"), "vi");
	EXPECT_EQ(languageTagOf(""), "");
	EXPECT_EQ(languageTagOf("not a language"), "");
	EXPECT_EQ(statedLanguage(TimingSample(R"({"language_code": "zho", "words": []})", "x.json")), "zho");
	EXPECT_EQ(statedLanguage(TimingSample("WEBVTT\nKind: captions\nLanguage: en\n\n00:01.000 --> 00:02.000\nhi\n", "x.vtt")), "en");
	EXPECT_EQ(statedLanguage(TimingSample(R"(<tt xmlns="http://www.w3.org/ns/ttml" xml:lang="fr"><body/></tt>)", "x.ttml")), "fr");
	EXPECT_EQ(statedLanguage(TimingSample("@UTF8\n@Begin\n@Languages:\teng, spa\n", "x.cha")), "eng");
}

// Formats of issue 50 with no real file in ../shared: small files written as their writers document them.
TEST(TimingReaders, servicesAsTheirWritersWriteThem) {
	const Transcript sm = parse(R"({"format": "2.9", "metadata": {"transcription_config": {"language": "en"}}, "results": [
	  {"type": "word", "start_time": 0.5, "end_time": 0.8, "alternatives": [{"content": "Hello", "confidence": 1, "speaker": "S1"}]},
	  {"type": "punctuation", "start_time": 0.8, "end_time": 0.8, "alternatives": [{"content": ","}]},
	  {"type": "word", "start_time": 0.9, "end_time": 1.3, "alternatives": [{"content": "world", "speaker": "S1"}]}]})",
	                            "sm.json");
	EXPECT_EQ(sm.format, "speechmatics");
	EXPECT_EQ(shape(sm), "Hello@0.500-0.800 @0.800-0.900 world@0.900-1.300");
	const Transcript v2 = parse(R"({"results": [{"alternatives": [{"transcript": "hi there", "words": [{"word": "hi", "endOffset": "0.400s"}, {"word": "there", "startOffset": "0.400s", "endOffset": "0.900s"}]}], "languageCode": "en-us"}]})",
	                            "g.json");
	EXPECT_EQ(v2.format, "google-stt");
	EXPECT_EQ(shape(v2), "hi@0.000-0.400 there@0.400-0.900");
	const Transcript az = parse(R"({"duration": "PT2S", "recognizedPhrases": [{"channel": 0, "nBest": [{"words": [{"word": "hello", "offsetInTicks": 5000000, "durationInTicks": 3000000}, {"word": "there", "offsetInTicks": 8000000, "durationInTicks": 4000000}]}]}]})",
	                            "az.json");
	EXPECT_EQ(az.format, "azure-stt");
	EXPECT_EQ(shape(az), "hello@0.500-0.800 there@0.800-1.200");
	// WhisperX diarized: a speaker to choose, by its own words' or its segment's speaker.
	const std::string wx = R"({"segments": [{"start": 0.1, "end": 1.0, "speaker": "SPEAKER_00", "words": [{"word": "Hello", "start": 0.1, "end": 0.5}, {"word": "there", "start": 0.5, "end": 1.0}]},
	  {"start": 1.2, "end": 2.0, "words": [{"word": "Hi", "start": 1.2, "end": 1.6, "speaker": "SPEAKER_01"}]}], "word_segments": []})";
	EXPECT_NE(err(wx, "wx.json").find("words of 2 speakers (SPEAKER_00, SPEAKER_01)"), std::string::npos) << err(wx, "wx.json");
	ReadOptions one;
	one.tier = "SPEAKER_01";
	EXPECT_EQ(shape(parse(wx, "wx.json", one)), "Hi@1.200-1.600");
	// YouTube json3 auto-captions: a word a seg at tStartMs + tOffsetMs; the next event's repeat left out.
	const Transcript yt = parse(R"({"wireMagic": "pb3", "events": [{"tStartMs": 0, "dDurationMs": 5000, "id": 1, "wpWinPosId": 1},
	  {"tStartMs": 1000, "dDurationMs": 2000, "wWinId": 1, "segs": [{"utf8": "hello", "acAsrConf": 0}, {"utf8": " world", "tOffsetMs": 400}]},
	  {"tStartMs": 2500, "dDurationMs": 1000, "wWinId": 1, "aAppend": 1, "segs": [{"utf8": "\n"}]}]})",
	                            "yt.json3");
	EXPECT_EQ(yt.format, "youtube-json3");
	EXPECT_EQ(shape(yt), "hello@1.000-1.400 world@1.400-3.000");
	const Transcript ibm = parse(R"({"result_index": 0, "results": [{"final": true, "alternatives": [{"transcript": "hello world ", "confidence": 0.9,
	  "timestamps": [["hello", 0.1, 0.5], ["world", 0.5, 0.9]]}]}]})",
	                             "w.json");
	EXPECT_EQ(ibm.format, "watson");
	EXPECT_EQ(shape(ibm), "hello@0.100-0.500 world@0.500-0.900");
	const Transcript det = parse(R"({"Id": "x", "RecognitionStatus": "Success", "Offset": 5000000, "Duration": 7000000, "DisplayText": "Hello world.",
	  "NBest": [{"Confidence": 0.9, "Lexical": "hello world", "Words": [{"Word": "hello", "Offset": 5000000, "Duration": 3000000}, {"Word": "world", "Offset": 8000000, "Duration": 4000000}]}]})",
	                             "d.json");
	EXPECT_EQ(det.format, "azure-detailed");
	EXPECT_EQ(shape(det), "hello@0.500-0.800 world@0.800-1.200");
	const Transcript alt = parse(R"({"alternatives": [{"confidence": 300.1, "result": [{"end": 0.9, "start": 0.5, "word": "one"}, {"end": 1.4, "start": 0.9, "word": "two"}], "text": "one two"}]})",
	                             "v.json");
	EXPECT_EQ(alt.format, "vosk");
	EXPECT_EQ(shape(alt), "one@0.500-0.900 two@0.900-1.400");
	// whisper --highlight_words: the underlined word over its cue, the cues between words left out.
	const Transcript hl = parse("WEBVTT\n\n00:00.000 --> 00:00.400\n<u>Hello</u> world\n\n00:00.400 --> 00:00.500\nHello world\n\n00:00.500 --> 00:00.900\nHello <u>world</u>\n",
	                            "hl.vtt");
	EXPECT_EQ(shape(hl), "Hello@0.000-0.400 @0.400-0.500 world@0.500-0.900");
	// NeMo's forced aligner: 8 columns, NA confidences.
	const Transcript nemo = parse("utt1 1 0.40 0.16 hello NA lex NA\nutt1 1 0.56 0.30 world NA lex NA\n", "n.ctm", [] {
		ReadOptions o;
		o.level = LabelLevel::Word;
		return o;
	}());
	EXPECT_EQ(nemo.format, "ctm");
	EXPECT_EQ(shape(nemo), "hello@0.400-0.560 world@0.560-0.860");
}

TEST(TimingReaders, documentsAndCaptions) {
	const Transcript trs = parse(R"(<?xml version="1.0"?><!DOCTYPE Trans SYSTEM "trans-14.dtd"><Trans version="1"><Speakers><Speaker id="spk1" name="Anna"/></Speakers>
<Episode><Section type="report" startTime="0" endTime="3"><Turn speaker="spk1" startTime="0" endTime="3"><Sync time="0"/>bonjour à tous<Event desc="rire" type="noise" extent="instantaneous"/><Sync time="1.5"/>merci</Turn></Section></Episode></Trans>)",
	                             "t.trs");
	EXPECT_EQ(trs.format, "transcriber");
	EXPECT_EQ(shape(trs), "bonjour à tous@0.000-1.500 merci@1.500-3.000");
	const Transcript cha = parse("@UTF8\n@Begin\n@Languages:\teng\n@Participants:\tCHI Target_Child, MOT Mother\n*CHI:\tmore cookie [/] cookie . \x15" "1200_2100\x15\n*CHI:\t&=laughs yes . \x15" "2500_3000\x15\n@End\n",
	                             "c.cha", [] {
		                             ReadOptions o;
		                             o.tier = "CHI";
		                             return o;
	                             }());
	EXPECT_EQ(cha.format, "chat");
	EXPECT_EQ(shape(cha), "more cookie cookie@1.200-2.100 @2.100-2.500 yes@2.500-3.000");
	const Transcript sbv = parse("0:00:01.000,0:00:02.500\nhello there\n\n0:00:02.500,0:00:04.000\ngeneral Kenobi\n", "x.sbv");
	EXPECT_EQ(sbv.format, "sbv");
	EXPECT_EQ(shape(sbv), "hello there@1.000-2.500 general Kenobi@2.500-4.000");
	// TTML spans inside a timed <p>: times relative to the <p>.
	const Transcript tt = parse(R"(<tt xmlns="http://www.w3.org/ns/ttml"><body><div><p begin="10s" end="12s"><span begin="0s" end="0.5s">hello</span> <span begin="0.5s" end="1.2s">world</span></p></div></body></tt>)",
	                            "x.ttml");
	EXPECT_EQ(shape(tt), "hello@10.000-10.500 world@10.500-11.200");
	// openai-whisper's TSV and whisper.cpp's CSV: milliseconds, by their header and integer times.
	const Transcript wtsv = parse("start\tend\ttext\n0\t1500\tHello there.\n1500\t2600\tGeneral Kenobi.\n", "a.tsv");
	EXPECT_EQ(wtsv.format, "whisper-tsv");
	EXPECT_EQ(shape(wtsv), "Hello there.@0.000-1.500 General Kenobi.@1.500-2.600");
	const Transcript csv = parse("start,end,text\n0,1500,\" Hello, there.\"\n", "a.csv");
	EXPECT_EQ(csv.format, "whispercpp-csv");
	EXPECT_EQ(shape(csv), "Hello, there.@0.000-1.500");
	const Transcript lyrics = parse("[ar:someone]\n[00:01.00] hello there\n[00:02.50] general Kenobi\n", "a.lrc");
	EXPECT_EQ(lyrics.format, "lrc");
	EXPECT_EQ(shape(lyrics), "hello there@1.000-2.500 general Kenobi@2.500-3.500");
	const Transcript exb = parse(R"(<?xml version="1.0"?><basic-transcription><head><speakertable><speaker id="SPK0"><abbreviation>A</abbreviation></speaker></speakertable></head>
<basic-body><common-timeline><tli id="T0" time="0.5"/><tli id="T1"/><tli id="T2" time="2.0"/></common-timeline>
<tier id="TIE0" speaker="SPK0" category="v" type="t"><event start="T0" end="T1">hello </event><event start="T1" end="T2">there</event></tier>
<tier id="TIE1" speaker="SPK0" category="en" type="d"><event start="T0" end="T2">((laughs))</event></tier></basic-body></basic-transcription>)",
	                             "a.exb");
	EXPECT_EQ(exb.format, "exmaralda");
	EXPECT_EQ(shape(exb), "hello there@0.500-2.000");
	EXPECT_NE(err("{0}{25}Hello\n{25}{50}there\n", "a.sub").find("frame numbers of a video"), std::string::npos);
	// Zoom: "Name: text" on every cue names the speakers.
	const std::string zoom = "WEBVTT\n\n1\n00:00:01.000 --> 00:00:02.000\nAnna Smith: Hello Bob\n\n2\n00:00:02.000 --> 00:00:03.500\nBob Jones: Hi Anna\n";
	EXPECT_NE(err(zoom, "z.vtt").find("words of 2 voices (Anna Smith, Bob Jones)"), std::string::npos) << err(zoom, "z.vtt");
	ReadOptions anna;
	anna.tier = "Anna Smith";
	EXPECT_EQ(shape(parse(zoom, "z.vtt", anna)), "Hello Bob@1.000-2.000");
	// Teams: <v> voices are speakers.
	const std::string teams = "WEBVTT\n\n1\n00:00:01.000 --> 00:00:02.000\n<v Anna Smith>Hello Bob</v>\n\n2\n00:00:02.000 --> 00:00:03.500\n<v Bob Jones>Hi Anna</v>\n";
	EXPECT_NE(err(teams, "t.vtt").find("words of 2 voices (Anna Smith, Bob Jones)"), std::string::npos) << err(teams, "t.vtt");
	ReadOptions bob;
	bob.tier = "Bob Jones";
	EXPECT_EQ(shape(parse(teams, "t.vtt", bob)), "Hi Anna@2.000-3.500");
	bob.tier = "Carol";
	EXPECT_NE(err(teams, "t.vtt", bob).find("no voice 'Carol' in this file (its voices: Anna Smith, Bob Jones)"), std::string::npos);
}

}  // namespace
}  // namespace talkhead
