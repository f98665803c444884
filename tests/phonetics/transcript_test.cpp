// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <functional>

#include "base/error.h"
#include "phonetics/language.h"
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
	// Cues out of time order (found by fuzzing, issue 15) are an error, not reversed intervals.
	EXPECT_NE(errorOf([] { parseTranscript("0.00\tX\n0.55\tF\n0.05\tX\n", "r.tsv", {"rhubarb-tsv", "", ""}); })
	              .find("r.tsv:3: cue at 0.05 s comes before the previous one (line 2)"),
	          std::string::npos);
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

// ---- Transcripts from real tools (issue 12 items 7–10, docs/decisions.md D39) ----------------------------
namespace {
struct TierSpec {
	std::string name;
	std::vector<std::tuple<double, double, std::string>> intervals;
};
// A long-format TextGrid of interval tiers spanning [0, 1].
std::string textGrid(const std::vector<TierSpec>& tiers) {
	std::string s = "File type = \"ooTextFile\"\nObject class = \"TextGrid\"\n\nxmin = 0\nxmax = 1\ntiers? <exists>\nsize = " +
	                std::to_string(tiers.size()) + "\nitem []:\n";
	for (std::size_t i = 0; i < tiers.size(); ++i) {
		s += "    item [" + std::to_string(i + 1) + "]:\n        class = \"IntervalTier\"\n        name = \"" + tiers[i].name +
		     "\"\n        xmin = 0\n        xmax = 1\n        intervals: size = " + std::to_string(tiers[i].intervals.size()) + "\n";
		std::size_t k = 0;
		for (const auto& [a, b, t] : tiers[i].intervals)
			s += "        intervals [" + std::to_string(++k) + "]:\n            xmin = " + std::to_string(a) + "\n            xmax = " +
			     std::to_string(b) + "\n            text = \"" + t + "\"\n";
	}
	return s;
}
ReadOptions knowing(const std::string& lang) {
	ReadOptions o;
	const Language* l = &Language::get(lang);
	o.knownPhone = [l](const std::string& label) { return l->normalize(label).has_value(); };
	return o;
}
ReadOptions levelled(LabelLevel level) {
	ReadOptions o;
	o.level = level;
	return o;
}
ReadOptions tierNamed(const std::string& tier) {
	ReadOptions o;
	o.tier = tier;
	return o;
}
std::vector<std::string> phonesOf(const std::vector<PhoneSegment>& s) {
	std::vector<std::string> p;
	for (const auto& x : s) p.push_back(x.phone);
	return p;
}
}  // namespace

TEST(TextGrid, phoneTierChosenByNameTokenAndLabelsAndNamed) {
	// MFA with two speakers: "SPEAKER - words/phones"; the first speaker's phones, the other named.
	const std::string mfa = textGrid({{"KY25A - words", {{0, 0.5, "yeah"}, {0.5, 1, "<unk>"}}},
	                                  {"KY25A - phones", {{0, 0.2, "Y"}, {0.2, 0.5, "AE1"}, {0.5, 0.8, "spn"}, {0.8, 1, "{LG}"}}},
	                                  {"IVR - words", {{0, 1, "well"}}},
	                                  {"IVR - phones", {{0, 0.4, "W"}, {0.4, 0.8, "EH1"}, {0.8, 1, "L"}}}});
	Transcript t = parseTranscript(mfa, "multi.TextGrid", knowing("en-US"));
	EXPECT_EQ(t.tier, "KY25A - phones");
	EXPECT_EQ(t.level, LabelLevel::Phone);
	EXPECT_EQ(t.tierNote, "phones; also 'IVR - phones' (tier 4): choose with {{tier}}");
	// spn and the noise tags are pauses.
	EXPECT_EQ(phonesOf(phoneSegments(t, Language::get("en-US"))), (std::vector<std::string>{"j", "æ", "_", "_"}));
	for (const char* p : {"spn", "SPN", "<unk>", "<noise>", "{LG}", "{NS}", "sil", "sp", "", "_"}) EXPECT_TRUE(isPauseLabel(p)) << p;
	for (const char* p : {"{", "}", "a", "<", "sh"}) EXPECT_FALSE(isPauseLabel(p)) << p;
	// --tier: a name, the same ignoring case, or a number.
	EXPECT_EQ(parseTranscript(mfa, "m", tierNamed("ivr - PHONES")).tier, "IVR - phones");
	EXPECT_EQ(parseTranscript(mfa, "m", tierNamed("3")).tier, "IVR - words");
	// WebMAUS: MAU holds the phones; ORT-MAU and KAN-MAU are words.
	const std::string maus = textGrid({{"ORT-MAU", {{0, 0.5, "hallo"}, {0.5, 1, ""}}},
	                                   {"KAN-MAU", {{0, 0.5, "halo:"}, {0.5, 1, ""}}},
	                                   {"MAU", {{0, 0.1, "<p:>"}, {0.1, 0.2, "h"}, {0.2, 0.3, "a"}, {0.3, 0.4, "l"}, {0.4, 0.5, "o:"}, {0.5, 1, "<p:>"}}}});
	EXPECT_EQ(parseTranscript(maus, "m.TextGrid").tier, "MAU");
	EXPECT_EQ(parseTranscript(maus, "m.TextGrid", levelled(LabelLevel::Word)).tier, "ORT-MAU");
	// EMU: a "Word" tier of C/F (content/function) labels, "Text", then "Phoneme" and "Phonetic".
	const std::string emu = textGrid({{"Word", {{0, 0.5, "C"}, {0.5, 1, "F"}}},
	                                  {"Text", {{0, 0.5, "amongst"}, {0.5, 1, "her"}}},
	                                  {"Phoneme", {{0, 0.2, "V"}, {0.2, 0.5, "m"}, {0.5, 1, "@:"}}},
	                                  {"Phonetic", {{0, 0.2, "V"}, {0.2, 0.4, "m"}, {0.4, 0.5, "H"}, {0.5, 1, "@:"}}}});
	Transcript e = parseTranscript(emu, "e.TextGrid", knowing("en-US"));
	EXPECT_EQ(e.tier, "Phoneme");
	EXPECT_EQ(e.tierNote, "phones; also 'Phonetic' (tier 4): choose with {{tier}}");
	EXPECT_EQ(parseTranscript(emu, "e.TextGrid", levelled(LabelLevel::Word)).tier, "Text");  // words, not C/F
	// No name says it: the tier whose labels are known phones wins over a words tier before it.
	const std::string unnamed = textGrid({{"a", {{0, 0.5, "hello"}, {0.5, 1, "world"}}}, {"b", {{0, 0.3, "h"}, {0.3, 0.6, "@"}, {0.6, 1, "l"}}}});
	EXPECT_EQ(parseTranscript(unnamed, "u.TextGrid", knowing("en-US")).tier, "b");
	// Tiers with no interval at all.
	EXPECT_NE(errorOf([] { parseTranscript(textGrid({{"words", {}}}), "empty.TextGrid"); }).find("no tier holds an interval (tiers: 'words' (intervals))"),
	          std::string::npos);
}

TEST(TextGrid, wordAndUtteranceTiersAreWordLevel) {
	const Language& en = Language::get("en-US");
	// One utterance per interval (MFA's input, LibriSpeech): words, phonemised by espeak-ng.
	const std::string utt = textGrid({{"61", {{0, 0.1, ""}, {0.1, 0.9, "HELLO THERE"}, {0.9, 1, ""}}}});
	Transcript u = parseTranscript(utt, "utt.TextGrid", knowing("en-US"));
	EXPECT_EQ(u.level, LabelLevel::Word);
	EXPECT_EQ(u.tierNote, "words");
	const auto p = phonesOf(phoneSegments(u, en));
	ASSERT_GE(p.size(), 6u);
	EXPECT_EQ(std::vector<std::string>(p.begin(), p.begin() + 3), (std::vector<std::string>{"_", "h", "ə"}));
	EXPECT_EQ(p.back(), "_");
	// A words tier alone is word level; beside a phones tier, the phones tier wins.
	EXPECT_EQ(parseTranscript(textGrid({{"words", {{0, 0.5, "yes"}, {0.5, 1, "no"}}}}), "w.TextGrid", knowing("en-US")).level, LabelLevel::Word);
	const std::string both = textGrid({{"words", {{0, 1, "hi"}}}, {"phones", {{0, 0.5, "h"}, {0.5, 1, "aI"}}}});
	EXPECT_EQ(parseTranscript(both, "b.TextGrid", knowing("en-US")).tier, "phones");
	EXPECT_EQ(parseTranscript(both, "b.TextGrid", levelled(LabelLevel::Word)).tier, "words");
	// Unsure: named like words, labelled like phones: the error asks for --level.
	EXPECT_EQ(errorOf([] { parseTranscript(textGrid({{"Word", {{0, 0.5, "C"}, {0.5, 1, "F"}}}}), "cf.TextGrid"); }),
	          "cf.TextGrid:10: tier 'Word' holds words, not phones, by its name, but its labels ('C' 'F') look like phones; use {{level}} words, or {{level}} phones");
	// Unsure: neither name nor labels tell (half known phones): read as phones, and a word among them says so.
	Transcript g = parseTranscript(textGrid({{"talker", {{0, 0.25, "a"}, {0.25, 0.5, "blah"}, {0.5, 0.75, "e"}, {0.75, 1, "qq"}}}}), "g.TextGrid", knowing("en-US"));
	EXPECT_TRUE(g.levelGuessed);
	EXPECT_EQ(errorOf([&] { phoneSegments(g, en); }), "g.TextGrid:20: tier 'talker' holds words, not phones; use {{level}} words ('blah' is no en-US phone)");
	// --level phones on an utterance tier: the same advice, the label abbreviated.
	Transcript forced = parseTranscript(utt, "utt.TextGrid", levelled(LabelLevel::Phone));
	EXPECT_EQ(errorOf([&] { phoneSegments(forced, en); }), "utt.TextGrid:20: tier '61' holds words, not phones; use {{level}} words ('HELLO THERE' is no en-US phone)");
}

TEST(LabelFiles, xlabelAndHtsFullContextLabels) {
	// festvox/EHMM xlabel: a header ending in "#", then end times in seconds, a colour, the label, "; score".
	const std::string xl = "seperator ;\nnfields 1\n#\n\t0.934\t26\tsil ; score -30527.558594 ;\n\t1.044\t26\too ; score -3862.8 ;\n"
	                       "\t1.144\t26\tth ; score -3755.7 ;\n\t1.256\t26\tr ; score -467.0 ;\n\t1.256\t26\tsp ; score -0.18 ;\n";
	Transcript x = parseTranscript(xl, "arctic_a0001.lab");
	EXPECT_EQ(x.format, "xlabel");
	EXPECT_EQ(labels(x), (std::vector<std::string>{"sil", "oo", "th", "r"}));  // the zero-length sp dropped
	EXPECT_EQ(x.intervals[0].start, Ticks(0));
	EXPECT_EQ(x.intervals[1].start, ms(934));
	EXPECT_EQ(x.intervals[1].end, ms(1044));
	EXPECT_EQ(errorOf([] { parseTranscript("nfields 1\n#\n0.5 26 a\n0.4 26 b\n", "x.lab"); }),
	          "x.lab:4: end time 0.4 is before the previous one (xlabel lines hold end times, in order)");
	// HTS full-context labels with HTK times: the centre phone.
	const std::string hts =
	    "0 1300000 x^x-sil+hh=iy@x_x/A:0_0_0/B:x-x-x@x-x&x-x#x-x$x-x!x-x;x-x|x/C:1+1+2/D:0_0/E:x+x@x+x&x+x#x+x/F:content_1/G:0_0/H:x=x@1=2|0/I:4=3/J:13+9-2\n"
	    "1300000 2050000 x^sil-hh+iy=t@1_2/A:0_0_0/B:1-1-2@1-1&1-4#1-3$1-4!0-1;0-1|iy/C:1+1+4/D:0_0/E:content+1@1+3&1+2#0+1/F:content_1/G:0_0/H:4=3@1=2|L-H%/I:9=6/J:13+9-2\n"
	    "2050000 2700000 sil^hh-iy+t=er@2_1/A:0_0_0/B:1-1-2@1-1&1-4#1-3$1-4!0-1;0-1|iy/C:1+1+4/D:0_0/E:content+1@1+3&1+2#0+1/F:content_1/G:0_0/H:4=3@1=2|L-H%/I:9=6/J:13+9-2\n";
	Transcript h = parseTranscript(hts, "arctic_a0009.lab");
	EXPECT_EQ(h.format, "htk");
	EXPECT_EQ(labels(h), (std::vector<std::string>{"sil", "hh", "iy"}));
	EXPECT_EQ(h.intervals[2].end, ms(270));
	// Lines without times (HTS input before alignment): which line, what is missing, the label abbreviated.
	const std::string untimed = "0 6800000 y^y-#+p=e/M2:y_y/S1:0_@0-y_@y+0_@0/S2:y_y/S3:y_y/S4:y_y/S5:y_y/S6:y/W1:y_#y-y_#y+y_#y/W2:y_y/W3:y_y/W4:y_1/W5:0/P1:y_!y-y_!y+16_!9/P2:y_y/U:16_$9_&1\n"
	                            " #^p-e+s=k/M2:2_2/S1:0_@0-0_@3+1_@2/S2:1_3/S3:1_16/S4:0_9/S5:0_1/S6:e/W1:y_#y-content_#3+content_#1/W2:1_9/W3:1_9/W4:0_1/W5:0/P1:y_!y-16_!9+1_!1/P2:1_1/U:16_$9_&1\n";
	const std::string err = errorOf([&] { parseTranscript(untimed, "m001_0001.lab"); });
	EXPECT_EQ(err, "m001_0001.lab:2: no times: the line holds only the label '#^p-e+s=k…' (an HTS full-context label, centre phone 'e'); every line needs 'start end label'");
	EXPECT_EQ(errorOf([] { parseTranscript("0 100000 a\n100000\n", "t.lab"); }), "t.lab:2: only a time (100000): expected 'start end label'");
}

TEST(Encoding, utf16WithoutByteOrderMarkAndNulBytes) {
	const std::string tsv = "0\t0.1\tk\n0.1\t0.2\tɐ\n";
	auto utf16 = [&](bool le) {  // the text above (ASCII and U+0250) as UTF-16, no BOM
		std::string out;
		for (const auto& cp : std::vector<unsigned>{'0', '\t', '0', '.', '1', '\t', 'k', '\n', '0', '.', '1', '\t', '0', '.', '2', '\t', 0x250, '\n'}) {
			const char hi = char(cp >> 8), lo = char(cp & 0xFF);
			out += le ? std::string{lo, hi} : std::string{hi, lo};
		}
		return out;
	};
	EXPECT_EQ(labels(parseTranscript(utf16(true), "le.tsv")), (std::vector<std::string>{"k", "ɐ"}));
	EXPECT_EQ(labels(parseTranscript(utf16(false), "be.tsv")), (std::vector<std::string>{"k", "ɐ"}));
	EXPECT_EQ(labels(parseTranscript(tsv, "utf8.tsv")), (std::vector<std::string>{"k", "ɐ"}));
	// Other bytes with NULs are no transcript: said without echoing them.
	const std::string err = errorOf([] { parseTranscript(std::string("0\t0.1\ta\x00\x01\x02\n", 11), "bin.tsv"); });
	EXPECT_EQ(err, "bin.tsv: NUL bytes (the first at byte 7): not a text transcript (UTF-8 and UTF-16 are read)");
}

TEST(UnknownPhones, nearestIsTheClosestSpellingNeverAPrefixOrAPause) {
	const Language& en = Language::get("en-US");
	const Language& pt = Language::get("pt-BR");
	using V = std::vector<std::string>;
	EXPECT_EQ(en.nearest("aː"), (V{"a"}));    // length mark
	EXPECT_EQ(en.nearest("tʰ"), (V{"t"}));    // modifier letter
	EXPECT_EQ(en.nearest("t͡ʃ"), (V{"tʃ"}));  // tie bar
	EXPECT_EQ(pt.nearest("ɐ̃ː"), (V{"ɐ̃"}));   // the nasal vowel kept
	EXPECT_EQ(pt.nearest("ɐ̰"), (V{"ɐ"}));     // creaky diacritic removed
	EXPECT_EQ(Language::get("de").nearest("ɗ"), (V{"d"}));  // hook (espeak-ng's Vietnamese đ)
	EXPECT_EQ(en.nearest("_x", Notation::Ipa), (V{"x"}));  // one edit (LaBB-CAT's _ prefix), never the pause "_"
	// A sentence is no phone (it used to become its first letter); nor is a long or one-letter label.
	EXPECT_EQ(en.nearest("this is the acoustic corpus"), std::nullopt);
	EXPECT_EQ(en.nearest(std::string(5000, 'a')), std::nullopt);
	EXPECT_EQ(en.nearest("œ"), std::nullopt);
	// Equally near spellings that disagree: none, and the message names them.
	std::string near;
	EXPECT_EQ(en.nearest("PT", Notation::Arpabet, &near), std::nullopt);
	EXPECT_NE(near.find("'P' [p]"), std::string::npos) << near;
	EXPECT_NE(near.find("'T' [t]"), std::string::npos) << near;
	// phoneSegments: --unknown nearest without a near spelling is an error naming the label, not silence.
	Transcript t = parseTranscript("0\t0.1\ta\n0.1\t0.2\tblah\n", "n.tsv");
	EXPECT_EQ(errorOf([&] { phoneSegments(t, en, UnknownPhone::Nearest); }),
	          "n.tsv:2: unknown en-US phone 'blah': no known spelling is near it; correct the label, or check {{lang}} and {{notation}}");
	// Silence is suggested only for a label that cannot be a sound (issue 29 item 4): a vowel is never silenced.
	Transcript m = parseTranscript("0\t0.1\ta\n0.1\t0.2\t+++\n", "m.tsv");
	EXPECT_EQ(errorOf([&] { phoneSegments(m, en, UnknownPhone::Nearest); }),
	          "m.tsv:2: unknown en-US phone '+++': no known spelling is near it; use {{unknown}} silence if it marks no speech, or correct the label");
	EXPECT_EQ(errorOf([&] { phoneSegments(m, en); }).find("{{unknown}}=nearest|silence)") != std::string::npos, true);
	// An EMU/MRPA file: H# is its silence; 'ai' is a sound: no suggestion to silence it.
	Transcript emu = parseTranscript("0\t0.2\tH#\n0.2\t0.4\tai\n", "emu.tsv");
	const std::string e = errorOf([&] { phoneSegments(emu, en); });
	EXPECT_NE(e.find("emu.tsv:2: unknown en-US phone 'ai'"), std::string::npos) << e;
	EXPECT_EQ(e.find("silence"), std::string::npos) << e;
	// aeneas fragment ids are not phones with a stress digit (issue 29 item 2): f000001 is unknown, not f.
	Transcript ids = parseTranscript("0.000\t0.080\ta\n0.080\t0.160\tf000002\n", "ids.tsv");
	EXPECT_NE(errorOf([&] { phoneSegments(ids, en); }).find("unknown en-US phone 'f000002'"), std::string::npos);
	EXPECT_NE(errorOf([] { parseTranscript("0.000\t2.680\tf000001\n2.680\t5.880\tf000002\n", "sync.tsv"); }).find("sync.tsv:1: the labels are aeneas fragment ids"),
	          std::string::npos);
	EXPECT_EQ(en.normalize("AY1", Notation::Arpabet).value_or(std::vector<std::string>{}), (std::vector<std::string>{"a", "j"}));
}

TEST(Transcript, everyReaderBoundsItsTimesToADay) {
	// 1e20 s once overflowed the tick type (negative times, exit 0) in the readers without a limit (issue 15 item 4).
	const std::string tg = "File type = \"ooTextFile\"\nObject class = \"TextGrid\"\n\nxmin = 0\nxmax = 1e20\ntiers? <exists>\nsize = 1\nitem []:\n"
	                       "    item [1]:\n        class = \"IntervalTier\"\n        name = \"phones\"\n        xmin = 0\n        xmax = 1e20\n"
	                       "        intervals: size = 1\n        intervals [1]:\n            xmin = 0\n            xmax = 1e20\n            text = \"a\"\n";
	EXPECT_NE(errorOf([&] { parseTranscript(tg, "big.TextGrid"); }).find("big.TextGrid:16: interval xmax is absurd"), std::string::npos);
	EXPECT_NE(errorOf([] { parseTranscript("{\"time\":1e20,\"type\":\"word\",\"value\":\"hi\"}\n", "big.marks"); }).find("big.marks:1: mark time is absurd"),
	          std::string::npos);
	EXPECT_NE(errorOf([] { parseTranscript("{\"mouthCues\": [{\"start\": 0, \"end\": 1e20, \"value\": \"A\"}]}", "big.json"); }).find("mouth cue 1 end is absurd"),
	          std::string::npos);
	EXPECT_NE(errorOf([] { parseTranscript("{\"mouthCues\": [{\"start\": 0, \"end\": 90000, \"value\": \"A\"}]}", "day.json"); }).find("at most 86400 s"),
	          std::string::npos);
}
