// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <functional>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/labels.h"
#include "phonetics/language.h"
#include "phonetics/writers.h"

#include "test_support.h"

using namespace talkhead;

namespace {
const std::string kDir = std::string(TALKHEAD_TEST_DATA_DIR) + "/transcripts/";

std::vector<std::string> cdvs(const std::vector<PhoneSegment>& p) {
	std::vector<std::string> c;
	for (const auto& s : p) c.push_back(s.cdv.label());
	return c;
}

// CDVs of a phone string (one phone per space-separated token), 100 ms each.
std::vector<std::string> cdvsOf(const std::string& phones, const std::string& lang = "pt-BR") {
	Transcript t;
	t.path = "test";
	long k = 0;
	std::string cur;
	for (std::size_t i = 0; i <= phones.size(); ++i) {
		if (i == phones.size() || phones[i] == ' ') {
			if (!cur.empty()) t.intervals.push_back({Ticks(k * 70560000), Ticks((k + 1) * 70560000), cur == "_" ? "" : cur, k + 1}), ++k;
			cur.clear();
		} else {
			cur += phones[i];
		}
	}
	return cdvs(phoneSegments(t, Language::get(lang)));
}

using test::errorOf;

const std::vector<std::string> kWorkedExample = {"sil", "k1", "i1", "t1", "o", "t1", "i1", "s1", "e", "l2", "e", "t1", "ɪ", "sil"};
}  // namespace

TEST(Cdv, thesisWorkedExampleFromEveryFormat) {
	// Costa 2015 Table 5.3: "Que notícia excelente!" = k i n o t i s e l ẽ t ɪ
	// → <k1> <i1> <t1> <o> <t1> <i1> <s1> <e> <l2> <e> <t1> <ɪ>.
	const Language& pt = Language::get("pt-BR");
	for (const char* f : {"que_noticia.TextGrid", "que_noticia_short.TextGrid", "que_noticia_utf16.TextGrid", "que_noticia.pho", "que_noticia.lab"})
		EXPECT_EQ(cdvs(phoneSegments(readTranscript(kDir + f), pt)), kWorkedExample) << f;
}

TEST(Cdv, thesisTable34Examples) {
	// Costa 2015 Table 3.4 ("Fear" text): the consonant in the middle of each snippet.
	EXPECT_EQ(cdvsOf("i p a")[1], "p1");    // conseguirei pagar
	EXPECT_EQ(cdvsOf("o p i")[1], "p2");    // o pior
	EXPECT_EQ(cdvsOf("ɐ f a")[1], "f1");    // minha família
	EXPECT_EQ(cdvsOf("u f i")[1], "f2");    // contrato ficarei
	EXPECT_EQ(cdvsOf("t u")[0], "t1");      // Tulha
	EXPECT_EQ(cdvsOf("a t a")[1], "t2");    // batalhei
	EXPECT_EQ(cdvsOf("a s a")[1], "s1");    // passado
	EXPECT_EQ(cdvsOf("ɪ s u")[1], "s2");    // simplesmente sumirão
	EXPECT_EQ(cdvsOf("u l i")[1], "l1");    // Juliano
	EXPECT_EQ(cdvsOf("a l i")[1], "l2");    // realizei
	EXPECT_EQ(cdvsOf("l u")[0], "l3");      // Lucas
	EXPECT_EQ(cdvsOf("i l ʊ")[1], "l4");    // Lilo
	EXPECT_EQ(cdvsOf("a ʒ u")[1], "ʃ1");    // ajuda
	EXPECT_EQ(cdvsOf("ʊ ʒ u")[1], "ʃ2");    // o Juliano
	EXPECT_EQ(cdvsOf("i ʎ ɐ")[1], "ʎ1");    // família
	EXPECT_EQ(cdvsOf("u ʎ ɐ")[1], "ʎ2");    // Tulha
	EXPECT_EQ(cdvsOf("i ɲ ʊ")[1], "ʎ3");    // sozinho
	EXPECT_EQ(cdvsOf("u k ɐ")[1], "k1");    // Lucas
	EXPECT_EQ(cdvsOf("ɐ k a")[1], "k2");    // linda casa
	EXPECT_EQ(cdvsOf("o k u")[1], "k3");    // preocupado
	EXPECT_EQ(cdvsOf("a ʁ a")[1], "r1");    // arrasado
	EXPECT_EQ(cdvsOf("a ʁ ʊ")[1], "r2");    // carro
	EXPECT_EQ(cdvsOf("d i z")[1], "i1");    // dizem: <i2> in Table 3.4, <i1> by our rule (decisions.md)
	EXPECT_EQ(cdvsOf("t i d")[1], "i2");    // [i] between two [t d n]
	EXPECT_EQ(cdvsOf("ʃ i ʒ")[1], "i2");    // … or two [ʃ ʒ]
}

TEST(Cdv, clustersCodasAndNotations) {
	// [pr]: the cluster liquid is stepped over to reach the vowel.
	EXPECT_EQ(cdvsOf("p ɾ u")[0], "p2");
	EXPECT_EQ(cdvsOf("p ɾ a")[0], "p1");
	// X-SAMPA / Praat spellings normalise to the same phones.
	EXPECT_EQ(cdvsOf("E"), (std::vector<std::string>{"ɛ"}));
	EXPECT_EQ(cdvsOf("\\ep"), (std::vector<std::string>{"ɛ"}));
	EXPECT_EQ(cdvsOf("S u"), cdvsOf("ʃ u"));
	EXPECT_EQ(cdvsOf("_ sil"), (std::vector<std::string>{"sil", "sil"}));
}

TEST(Cdv, englishMapsOntoTheSameClasses) {
	const Language& en = Language::get("en-US");
	std::vector<PhoneSegment> p = phoneSegments(readTranscript(kDir + "hello_arpabet.lab"), en);
	ASSERT_EQ(p.size(), 11u);  // OW1 is a diphthong: o + ʊ
	for (const auto& s : p) EXPECT_TRUE(canonicalViseme(s.cdv.label()).has_value()) << s.label << " → " << s.cdv.label();
	EXPECT_EQ(p.front().cdv, "sil");
	EXPECT_EQ(p[3].phone, "l");
	EXPECT_EQ(p[3].cdv.label().substr(0, 1), "l");
	EXPECT_EQ(p[4].phone, "o");
	EXPECT_EQ(p[9].cdv.label().substr(0, 1), "t");  // D: alveolar
	// ARPAbet diphthongs expand into two phones, each half the interval.
	Transcript t;
	t.path = "d";
	t.intervals = {{Ticks(0), Ticks(70560000), "AY1", 1}};
	auto d = phoneSegments(t, en);
	ASSERT_EQ(d.size(), 2u);
	EXPECT_EQ(d[0].end, Ticks(35280000));
}

TEST(Cdv, moreLanguagesMapOntoTheSameClasses) {
	// Issue 12: one word per language, in the phones espeak-ng writes (phonetics/<tag>/inventory.tsv says why).
	using V = std::vector<std::string>;
	EXPECT_EQ(cdvsOf("_ b ɔ̃ ʒ u ʁ _", "fr"), (V{"sil", "p2", "o", "ʃ2", "u", "r2", "sil"}));  // bonjour
	EXPECT_EQ(cdvsOf("t y", "fr"), (V{"t1", "u"}));           // tu: rounded front y -> <u>
	EXPECT_EQ(cdvsOf("t ʁ ɛ", "fr")[0], "t2");                // très: the cluster steps over ʁ (liquid) to ɛ
	EXPECT_EQ(cdvsOf("k a ð a", "es"), (V{"k2", "a", "t2", "a"}));  // cada: ð in the t group
	EXPECT_EQ(cdvsOf("l o β o", "es")[2], "p2");              // lobo: β in the p group
	EXPECT_EQ(cdvsOf("b uː x", "de"), (V{"p2", "u", "k3"}));  // Buch: x in the k group
	EXPECT_EQ(cdvsOf("ɪ ç", "de"), (V{"ɪ", "k1"}));           // ich
	EXPECT_EQ(cdvsOf("f i ʎ a", "it"), (V{"f1", "i1", "ʎ1", "a"}));  // figlia
	// espeak-ng event names that are not IPA.
	EXPECT_EQ(Language::get("de").normalize("??"), (V{"ʊ", "ɐ"}));
	EXPECT_EQ(Language::get("it").normalize("ss"), (V{"s"}));
	EXPECT_EQ(Language::get("fr").normalize("ə-"), (V{"ə"}));
	// Tags: case-insensitive; a region the tables do not split reads as the language.
	EXPECT_EQ(Language::get("FR").tag(), "fr");
	EXPECT_EQ(Language::get("de-AT").tag(), "de");
	EXPECT_THROW(Language::get("pt-PT-x"), Error);
	// The generic table knows every phone of every table (scripts/make-generic-phonetics.py was re-run), and a
	// language mapped through it is then what get() returns.
	EXPECT_THROW(Language::get("nl"), Error);
	const Language& nl = Language::generic("nl");
	EXPECT_EQ(&Language::get("NL"), &nl);
	EXPECT_EQ(nl.tag(), "nl");
	for (const auto& tag : Language::available())
		for (const auto& p : splitWhitespace(Language::get(tag).inventoryList())) EXPECT_TRUE(nl.normalize(p).has_value()) << tag << " " << p;
}

TEST(Cdv, unknownPhonesAreReportedOrMapped) {
	Transcript t;
	t.path = "x.TextGrid";
	t.intervals = {{Ticks(0), Ticks(100), "a", 3}, {Ticks(100), Ticks(200), "tʰ", 4}, {Ticks(200), Ticks(300), "a", 5}};
	const Language& pt = Language::get("pt-BR");
	const std::string e = errorOf([&] { phoneSegments(t, pt); });
	EXPECT_EQ(e.rfind("x.TextGrid:4: unknown pt-BR phone 'tʰ' (known: ", 0), 0u) << e;
	EXPECT_NE(e.find("check {{lang}} and {{notation}}, or use {{unknown}} nearest"), std::string::npos);
	auto near = phoneSegments(t, pt, UnknownPhone::Nearest);
	EXPECT_EQ(near[1].phone, "t");
	auto sil = phoneSegments(t, pt, UnknownPhone::Silence);
	EXPECT_EQ(sil[1].cdv, "sil");
	EXPECT_THROW(Language::get("xx-YY"), Error);
}

TEST(Cdv, visemeLevelInputMapsStraight) {
	const Language& pt = Language::get("pt-BR");
	auto polly = phoneSegments(readTranscript(kDir + "polly_visemes.marks"), pt);
	EXPECT_EQ(polly.front().cdv, "k1");
	EXPECT_EQ(polly.back().cdv, "sil");
	auto rh = phoneSegments(readTranscript(kDir + "rhubarb.tsv"), pt);
	EXPECT_EQ(rh[0].cdv, "sil");  // X
	EXPECT_EQ(rh[3].cdv, "p1");   // A: closed lips
}

TEST(Keyposes, oneAtEachPhoneMidpointWithMergesAndDrops) {
	const Ticks frame(kTicksPerSecond / 30);
	auto ms = [](long v) { return Ticks(v * (kTicksPerSecond / 1000)); };
	std::vector<PhoneSegment> p = {{ms(0), ms(100), "", "_", "sil", 1},       {ms(100), ms(200), "a", "a", "a", 2},
	                               {ms(200), ms(300), "a", "a", "a", 3},      {ms(300), ms(340), "p", "p", "p1", 4},
	                               {ms(340), ms(341), "i", "i", "i1", 5},     {ms(341), ms(441), "u", "u", "u", 6}};
	auto k = keyposes(p, frame);
	ASSERT_EQ(k.size(), 4u);
	EXPECT_EQ(k[0].time, ms(50));   // Eq. 5.1: (t_{i−1} + t_i) / 2, exact in flicks
	EXPECT_EQ(k[1].cdv, "a");       // two [a]s: one keypose at the run's midpoint
	EXPECT_EQ(k[1].time, ms(200));
	EXPECT_EQ(k[2].cdv, "p1");      // the 1 ms [i] (keypose at 340.5 ms) falls within a frame of [p]'s (320 ms): dropped
	EXPECT_EQ(k[3].cdv, "u");
	EXPECT_EQ(k[3].time, ms(391));
	EXPECT_EQ(k[1].first, 1u);
	EXPECT_EQ(k[1].last, 2u);
}

TEST(Keyposes, aBilabialShorterThanItsNeighbourIsKeptWhenAsked) {
	// pwij3p at 25 fps (D90): a 30-ms /p/ then a 34-ms /l/ — their keyposes 32 ms apart, under a frame.
	const Ticks frame(kTicksPerSecond / 25);
	auto ms = [](long v) { return Ticks(v * (kTicksPerSecond / 1000)); };
	std::vector<PhoneSegment> p = {{ms(0), ms(300), "", "_", "sil", 1},   {ms(300), ms(330), "p", "p", "p1", 2},
	                               {ms(330), ms(364), "l", "l", "l2", 3}, {ms(364), ms(464), "e", "e", "e", 4},
	                               {ms(464), ms(494), "m", "m", "p1", 5}, {ms(494), ms(600), "", "_", "sil", 6}};
	auto cdvs = [](const std::vector<Keypose>& k) {
		std::string s;
		for (const Keypose& x : k) s += x.cdv.label() + " ";
		return s;
	};
	EXPECT_EQ(cdvs(keyposes(p, frame)), "sil l2 e p1 sil ");  // the thesis's rule: the longer phone stays
	EXPECT_EQ(cdvs(keyposes(p, frame, PauseStyle::Natural, true)), "sil p1 e p1 sil ");
	// Where nothing conflicts, the same keyposes either way.
	const Ticks fine(kTicksPerSecond / 100);
	EXPECT_EQ(cdvs(keyposes(p, fine, PauseStyle::Natural, true)), cdvs(keyposes(p, fine)));
}

TEST(Keyposes, naturalPausesRestSoonAndBreatheInBeforeSpeech) {
	const Ticks frame(kTicksPerSecond / 25);
	auto ms = [](long v) { return Ticks(v * (kTicksPerSecond / 1000)); };
	// 600 ms leading pause, "a", 300 ms pause (short), "a" → "p", 1 s pause, "u", 800 ms trailing pause.
	std::vector<PhoneSegment> p = {{ms(0), ms(600), "", "_", "sil", 1},      {ms(600), ms(700), "a", "a", "a", 2},
	                               {ms(700), ms(1000), "", "_", "sil", 3},   {ms(1000), ms(1100), "a", "a", "a", 4},
	                               {ms(1100), ms(1200), "p", "p", "p1", 5},  {ms(1200), ms(2200), "", "_", "sil", 6},
	                               {ms(2200), ms(2300), "u", "u", "u", 7},   {ms(2300), ms(3100), "", "_", "sil", 8}};
	auto thesis = keyposes(p, frame, PauseStyle::Thesis);
	ASSERT_EQ(thesis.size(), 8u);  // one per phone, pauses at their midpoints
	EXPECT_EQ(thesis[0].time, ms(300));
	EXPECT_EQ(thesis[5].time, ms(1700));
	EXPECT_EQ(thesis[7].time, ms(2700));

	auto k = keyposes(p, frame);  // natural (D34)
	std::vector<std::pair<long, std::string>> got;
	for (const auto& x : k) got.push_back({long(x.time / ms(1)), x.cdv.label() + (x.breath ? "*" : "")});
	const std::vector<std::pair<long, std::string>> want = {
	    {150, "sil"}, {300, "ɐ*"},                // leading: rest until 450 ms before speech, in-breath 300 ms before
	    {650, "a"},   {850, "sil"},  {1050, "a"},  // a 300-ms pause is short: one keypose at its midpoint (thesis)
	    {1150, "p1"}, {1320, "sil"}, {1750, "sil"}, {1900, "ɐ*"},  // rest 120 ms after speech, held, then breath
	    {2250, "u"},  {2420, "sil"}};             // trailing: rest 120 ms after the last phone, held to the end
	EXPECT_EQ(got, want);
	// Each keypose carries its phone context as corpus rows write it (two before, own, two after).
	const std::array<std::string, 5> pContext{"_", "a", "p", "_", "u"};
	EXPECT_EQ(k[5].context, pContext);
	// The per-phone keypose column names a pause's rest keypose, never the breath.
	const std::string tsv = formatVisemes(p, k, "tsv", "pt-BR", "x");
	EXPECT_NE(tsv.find("0.000000\t0.600000\t_\tsil\t0.150000\n"), std::string::npos) << tsv;
	EXPECT_NE(tsv.find("1.200000\t2.200000\t_\tsil\t1.320000\n"), std::string::npos) << tsv;
	EXPECT_EQ(parsePauseStyle("thesis"), PauseStyle::Thesis);
	EXPECT_EQ(parsePauseStyle("Natural"), std::nullopt);
	// Still (D62, D70): before the first words one held mouth (#) from the start until kStillLead (150 ms)
	// before the first phone, no in-breath; a later pause's breath rises over up to 300 ms (twice
	// Natural's) where the pause allows; the rest as Natural.
	auto still = keyposes(p, frame, PauseStyle::Still);
	got.clear();
	for (const auto& x : still) got.push_back({long(x.time / ms(1)), x.cdv.label() + (x.breath ? "*" : "") + (x.hold ? "#" : "")});
	const std::vector<std::pair<long, std::string>> wantStill = {
	    {0, "sil#"},   {450, "sil#"}, {650, "a"},    {850, "sil"},  {1050, "a"},  {1150, "p1"},
	    {1320, "sil"}, {1600, "sil"}, {1900, "ɐ*"}, {2250, "u"},  {2420, "sil"}};
	EXPECT_EQ(got, wantStill);
	EXPECT_EQ(parsePauseStyle("still"), PauseStyle::Still);
}

TEST(Writers, textGridRoundTripIsIdentical) {
	const Language& pt = Language::get("pt-BR");
	auto phones = phoneSegments(readTranscript(kDir + "que_noticia.TextGrid"), pt);
	auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	const std::string tg = formatVisemes(phones, keys, "textgrid", "pt-BR", "x");
	auto again = phoneSegments(parseTranscript(tg, "roundtrip.TextGrid"), pt);
	ASSERT_EQ(again.size(), phones.size());
	for (std::size_t i = 0; i < phones.size(); ++i) {
		EXPECT_EQ(again[i].phone, phones[i].phone);
		EXPECT_EQ(again[i].cdv, phones[i].cdv);
		EXPECT_EQ(again[i].start, phones[i].start);
		EXPECT_EQ(again[i].end, phones[i].end);
	}
	EXPECT_EQ(formatVisemes(again, keyposes(again, Ticks(kTicksPerSecond / 30)), "textgrid", "pt-BR", "x"), tg);
	// The CDV tier reads back as CDVs too.
	Transcript cdvTier = parseTranscript(tg, "roundtrip.TextGrid", {"", "cdv", ""});
	EXPECT_EQ(cdvTier.intervals[1].label, "k1");
	// Rhubarb cues: closed lips for [p b m] would be A; the first cue is the pause.
	const std::string rh = formatVisemes(phones, keys, "rhubarb-tsv", "pt-BR", "x");
	EXPECT_EQ(rh.substr(0, 7), "0.00\tX\n");
}

TEST(Espeak, gridWordsExpandToPhonesInsideEachWord) {
	const std::string path = std::string(TALKHEAD_SHARED_DATA) + "/grid/swwp2s.align";
	Transcript words;
	try {
		words = readTranscript(path);
	} catch (const Error&) {
		GTEST_SKIP() << "GRID data not found at " << path;
	}
	const Language& en = Language::get("en-US");
	auto phones = phoneSegments(words, en, UnknownPhone::Nearest);
	ASSERT_GT(phones.size(), 15u);
	for (const auto& w : words.intervals) {
		int inside = 0;
		for (const auto& p : phones) {
			if (p.line != w.line) continue;
			EXPECT_GE(p.start, w.start) << w.label;
			EXPECT_LE(p.end, w.end) << w.label;
			++inside;
		}
		EXPECT_GE(inside, 1) << w.label;
		if (w.label == "white") {
			EXPECT_GE(inside, 3);  // w aɪ t
		}
	}
	for (std::size_t i = 1; i < phones.size(); ++i) EXPECT_EQ(phones[i].start, phones[i - 1].end);
	EXPECT_EQ(phones.front().start, words.intervals.front().start);
	EXPECT_EQ(phones.back().end, words.intervals.back().end);
}

TEST(Cdv, aHundredSecondWordKeepsItsPhonesInOrder) {
	// A valid GRID file with one 100-s word: span × duration once overflowed 64 bits and the phone times
	// ran backwards and negative with exit 0 (issue 15 item 3).
	// The plausibility gate (issue 50) refuses such a file now; the word is stretched after reading.
	Transcript t = parseTranscript("0 25000 sil\n25000 35000 set\n35000 60000 sil\n", "long.align");
	ASSERT_EQ(t.intervals.size(), 3u);
	t.intervals[1].end = Ticks(2525000 * (kTicksPerSecond / 25000));
	t.intervals[2].start = t.intervals[1].end;
	t.intervals[2].end = Ticks(2550000 * (kTicksPerSecond / 25000));
	auto phones = phoneSegments(t, Language::get("en-US"));
	ASSERT_GE(phones.size(), 5u);
	for (std::size_t i = 0; i < phones.size(); ++i) {
		EXPECT_GE(phones[i].start, Ticks(0));
		EXPECT_GT(phones[i].end, phones[i].start) << i;
		if (i > 0) EXPECT_EQ(phones[i].start, phones[i - 1].end) << i;
	}
	EXPECT_EQ(phones.back().end, Ticks(102 * kTicksPerSecond));
}

TEST(Cdv, nearestIsBoundedForHugeLabels) {
	// --unknown nearest once searched every prefix of a label: a 40 000-character label took 32 s and a 600 KB
	// one never finished (issue 15 item 5). A label longer than 16 characters is near nothing: one clear error.
	Transcript t;
	t.path = "huge.tsv";
	t.intervals = {{Ticks(0), Ticks(kTicksPerSecond), std::string(40000, 'x'), 1}};
	const std::string e = errorOf([&] { phoneSegments(t, Language::get("pt-BR"), UnknownPhone::Nearest); });
	EXPECT_NE(e.find("huge.tsv:1: unknown pt-BR phone 'xxxx"), std::string::npos) << e.substr(0, 200);
	EXPECT_NE(e.find("no known spelling is near it"), std::string::npos);
	EXPECT_LT(e.size(), 400u);  // the label is abbreviated in the message
}

TEST(Cdv, aLabelIsTypedWhereItIsReadAndEveryOtherSpellingIsRefused) {
	EXPECT_EQ(Cdv::parse("ʃ1"), Cdv::parse("<sh1>"));  // its ASCII alias, with or without <>
	EXPECT_EQ(Cdv::parse(" p1 ").label(), "p1");
	EXPECT_EQ(Cdv::parse("sh1").ascii(), "sh1");
	EXPECT_TRUE(Cdv().isSilence());
	EXPECT_EQ(Cdv().label(), "sil");
	EXPECT_FALSE(Cdv("p1").isSilence());
	EXPECT_TRUE(Cdv("a").in({"a", "e"}));
	EXPECT_EQ(Cdv("e").info().kind, "vowel");
	EXPECT_FALSE(Cdv::find("p9"));
	EXPECT_NE(errorOf([] { Cdv::parse("p9"); }).find("unknown viseme 'p9' (known: "), std::string::npos);
	EXPECT_THROW(Cdv::of("sh1"), std::logic_error);  // in code, the canonical label only
	EXPECT_THROW(Cdv("P1"), std::logic_error);
	// Ordered as their labels, as the strings were.
	EXPECT_LT(Cdv("a"), Cdv("p1"));
	EXPECT_LT(Cdv("p1"), Cdv("sil"));
	EXPECT_EQ(Cdv::count(), visemeLabels().size());
	for (std::size_t i = 0; i < Cdv::count(); ++i) EXPECT_EQ(Cdv::at(i).index(), i);
}
