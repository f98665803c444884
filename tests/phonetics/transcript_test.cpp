// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <functional>

#include "base/error.h"
#include "phonetics/transcript.h"

#include "test_support.h"

using namespace talkhead;

namespace {
const std::string kDir = std::string(TALKHEAD_TEST_DATA_DIR) + "/transcripts/";

using test::errorOf;

std::vector<std::string> labels(const Transcript& t) {
	std::vector<std::string> l;
	for (const auto& iv : t.intervals) l.push_back(iv.label);
	return l;
}

const std::vector<std::string> kQueNoticia = {"", "k", "i", "n", "o", "t", "i", "s", "e", "l", "ẽ", "t", "ɪ", ""};

Ticks ms(long v) { return Ticks(v * (kTicksPerSecond / 1000)); }
}  // namespace

TEST(TextGrid, longShortAndUtf16FormsReadTheSamePhoneTier) {
	for (const char* f : {"que_noticia.TextGrid", "que_noticia_short.TextGrid", "que_noticia_utf16.TextGrid"}) {
		Transcript t = readTranscript(kDir + f);
		EXPECT_EQ(t.format, "textgrid") << f;
		EXPECT_EQ(labels(t), kQueNoticia) << f;  // the "phones" tier, not the first ("words") one
		EXPECT_EQ(t.intervals[1].start, ms(100)) << f;
		EXPECT_EQ(t.intervals[1].end, ms(180)) << f;
		EXPECT_EQ(t.intervals.back().end, ms(1300)) << f;
	}
	Transcript words = readTranscript(kDir + "que_noticia.TextGrid", {"", "words", ""});
	EXPECT_EQ(labels(words), (std::vector<std::string>{"", "Que", "notícia", "excelente", ""}));
}

TEST(TextGrid, escapedQuotesTrigraphsAndTierSelection) {
	Transcript t = readTranscript(kDir + "quotes.TextGrid");  // first tier is a point tier: skipped
	EXPECT_EQ(labels(t), (std::vector<std::string>{"\\ep", "say \"hi\"", ""}));
	EXPECT_EQ(errorOf([] { readTranscript(kDir + "quotes.TextGrid", {"", "phones", ""}); }),
	          kDir + "quotes.TextGrid: no tier named 'phones' (tiers: 'pts' (points), 'segs' (intervals))");
	EXPECT_NE(errorOf([] { readTranscript(kDir + "quotes.TextGrid", {"", "pts", ""}); }).find("is a point tier"), std::string::npos);
}

TEST(TextGrid, malformedInputIsRejectedWithFileAndLine) {
	const std::string head = "File type = \"ooTextFile\"\nObject class = \"TextGrid\"\n\nxmin = 0\nxmax = 1\ntiers? <exists>\nsize = 1\nitem []:\n"
	                         "    item [1]:\n        class = \"IntervalTier\"\n        name = \"phones\"\n        xmin = 0\n        xmax = 1\n";
	// An interval past the end of its tier (line 17).
	std::string past = head + "        intervals: size = 1\n        intervals [1]:\n            xmin = 0\n            xmax = 1.5\n            text = \"a\"\n";
	EXPECT_EQ(errorOf([&] { parseTranscript(past, "p.TextGrid"); }).rfind("p.TextGrid:16: interval [0.000000, 1.500000] lies outside its tier", 0), 0u);
	// Reversed times.
	std::string rev = head + "        intervals: size = 1\n        intervals [1]:\n            xmin = 0.5\n            xmax = 0.2\n            text = \"a\"\n";
	EXPECT_NE(errorOf([&] { parseTranscript(rev, "r.TextGrid"); }).find("r.TextGrid:16: interval ends"), std::string::npos);
	// Truncated file.
	EXPECT_NE(errorOf([&] { parseTranscript(head + "        intervals: size = 2\n", "t.TextGrid"); }).find("unexpected end of file"), std::string::npos);
	// Overlapping intervals.
	std::string ov = head + "        intervals: size = 2\n        intervals [1]:\n            xmin = 0\n            xmax = 0.6\n            text = \"a\"\n"
	                        "        intervals [2]:\n            xmin = 0.5\n            xmax = 1\n            text = \"b\"\n";
	EXPECT_EQ(errorOf([&] { parseTranscript(ov, "o.TextGrid"); }), "o.TextGrid:20: interval 'b' [0.5, 1] overlaps 'a' [0, 0.6] (line 16) by 0.1 s");
}

TEST(Pho, cumulativeDurationsFromMilliseconds) {
	Transcript t = readTranscript(kDir + "que_noticia.pho");
	EXPECT_EQ(t.format, "pho");
	ASSERT_EQ(t.intervals.size(), 14u);
	EXPECT_EQ(t.intervals[0].label, "");  // "_" is a pause
	EXPECT_EQ(t.intervals[1].label, "k");
	EXPECT_EQ(t.intervals[1].start, ms(100));
	EXPECT_EQ(t.intervals[2].end, ms(250));
	EXPECT_EQ(t.intervals[10].label, "e~");
	EXPECT_EQ(t.intervals.back().end, ms(1300));
	EXPECT_NE(errorOf([] { parseTranscript("a 10\nb x\n", "bad.pho", {"pho", "", ""}); }).find("bad.pho:2: bad duration 'x'"), std::string::npos);
}

TEST(Htk, labelFileAndMasterLabelFile) {
	Transcript t = readTranscript(kDir + "que_noticia.lab");
	EXPECT_EQ(t.format, "htk");
	ASSERT_EQ(t.intervals.size(), 14u);
	EXPECT_EQ(t.intervals[0].label, "sil");
	EXPECT_EQ(t.intervals[1].start, ms(100));  // 1 000 000 × 100 ns
	Transcript first = readTranscript(kDir + "two.mlf");
	EXPECT_EQ(labels(first), (std::vector<std::string>{"sil", "a"}));
	Transcript second = readTranscript(kDir + "two.mlf", {"", "", "second"});
	EXPECT_EQ(labels(second), (std::vector<std::string>{"sil", "u", "sil"}));
	EXPECT_EQ(second.intervals[1].end, ms(300));
	EXPECT_EQ(labels(readTranscript(kDir + "two.mlf", {"", "", "2"})), labels(second));
	EXPECT_NE(errorOf([] { readTranscript(kDir + "two.mlf", {"", "", "third"}); }).find("no utterance 'third' in the MLF (utterances: */first.lab, */second.lab)"),
	          std::string::npos);
	// Numbers are indices, never substrings of names; a suffix must be unique (issue 12 item 5).
	EXPECT_NE(errorOf([] { readTranscript(kDir + "two.mlf", {"", "", "3"}); }).find("no utterance 3: the MLF holds 2 (*/first.lab, */second.lab)"),
	          std::string::npos);
	EXPECT_NE(errorOf([] { readTranscript(kDir + "two.mlf", {"", "", ".lab"}); }).find("utterance '.lab' is ambiguous"), std::string::npos);
	EXPECT_EQ(labels(readTranscript(kDir + "two.mlf", {"", "", "*/second.lab"})), labels(second));
	EXPECT_EQ(labels(readTranscript(kDir + "two.mlf", {"", "", "second.lab"})), labels(second));
}

TEST(Grid, wordAlignmentInFortyMicrosecondUnits) {
	const std::string path = std::string(TALKHEAD_SHARED_DATA) + "/grid/swwp2s.align";
	Transcript t;
	try {
		t = readTranscript(path);
	} catch (const Error&) {
		GTEST_SKIP() << "GRID data not found at " << path;
	}
	EXPECT_EQ(t.format, "grid");
	EXPECT_EQ(t.level, LabelLevel::Word);
	EXPECT_EQ(labels(t), (std::vector<std::string>{"sil", "set", "white", "with", "p", "two", "soon", "sil"}));
	EXPECT_EQ(t.intervals[1].start, Ticks(12250 * (kTicksPerSecond / 25000)));  // 0.49 s
	EXPECT_EQ(t.intervals.back().end, Ticks(74500 * (kTicksPerSecond / 25000)));  // 2.98 s
}

TEST(Tsv, headerBomUnsortedRowsAndGaps) {
	Transcript t = readTranscript(kDir + "unsorted_gap.tsv");
	EXPECT_EQ(t.format, "tsv");
	EXPECT_EQ(labels(t), (std::vector<std::string>{"k", "i", "n", "", "t"}));  // sorted; the gap became a pause
	EXPECT_EQ(t.intervals[3].start, ms(310));
	EXPECT_EQ(t.intervals[3].end, ms(400));
	// Zero-length intervals are dropped; negative times rejected.
	EXPECT_EQ(labels(parseTranscript("0\t0.1\ta\n0.1\t0.1\tb\n0.1\t0.2\tc\n", "z.tsv")), (std::vector<std::string>{"a", "c"}));
	EXPECT_EQ(errorOf([] { parseTranscript("0\t0.1\ta\n-0.1\t0.2\tc\n", "n.tsv", {"tsv", "", ""}); }), "n.tsv:2: start is negative (-0.1)");
	EXPECT_EQ(errorOf([] { parseTranscript("   \n", "e.tsv"); }), "e.tsv: empty transcript");
}

TEST(SpeechMarks, visemeMarksWinOverWordMarks) {
	Transcript v = readTranscript(kDir + "polly_visemes.marks");
	EXPECT_EQ(v.format, "marks");
	EXPECT_EQ(v.level, LabelLevel::Viseme);
	EXPECT_EQ(v.visemeScheme, "polly");
	EXPECT_EQ(labels(v).front(), "k");
	EXPECT_EQ(v.intervals[0].start, ms(6));
	EXPECT_EQ(v.intervals[0].end, ms(80));
	EXPECT_EQ(v.intervals.back().end, ms(450));  // the last mark lasts 150 ms
	Transcript w = readTranscript(kDir + "polly_words.marks");
	EXPECT_EQ(w.level, LabelLevel::Word);
	EXPECT_EQ(labels(w), (std::vector<std::string>{"Que", "notícia"}));
	EXPECT_NE(errorOf([] { parseTranscript("{\"time\": 5, \"type\": \"word\"\n", "m.marks", {"marks", "", ""}); }).find("m.marks:1: malformed JSON"),
	          std::string::npos);
}

TEST(Rhubarb, mouthCuesInTsvAndJson) {
	Transcript a = readTranscript(kDir + "rhubarb.tsv"), b = readTranscript(kDir + "rhubarb.json");
	EXPECT_EQ(a.format, "rhubarb-tsv");
	EXPECT_EQ(b.format, "rhubarb-json");
	EXPECT_EQ(labels(a), (std::vector<std::string>{"X", "B", "C", "A", "F"}));
	EXPECT_EQ(labels(a), labels(b));
	for (std::size_t i = 0; i < a.intervals.size(); ++i) {
		EXPECT_EQ(a.intervals[i].start, b.intervals[i].start);
		EXPECT_EQ(a.intervals[i].end, b.intervals[i].end);
	}
}

TEST(SpeechMarks, ssmlTagsReportedAsWordsArePausesAndArraysRead) {
	// Polly reports <break/> as a word mark; it must be a pause, not phonemised and spoken (issue 12 item 3).
	const std::string lines =
	    "{\"time\":0,\"type\":\"sentence\",\"start\":0,\"end\":30,\"value\":\"Hi there\"}\n"
	    "{\"time\":6,\"type\":\"word\",\"start\":0,\"end\":2,\"value\":\"Hi\"}\n"
	    "{\"time\":300,\"type\":\"ssml\",\"start\":3,\"end\":30,\"value\":\"<break time=\\\"300ms\\\"/>\"}\n"
	    "{\"time\":310,\"type\":\"word\",\"start\":3,\"end\":30,\"value\":\"<break time=\\\"300ms\\\"/>\"}\n"
	    "{\"time\":620,\"type\":\"word\",\"start\":31,\"end\":36,\"value\":\"there\"}\n";
	Transcript t = parseTranscript(lines, "s.marks");
	EXPECT_EQ(t.level, LabelLevel::Word);
	EXPECT_EQ(labels(t), (std::vector<std::string>{"Hi", "", "there"}));
	EXPECT_EQ(t.intervals[1].start, ms(310));
	EXPECT_EQ(t.intervals[1].end, ms(620));
	// The same marks as one JSON array.
	Transcript a = parseTranscript("[{\"time\":6,\"type\":\"word\",\"value\":\"Hi\"},\n{\"time\":620,\"type\":\"word\",\"value\":\"there\"}]\n", "a.json");
	EXPECT_EQ(a.format, "marks");
	EXPECT_EQ(labels(a), (std::vector<std::string>{"Hi", "there"}));
}

TEST(Timit, phnTimesAreSamplesAndIntegerTimesAreNeverGuessed) {
	// TIMIT .phn: sample numbers at 16 kHz (issue 12 item 4); once read as GRID's 1/25000 s units.
	const std::string phn = "0 3050 h#\n3050 4559 sh\n4559 5723 iy\n5723 8000 h#\n";
	Transcript t = parseTranscript(phn, "SA1.PHN");
	EXPECT_EQ(t.format, "timit");
	EXPECT_EQ(t.level, LabelLevel::Phone);
	ASSERT_EQ(t.intervals.size(), 4u);
	EXPECT_EQ(t.intervals[1].start, Ticks(3050 * (kTicksPerSecond / 16000)));
	EXPECT_EQ(parseTranscript(phn, "no-extension").format, "timit");  // starts with h#
	ReadOptions o;
	o.sampleRate = 8000;
	EXPECT_EQ(parseTranscript(phn, "x.phn", o).intervals[1].start, Ticks(3050 * (kTicksPerSecond / 8000)));
	// GRID starts with sil; integer times with neither marker and no telling extension: an error, no guess.
	EXPECT_EQ(parseTranscript("0 12250 sil\n12250 19250 set\n", "g").format, "grid");
	EXPECT_NE(errorOf([] { parseTranscript("0 3050 x\n3050 4559 y\n", "u.txt"); }).find("integer times have no unit of their own"), std::string::npos);
}
