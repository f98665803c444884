// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "base/error.h"
#include "base/sha256.h"
#include "media/audio.h"
#include "stimuli/batch.h"
#include "test_support.h"

using namespace talkhead;

namespace {
// A row's job as "field=value" words (a switch alone), in order.
std::vector<std::string> jobWords(const std::vector<JobField>& job) {
	std::vector<std::string> w;
	for (const JobField& f : job) w.push_back(f.value ? f.field + "=" + *f.value : f.field);
	return w;
}

std::vector<std::string> errorsOf(const std::string& text, const std::string& path = "m.csv") {
	try {
		parseManifest(text, path);
	} catch (const ManifestErrors& e) {
		return e.messages;
	}
	return {};
}
}  // namespace

TEST(Batch, manifestRowsBecomeCommandsAndEveryErrorIsNamedAtOnce) {
	const Manifest m = parseManifest("# a comment\ntext,emotion,muted,size,condition\nBom dia.,joy:0.5,yes,320x180,a\n\"Olá, tudo bem?\",Sadness,no,,b\n", "m.csv");
	ASSERT_EQ(m.rows.size(), 2u);
	EXPECT_EQ(m.rows[0].line, 3);
	EXPECT_EQ(m.rows[0].command, "say");
	EXPECT_EQ(jobWords(m.rows[0].job), (std::vector<std::string>{"text=Bom dia.", "emotion=joy:0.5", "no-audio", "size=320x180"}));
	EXPECT_EQ(m.rows[1].emotion, "distress");  // an alias, canonical
	EXPECT_EQ(jobWords(m.rows[1].job)[0], "text=Olá, tudo bem?");
	EXPECT_EQ(m.rows[1].fields.at("condition"), "b");
	// JSON: an array of objects (numbers and booleans welcome).
	const Manifest j = parseManifest(R"({"stimuli": [{"text": "Oi.", "emotion": "fear", "intensity": 0.8, "muted": true, "fps": 25}]})", "m.json");
	ASSERT_EQ(j.rows.size(), 1u);
	EXPECT_EQ(jobWords(j.rows[0].job), (std::vector<std::string>{"text=Oi.", "emotion=fear:0.8", "no-audio", "fps=25"}));
	// Every problem at once, each with its line and column.
	const auto errors = errorsOf("text,emotion,colour,model,muted\nBom dia.,glee,red,nofile.thm,maybe\n,joy,,,\n");
	ASSERT_EQ(errors.size(), 5u);
	EXPECT_EQ(errors[0].rfind("m.csv:1:colour: unknown column (known: text, transcript, ", 0), 0u);
	EXPECT_EQ(errors[1], "m.csv:2:model: no such file 'nofile.thm'");
	EXPECT_EQ(errors[2].rfind("m.csv:2:emotion: unknown emotion 'glee' (known: neutral, joy, ", 0), 0u);
	EXPECT_EQ(errors[3], "m.csv:2:muted: 'maybe' is not yes or no");
	EXPECT_EQ(errors[4], "m.csv:3:text: a stimulus needs text (spoken by espeak-ng), a transcript, or audio (its phones recognised)");
	EXPECT_EQ(errorsOf("text,voice\nOi.,pt\n", "m.csv").size(), 0u);
	// The text of a timing file goes with a transcript, resolved against the manifest's folder.
	const std::string timing = std::string(TALKHEAD_TEST_DATA_DIR) + "/timing/";
	const Manifest t = parseManifest("transcript,timing-text\n" + timing + "aeneas.smil," + timing + "aeneas.xhtml\n", "m.csv");
	ASSERT_EQ(t.rows.size(), 1u);
	EXPECT_EQ(jobWords(t.rows[0].job), (std::vector<std::string>{"emotion=neutral", "timing-text=" + timing + "aeneas.xhtml", "transcript=" + timing + "aeneas.smil"}));
	EXPECT_EQ(errorsOf("text,timing-text\nOi.," + timing + "aeneas.xhtml\n")[0], "m.csv:2:timing-text: the text of a timing file, but the row has no transcript");
	EXPECT_EQ(errorsOf("text\nOi.,extra\n")[0], "m.csv:2: 2 fields, the header has 1");
	EXPECT_EQ(errorsOf("text,fps\nOi.,31.5x\n")[0], "m.csv:2:fps: '31.5x' is not a frame rate (30, 25, 29.97, 30000/1001)");
}

TEST(Batch, blindIdsComeFromTheSeedAndThePositionOnly) {
	const auto a = blindIds(300, 7), b = blindIds(300, 7), c = blindIds(300, 8);
	EXPECT_EQ(a, b);
	EXPECT_NE(a, c);
	EXPECT_EQ(std::set<std::string>(a.begin(), a.end()).size(), 300u);  // all distinct
	EXPECT_EQ(a[0].size(), 7u);
	EXPECT_EQ(a[0][0], 'S');
}

TEST(Batch, ordersArePermutationsBalancedInPositionAndCarryOver) {
	for (std::size_t n : {6u, 5u, 23u}) {
		const std::size_t rows = n % 2 ? 2 * n : n;
		const auto orders = presentationOrders(n, rows, 3);
		ASSERT_EQ(orders.size(), rows);
		std::map<std::pair<std::size_t, std::size_t>, int> position, neighbours;
		for (const auto& o : orders) {
			ASSERT_EQ(o.size(), n);
			EXPECT_EQ(std::set<std::size_t>(o.begin(), o.end()).size(), n);  // a permutation
			for (std::size_t k = 0; k < n; ++k) ++position[{o[k], k}];
			for (std::size_t k = 1; k < n; ++k) ++neighbours[{o[k - 1], o[k]}];
		}
		// Each stimulus equally often in each position (once, twice for odd n), each ordered pair of
		// neighbours equally often (once, twice for odd n).
		for (const auto& [key, count] : position) EXPECT_EQ(count, n % 2 ? 2 : 1) << n;
		EXPECT_EQ(position.size(), n * n);
		for (const auto& [key, count] : neighbours) EXPECT_EQ(count, n % 2 ? 2 : 1) << n;
		EXPECT_EQ(neighbours.size(), n * (n - 1));
		EXPECT_EQ(presentationOrders(n, rows, 3), orders);  // seeded
		EXPECT_NE(presentationOrders(n, rows, 4), orders);
	}
	// No two neighbours with the same label, when that is possible.
	const std::vector<std::string> labels = {"joy", "joy", "joy", "anger", "anger", "anger", "fear", "fear", "fear", "hate", "hate", "hate"};
	std::string warning;
	const auto orders = presentationOrders(labels.size(), 3, 1, &labels, &warning);
	EXPECT_TRUE(warning.empty()) << warning;
	for (const auto& o : orders)
		for (std::size_t k = 1; k < o.size(); ++k) EXPECT_NE(labels[o[k]], labels[o[k - 1]]);
}

TEST(Batch, keyAndOrdersAreCsvAndTheKeyResumes) {
	const Manifest m = parseManifest("text,condition\nOi.,\"a,b\"\nTchau.,c\n", "m.csv");
	const auto ids = blindIds(2, 1);
	std::vector<StimulusResult> results = {{"ok", std::string(64, 'a'), ids[0] + ".mp4", ""}, {"failed", "", ids[1] + ".mp4", "boom"}};
	const std::string key = keyCsv(m, ids, results);
	EXPECT_EQ(key, "id,row,status,sha256,file,text,condition\n" + ids[0] + ",2,ok," + std::string(64, 'a') + "," + ids[0] + ".mp4,Oi.,\"a,b\"\n" + ids[1] +
	                   ",3,failed,," + ids[1] + ".mp4,Tchau.,c\n");
	const std::string path = test::tempDir("batchkey") + "/key.csv";
	std::ofstream(path) << key;
	const auto sums = readKeyChecksums(path);
	ASSERT_EQ(sums.size(), 1u);  // only the complete one
	EXPECT_EQ(sums.at(ids[0]), std::string(64, 'a'));
	EXPECT_EQ(orderCsv({1, 0}, ids, results), "position,id,file\n1," + ids[1] + "," + ids[1] + ".mp4\n2," + ids[0] + "," + ids[0] + ".mp4\n");
	EXPECT_EQ(sha256("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");  // FIPS 180-2
}

TEST(Batch, anUnknownColumnNamesTheHeadersLine) {
	const auto e = errorsOf("# stimuli for the pilot\n\ntext,mood\nOi.,x\n");
	ASSERT_EQ(e.size(), 1u);
	EXPECT_EQ(e[0].rfind("m.csv:3:mood: unknown column", 0), 0u);
}

TEST(Batch, shiftedAudioStartsLaterOrEarlierInsideSilence) {
	// --lead-in / --av-offset / --tail on the audio: a 10-sample ramp at 1000 Hz.
	AudioClip clip;
	clip.sampleRate = 1000;
	clip.channels = 1;
	for (int i = 1; i <= 10; ++i) clip.samples.push_back(float(i));
	auto all = [](std::unique_ptr<AudioSource> s) {
		std::vector<float> out, buf(4);
		for (std::size_t n; (n = s->read(buf.data(), buf.size())) > 0;) out.insert(out.end(), buf.begin(), buf.begin() + long(n));
		return out;
	};
	const Ticks ms3(3 * kTicksPerSecond / 1000), ms5(5 * kTicksPerSecond / 1000), ms15(15 * kTicksPerSecond / 1000);
	EXPECT_EQ(all(shiftedSource(clipSource(clip), ms3, ms15)), (std::vector<float>{0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 0, 0}));
	EXPECT_EQ(all(shiftedSource(clipSource(clip), -ms3, ms5)), (std::vector<float>{4, 5, 6, 7, 8}));
	EXPECT_EQ(all(shiftedSource(clipSource(clip), -ms15, ms3)), (std::vector<float>{0, 0, 0}));  // all dropped: silence
}

TEST(Batch, answersAreScoredAgainstTheKey) {
	const std::string dir = test::tempDir("batchscore");
	std::ofstream(dir + "/key.csv") << "id,row,status,sha256,file,text,emotion,condition\n"
	                                   "SA,2,ok,x,SA.mp4,Oi.,joy,full\nSB,3,ok,x,SB.mp4,Oi.,anger:0.5,weak\nSC,4,ok,x,SC.mp4,Oi.,,full\n";
	std::ofstream(dir + "/a1.csv") << "participant,position,id,valence,valence_ms,emotion,emotion_ms\n"
	                                  "1,1,SA,positive,900,joy,1200\n1,2,SB,negative,800,hate,1500\n1,3,SC,neutral,700,none,1000\n";
	std::ofstream(dir + "/a2.csv") << "participant,position,id,valence,valence_ms,emotion,emotion_ms\n"
	                                  "2,1,SB,negative,900,anger,1100\n2,2,SA,positive,600,hope,900\n2,3,SC,neutral,650,joy,800\n";
	const Score s = scoreAnswers(dir + "/key.csv", {dir + "/a1.csv", dir + "/a2.csv"});
	EXPECT_EQ(s.answered, 6);
	EXPECT_EQ(s.correct, 3);  // joy → joy, anger → anger, neutral → none of the above
	EXPECT_EQ(s.byCondition.at("full"), std::make_pair(2, 4));
	EXPECT_EQ(s.byCondition.at("weak"), std::make_pair(1, 2));
	auto cell = [&](const char* t, const char* a) {
		return s.confusion[std::size_t(std::find(s.truths.begin(), s.truths.end(), t) - s.truths.begin())]
		                  [std::size_t(std::find(s.answers.begin(), s.answers.end(), a) - s.answers.begin())];
	};
	EXPECT_EQ(cell("anger", "hate"), 1);
	EXPECT_EQ(cell("joy", "hope"), 1);
	const std::string report = scoreReport(s);
	EXPECT_NE(report.find("anger                    2   50.0 %"), std::string::npos) << report;
	EXPECT_NE(report.find("weak                     2   50.0 %"), std::string::npos) << report;
	EXPECT_NE(report.find("all                      6   50.0 %"), std::string::npos) << report;
	writeConfusionPng(s, dir + "/confusion.png");
	EXPECT_GT(std::filesystem::file_size(dir + "/confusion.png"), 1000u);
	// A stimulus the key lacks, or an unknown answer: the file and line.
	std::ofstream(dir + "/bad.csv") << "participant,position,id,valence,valence_ms,emotion,emotion_ms\n1,1,SZ,positive,1,joy,1\n";
	try {
		scoreAnswers(dir + "/key.csv", {dir + "/bad.csv"});
		ADD_FAILURE() << "no error";
	} catch (const Error& e) {
		EXPECT_EQ(std::string(e.what()), dir + "/bad.csv:2: stimulus 'SZ' is not in " + dir + "/key.csv");
	}
}

TEST(Batch, aRowMayNameADrivingVideo) {
	// Issue 17 §3: matched stimuli — the real clip's head motion, blinks and timing on the synthetic face.
	const auto dir = std::filesystem::temp_directory_path() / "talkhead_batch_drive";
	std::filesystem::create_directories(dir);
	std::ofstream(dir / "clip.mp4") << "x";
	const std::string path = (dir / "m.csv").string();
	const Manifest m = parseManifest("drive,drive-mouth,text,emotion\nclip.mp4,yes,,joy\nclip.mp4,,bin blue at f two now,\n", path);
	ASSERT_EQ(m.rows.size(), 2u);
	EXPECT_EQ(m.rows[0].command, "render");
	EXPECT_EQ(jobWords(m.rows[0].job), (std::vector<std::string>{"drive-mouth", "emotion=joy", "drive=" + (dir / "clip.mp4").string()}));
	EXPECT_EQ(m.rows[1].command, "render");  // text aligned to the driving video's audio
	EXPECT_EQ(jobWords(m.rows[1].job), (std::vector<std::string>{"text=bin blue at f two now", "emotion=neutral", "drive=" + (dir / "clip.mp4").string()}));
	const auto errors = errorsOf("drive,drive-mouth,text\nclip.mp4,yes,Oi.\n,yes,\nnone.mp4,maybe,Oi.\n", path);
	ASSERT_EQ(errors.size(), 4u);
	EXPECT_EQ(errors[0], path + ":2:drive-mouth: takes the mouth from the drive video: no text or transcript");
	EXPECT_EQ(errors[1], path + ":3:drive-mouth: needs a drive video");
	EXPECT_EQ(errors[2], path + ":4:drive: no such file 'none.mp4'");
	EXPECT_EQ(errors[3], path + ":4:drive-mouth: 'maybe' is not yes or no");
	std::filesystem::remove_all(dir);
}

TEST(Batch, aRowMayChooseHowTheFaceIsResampledAndItsSkinAndPairThem) {
	// Issue 47 (D84, D85): resampling and au-appearance are drawing columns, on a row and on its other side.
	const Manifest m = parseManifest("text,resampling,au-appearance,versus:resampling\nOi.,linear,learned,sharp\n", "m.csv");
	ASSERT_EQ(m.rows.size(), 1u);
	const std::vector<std::string> w = jobWords(m.rows[0].job);
	EXPECT_NE(std::find(w.begin(), w.end(), "resampling=linear"), w.end());
	EXPECT_NE(std::find(w.begin(), w.end(), "au-appearance=learned"), w.end());
}
