// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <filesystem>
#include "base/text.h"

#include <fstream>
#include <utility>
#include <vector>

#include "base/error.h"
#include "corpus/build.h"
#include "corpus/corpus.h"
#include "test_support.h"

using namespace talkhead;

namespace {
const std::string kData = TALKHEAD_TEST_DATA_DIR;

using test::errorOf;

std::string writeFile(const std::string& name, const std::string& text) {
	std::string p = test::tempDir("corpus") + "/" + name;
	std::ofstream(p, std::ios::binary) << text;
	return p;
}

std::string row(int points, const std::string& firstPoint = "(1;2)") {
	std::string r = "a.png,joy,k,i,n,o,t,<t1>,word";
	for (int k = 0; k < points; ++k) r += "," + (k == 0 ? firstPoint : std::string("(3.5;4)"));
	return r;
}
}  // namespace

TEST(ChUnicampCsv, readsRowsExactly) {
	Corpus c = readChUnicampCsv(kData + "/corpus/mini.csv");
	EXPECT_EQ(c.schemeName, "ch-unicamp-56");
	ASSERT_EQ(c.entries.size(), 2u);
	const CorpusEntry& a = c.entries[0];
	EXPECT_EQ(a.imagePath, kData + "/corpus/img_0001.png");
	EXPECT_EQ(a.emotionLabel(), "joy");
	EXPECT_EQ(a.context[0], "\\ep");
	EXPECT_EQ(a.context[2], "i");
	EXPECT_EQ(a.cdv, Cdv("i1"));  // written <i1>: labels come out canonical (D36)
	EXPECT_EQ(a.word, "que");
	ASSERT_EQ(a.points.rows(), 56);
	EXPECT_DOUBLE_EQ(a.points(0, 0), 100.0);
	EXPECT_DOUBLE_EQ(a.points(55, 0), 100 + 55 * 3.5);
	EXPECT_DOUBLE_EQ(a.points(55, 1), 200 + 55 * 1.25);
	EXPECT_EQ(c.entries[1].cdv, Cdv("o"));
	EXPECT_EQ(c.entries[1].word, "notícia, não");
	EXPECT_DOUBLE_EQ(c.entries[1].points(0, 1), 202.0);
	EXPECT_EQ(c.entries[1].source, kData + "/corpus/mini.csv:2");
}

TEST(ChUnicampCsv, malformedRowsNameFileAndLine) {
	std::string p = writeFile("bad1.csv", row(56) + "\n" + row(55) + "\n");
	EXPECT_EQ(errorOf([&] { readChUnicampCsv(p); }),
	          p + ":2: expected 65 columns (image, emotion, 5 phones, CDV, word, 56 points), found 64");
	p = writeFile("bad2.csv", "\n" + row(56, "(1,2)") + "\n");
	EXPECT_NE(errorOf([&] { readChUnicampCsv(p); }).find(p + ":2: "), std::string::npos);
	p = writeFile("bad3.csv", row(56, "(x;2)"));
	EXPECT_EQ(errorOf([&] { readChUnicampCsv(p); }), p + ":1: column 10: expected a point '(x;y)', found '(x;2)'");
	p = writeFile("bad4.csv", row(56, "(nan;2)"));
	EXPECT_NE(errorOf([&] { readChUnicampCsv(p); }).find("column 10"), std::string::npos);
	p = writeFile("empty.csv", "\n\n");
	EXPECT_EQ(errorOf([&] { readChUnicampCsv(p); }), p + ": the corpus file has no rows");
	EXPECT_NE(errorOf([&] { readChUnicampCsv("/nonexistent/x.csv"); }).find("/nonexistent/x.csv: cannot read file"), std::string::npos);
}

namespace {
// The same rows with the labels spelled three ways: as the thesis's CSV writes them (<k1>), canonical, and
// through the aliases of phonetics/emotions.tsv and visemes.tsv (case-insensitive emotions, case-sensitive
// ASCII visemes: E is ɛ, e is e).
std::string labelledCorpus(const std::string& name, const std::vector<std::pair<std::string, std::string>>& labels) {
	std::string text = "# " + name + "\n";
	for (std::size_t i = 0; i < labels.size(); ++i) {
		std::string r = "img" + std::to_string(i) + ".png," + labels[i].first + ",_,_,k,i,_," + labels[i].second + ",-";
		for (int k = 0; k < 56; ++k) r += ",(" + std::to_string(k) + ";2)";
		text += r + "\n";
	}
	const std::string p = test::tempDir("labels-" + name) + "/" + name;  // its own folder: tempDir empties it
	std::ofstream(p, std::ios::binary) << text;
	return p;
}

std::vector<std::string> labelsOf(const Corpus& c) {
	std::vector<std::string> out;
	for (const auto& e : c.entries) out.push_back(e.emotionLabel() + " " + e.cdvLabel());
	return out;
}
}  // namespace

TEST(ChUnicampCsv, labelsAreCanonicalWhateverTheSpelling) {
	const std::vector<std::string> canonical = {"joy k1", "joy ʃ1", "neutral ɛ", "neutral e", "distress ʎ3", "hate ɐ", "fear sil", "happy-for r1"};
	const auto bracketed = labelledCorpus(
	    "bracketed.csv", {{"joy", "<k1>"}, {"joy", "<ʃ1>"}, {"neutral", "<ɛ>"}, {"neutral", "<e>"}, {"distress", "<ʎ3>"}, {"hate", "<ɐ>"}, {"fear", "<sil>"}, {"happy-for", "<r1>"}});
	const auto plain = labelledCorpus(
	    "plain.csv", {{"joy", "k1"}, {"joy", "ʃ1"}, {"neutral", "ɛ"}, {"neutral", "e"}, {"distress", "ʎ3"}, {"hate", "ɐ"}, {"fear", "sil"}, {"happy-for", "r1"}});
	const auto aliases = labelledCorpus(
	    "aliases.csv", {{"Happiness", "k1"}, {"happy", "sh1"}, {"NEUTRAL", "E"}, {"Neutral", "<e>"}, {"sadness", "<lh3>"}, {"disgust", "6"}, {"Fear", "sil"}, {"happy_for", "r1"}});
	EXPECT_EQ(labelsOf(readChUnicampCsv(bracketed)), canonical);
	EXPECT_EQ(labelsOf(readChUnicampCsv(plain)), canonical);
	EXPECT_EQ(labelsOf(readChUnicampCsv(aliases)), canonical);
	// Context phones and the word are not labels of the model's keys: kept as written.
	EXPECT_EQ(readChUnicampCsv(bracketed).entries[0].context[2], "k");
}

TEST(ChUnicampCsv, unknownLabelsNameFileAndRow) {
	// Line 1 is a comment, so the rows are lines 2, 3, …: the error names the file's line.
	auto p = labelledCorpus("badcdv.csv", {{"joy", "<k1>"}, {"joy", "<x9>"}});
	std::string err = errorOf([&] { readChUnicampCsv(p); });
	EXPECT_EQ(err.rfind(p + ":3: unknown viseme '<x9>' (known: p1 p2 f1 ", 0), 0u) << err;
	EXPECT_NE(err.find(" sil, their ASCII aliases, with or without <>)"), std::string::npos) << err;
	EXPECT_EQ(err.find('\n'), std::string::npos);
	p = labelledCorpus("badcase.csv", {{"joy", "SH1"}});  // ASCII aliases are case-sensitive
	EXPECT_EQ(errorOf([&] { readChUnicampCsv(p); }).rfind(p + ":2: unknown viseme 'SH1' (known: ", 0), 0u);
	p = labelledCorpus("bademotion.csv", {{"joy", "k1"}, {"neutral", "a"}, {"grumpy", "k1"}});
	err = errorOf([&] { readChUnicampCsv(p); });
	EXPECT_EQ(err.rfind(p + ":4: unknown emotion 'grumpy' (known: neutral, joy, distress, ", 0), 0u) << err;
	EXPECT_NE(err.find("; '-' for an unlabelled row)"), std::string::npos) << err;
	// A labelled row needs a CDV from the table even when it looks like an image stem.
	p = labelledCorpus("stem.csv", {{"joy", "01_01"}});
	EXPECT_EQ(errorOf([&] { readChUnicampCsv(p); }).rfind(p + ":2: unknown viseme '01_01'", 0), 0u);
}

TEST(ChUnicampCsv, unlabelledRowsKeepTheirCdvAsWritten) {
	// Emotion "-": no labels (IMM and iBUG shapes written as CSV, D11); the CDV is an image stem.
	auto p = labelledCorpus("unlabelled.csv", {{"-", "01_01"}, {"-", "<anything>"}, {"-", "E"}});
	const std::vector<std::string> expected = {"- 01_01", "- <anything>", "- E"};
	EXPECT_EQ(labelsOf(readChUnicampCsv(p)), expected);
}

TEST(Pts, readsOneBasedCoordinatesAndFindsTheImage) {
	CorpusEntry e = readPts(kData + "/corpus/face.pts");
	ASSERT_EQ(e.points.rows(), 4);
	EXPECT_DOUBLE_EQ(e.points(0, 0), 10.0);
	EXPECT_DOUBLE_EQ(e.points(1, 0), 30.5);
	EXPECT_DOUBLE_EQ(e.points(2, 1), 40.0);
	EXPECT_EQ(e.imagePath, kData + "/corpus/face.ppm");
	std::string p = writeFile("short.pts", "version: 1\nn_points: 3\n{\n1 2\n3 4\n}\n");
	EXPECT_EQ(errorOf([&] { readPts(p); }), p + ": n_points says 3 but 2 points follow");
}

TEST(Asf, immShapesAreInPixels) {
	SKIP_WITHOUT_IMM();
	const Corpus& c = test::immCorpus();
	EXPECT_EQ(c.schemeName, "imm-73");
	ASSERT_EQ(c.entries.size(), 120u);
	const CorpusEntry& e = c.entries[0];
	EXPECT_NE(e.imagePath.find("01_01.jpg"), std::string::npos);
	ASSERT_EQ(e.points.rows(), 73);
	// First point of 01_01.asf: 0.31251052, 0.37090045 of an 800×600 image.
	EXPECT_NEAR(e.points(0, 0), 0.31251052 * 800, 1e-9);
	EXPECT_NEAR(e.points(0, 1), 0.37090045 * 600, 1e-9);
	EXPECT_FALSE(e.cdv);
	EXPECT_EQ(e.name, "01_01");
}

// Issue 46: the corpus → model step is a library call (talkhead build and the first run's default face
// use it; the default face comes out byte for byte as before).
TEST(CorpusBuild, schemeAndModelFromACorpusAndClearErrors) {
	SKIP_WITHOUT_IMM();
	Corpus c = test::immCorpus();
	EXPECT_EQ(corpusScheme(c).name, "imm-73");
	EXPECT_NE(errorOf([&] { corpusScheme(c, "ibug-68"); }).find("has 73 points per shape, scheme ibug-68 has 68"), std::string::npos);
	c.entries.resize(6);
	NullProgress quiet;
	const FaceModel m = buildFaceModel(c, corpusScheme(c), BuildOptions{}, quiet);
	EXPECT_EQ(m.sampleCount(), 6u);
	EXPECT_EQ(m.width, 800);
	EXPECT_EQ(m.height, 600);
	EXPECT_EQ(m.pointCount(), 73);
	c.entries.clear();
	EXPECT_NE(errorOf([&] { corpusScheme(c); }).find("the corpus has no image"), std::string::npos);
}

TEST(Corpus, folderWithoutShapesIsRejected) {
	std::string dir = test::tempDir("emptycorpus");
	EXPECT_EQ(errorOf([&] { loadCorpus(dir); }), dir + ": no .asf or .pts shape files in this folder");
	EXPECT_EQ(errorOf([&] { loadCorpus(dir + "/nope"); }), dir + "/nope: corpus not found");
}

TEST(ChUnicampCsv, aClosedEyesImageIsAnUnlabelledRowTheCsvNames) {
	// D50: "# closed-eyes: IMAGE" names the row whose face has its eyes shut; it must be unlabelled.
	auto p = labelledCorpus("closed.csv", {{"neutral", "sil"}, {"-", "closed-eyes"}});
	const std::string text = readTextFile(p);
	std::ofstream(p, std::ios::binary) << "# closed-eyes: img1.png\n" + text;
	const Corpus c = readChUnicampCsv(p);
	EXPECT_EQ(c.closedEyes, (std::filesystem::path(p).parent_path() / "img1.png").string());
	std::ofstream(p, std::ios::binary) << "# closed-eyes: img0.png\n" + text;
	EXPECT_EQ(errorOf([&] { readChUnicampCsv(p); }), p + ":3: the closed-eyes image must be an unlabelled row (emotion '-'), so no keypose uses it");
	std::ofstream(p, std::ios::binary) << "# closed-eyes: other.png\n" + text;
	EXPECT_EQ(errorOf([&] { readChUnicampCsv(p); }).rfind(p + ": the closed-eyes image '", 0), 0u);
	std::ofstream(p, std::ios::binary) << "# closed-eyes:\n" + text;
	EXPECT_EQ(errorOf([&] { readChUnicampCsv(p); }), p + ":1: '# closed-eyes:' names no image");
}
