// SPDX-License-Identifier: GPL-3.0-or-later
// Issue 32 (D62): the coarticulation model learns a known coarticulation back, bilabials shut whatever
// the regression says, the face's exemplars follow the predicted opening, and a damaged model file is one
// clear error naming it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "base/error.h"
#include "base/progress.h"
#include "geometry/scheme.h"
#include "model/face_model.h"
#include "perform/plan.h"
#include "render/live.h"
#include "synth/coarticulation.h"
#include "synth/synthesizer.h"
#include "synth_corpus.h"
#include "test_support.h"

using namespace talkhead;

namespace {

Ticks ms(long v) { return Ticks(v * (kTicksPerSecond / 1000)); }

struct Phone {
	const char* phone;
	const char* cdv;
};

// A clip of "t V t V … " between pauses, 100 ms a phone, tracked at 100 frames/s. Its mouth: each phone
// holds its own opening and width, except that a consonant before a rounded vowel is rounded already
// (the anticipation real speech has) and a consonant after an open vowel is opener.
CoarticulationClip clip(const std::vector<Phone>& sequence, int seed) {
	CoarticulationClip c;
	c.name = "clip" + std::to_string(seed);
	std::vector<Phone> all = {{"_", "sil"}};
	all.insert(all.end(), sequence.begin(), sequence.end());
	all.push_back({"_", "sil"});
	long t = 0;
	std::vector<std::pair<double, double>> mouth;
	for (std::size_t i = 0; i < all.size(); ++i) {
		const long len = all[i].phone == std::string("_") ? 400 : 80 + 10 * ((seed + long(i)) % 5);
		c.phones.push_back({ms(t), ms(t + len), all[i].phone, all[i].phone, Cdv::of(all[i].cdv), 0});
		const std::string cdv = all[i].cdv, next = i + 1 < all.size() ? all[i + 1].cdv : "sil", before = i > 0 ? all[i - 1].cdv : "sil";
		double open = cdv == "a" ? 1.0 : cdv == "u" ? 0.45 : cdv == "i1" ? 0.55 : cdv == "t1" ? 0.25 : 0.0;
		double width = cdv == "u" ? 0.7 : cdv == "i1" ? 1.15 : 1.0;
		if (cdv == "t1" && next == "u") width = 0.78;  // rounding spreads back
		if (cdv == "t1" && before == "a") open = 0.45;
		for (long f = t; f < t + len; f += 10) mouth.push_back({open, width});
		t += len;
	}
	for (std::size_t f = 0; f < mouth.size(); ++f) {
		c.times.push_back(double(f) * 0.01);
		c.openings.push_back(0.1 * mouth[f].first);  // any unit: each clip is normalised by its own
		c.widths.push_back(0.5 * mouth[f].second);
	}
	return c;
}

std::vector<PhoneSegment> phones(const std::vector<Phone>& sequence) { return clip(sequence, 0).phones; }

const std::vector<CoarticulationClip>& clips() {
	static const std::vector<CoarticulationClip> c = [] {
		std::vector<CoarticulationClip> out;
		const Phone t = {"t", "t1"}, a = {"a", "a"}, u = {"u", "u"}, i = {"i", "i1"};
		const std::vector<std::vector<Phone>> sentences = {{t, a, t, u, t, i}, {t, u, t, a, t, i, t, u}, {t, i, t, u, t, a},
		                                                   {t, a, t, i, t, u, t, a}, {t, u, t, i, t, a, t, u}, {t, i, t, a, t, u}};
		for (int k = 0; k < 24; ++k) out.push_back(clip(sentences[std::size_t(k) % sentences.size()], k));
		return out;
	}();
	return c;
}

// The predicted opening and width of the keypose of phone `index` (in the phones with the pauses).
std::pair<double, double> predicted(const CoarticulationModel& m, const std::vector<Phone>& sequence, std::size_t index) {
	const auto ph = phones(sequence);
	auto keys = keyposes(ph, ms(40));
	predictMouthOpenings(m, ph, keys);
	for (const Keypose& k : keys)
		if (k.first == index) return {k.mouthOpening.value_or(-1), k.mouthWidth.value_or(-1)};
	ADD_FAILURE() << "no keypose for phone " << index;
	return {0, 0};
}

// A face whose corpus has a shut /p/, an open /a/, a rounded /u/ and a mid /i/ (neutral only).
const FaceModel& smallFace() {
	static const FaceModel model = [] {
		SynthCorpusOptions o;
		o.width = 320;
		o.height = 180;
		o.emotions = {"neutral"};
		o.visemes = {"sil", "a", "u", "p1", "i1", "t1"};
		return test::synthModel(o);
	}();
	return model;
}

// The model without D107's rest (what a file before version 5 can hold): the tests of the earlier versions' lines.
CoarticulationModel beforeRest(CoarticulationModel m) {
	m.restOpening.reset(), m.restWidth.reset(), m.restClips = 0;
	return m;
}

// Loading the file at path fails with one error naming it and containing expected.
// A saved model file whose line `key` a test replaces (and whose version it sets) to write damaged copies.
struct SavedLine {
	std::string path, text;
	std::size_t at = 0, end = 0;
	SavedLine(const std::string& file, const std::string& key) : path(file) {
		std::ifstream in(path);
		text.assign(std::istreambuf_iterator<char>(in), {});
		at = text.find("\n" + key + "\t") + 1, end = text.find('\n', at) + 1;
	}
	bool found() const { return at != std::string::npos + 1; }
	std::string line() const { return text.substr(at, end - at); }
	void write(const std::string& version, const std::string& line) const {
		std::string v = text;
		v.replace(at, end - at, line);
		v.replace(v.find("talkhead-coarticulation\t"), 25, "talkhead-coarticulation\t" + version);
		std::ofstream(path) << v;
	}
};

void expectLoadError(const std::string& path, const std::string& expected) {
	try {
		loadCoarticulation(path);
		ADD_FAILURE() << "loaded a damaged file";
	} catch (const Error& e) {
		EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
		EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
	}
}

// A line that file version `since` added (`saved`'s): a file of the version before without it reads with
// `has` false, one with it is refused, and so is the line twice.
void expectLineOfVersion(const SavedLine& saved, const std::string& before, const std::string& since,
                         const std::function<bool(const CoarticulationModel&)>& has) {
	ASSERT_TRUE(saved.found());
	saved.write(before, "");
	EXPECT_FALSE(has(loadCoarticulation(saved.path)));
	saved.write(before, saved.line());
	expectLoadError(saved.path, "unexpected line");  // the version before has none
	saved.write(since, saved.line() + saved.line());
	expectLoadError(saved.path, "unexpected line");  // twice
}

}  // namespace

TEST(Coarticulation, aRoundedVowelRoundsTheConsonantBeforeItAndAnOpenVowelOpensTheOneAfter) {
	const CoarticulationModel m = trainCoarticulation(clips(), ms(40), 1.0);
	const Phone t = {"t", "t1"}, a = {"a", "a"}, u = {"u", "u"}, i = {"i", "i1"};
	// The /t/ of "t u" is rounder (narrower) than the /t/ of "t i": its width comes from what follows.
	const double beforeU = predicted(m, {t, u, t, i}, 1).second, beforeI = predicted(m, {t, i, t, u}, 1).second;
	EXPECT_LT(beforeU, beforeI - 0.1) << beforeU << " " << beforeI;
	// The /t/ after /a/ opens more than the /t/ after /i/.
	EXPECT_GT(predicted(m, {i, a, t, u}, 3).first, predicted(m, {a, i, t, u}, 3).first + 0.1);
	// Vowels keep their own: /a/ open, /u/ narrow.
	EXPECT_GT(predicted(m, {t, a, t}, 2).first, predicted(m, {t, u, t}, 2).first + 0.2);
	EXPECT_LT(predicted(m, {t, u, t}, 2).second, predicted(m, {t, i, t}, 2).second - 0.2);
	// The in-breath gets no prediction; a pause's rest the speakers' rest after speech (D107), and none
	// from a model without one (a file before version 5).
	const auto ph = phones({t, a});
	auto keys = keyposes(ph, ms(40));
	predictMouthOpenings(m, ph, keys);
	for (const Keypose& k : keys) EXPECT_EQ(k.mouthOpening.has_value(), isPhoneKeypose(ph, k) || (k.cdv.isSilence() && !k.breath)) << k.cdv;
	keys = keyposes(ph, ms(40));
	predictMouthOpenings(beforeRest(m), ph, keys);
	for (const Keypose& k : keys) EXPECT_EQ(k.mouthOpening.has_value(), isPhoneKeypose(ph, k)) << k.cdv;
}

TEST(Coarticulation, theShippedModelLoadsFromTheDataFoldersAndMovesTheMouthAsTheRealSpeakersDo) {
	// Issue 48 (D90): models/coarticulation/grid.tsv, learned from 95 GRID clips; "on" is it, "off" none.
	const auto m = shippedCoarticulation();
	ASSERT_TRUE(m);
	EXPECT_EQ(m->features, coarticulationFeatureNames());
	EXPECT_GT(m->samples, 1000u);
	ASSERT_TRUE(m->leadOpening && m->bilabialLead);
	EXPECT_GT(*m->leadOpening, 0.2);  // GRID speakers part their lips before they speak (D70)
	EXPECT_LT(*m->bilabialLead, 0.0);  // and shut /p b m/ before the phone's midpoint (D71)
	EXPECT_EQ(coarticulationOption("on"), m);
	EXPECT_EQ(coarticulationOption("off"), nullptr);
	// Real speakers' mouths: vowels open, /p/ and /f/ close, /w/ rounds.
	const Phone t = {"t", "t1"}, a = {"a", "a"}, i = {"i", "i1"}, p = {"p", "p1"}, f = {"f", "f1"}, w = {"w", "ʊ"};
	const double open = std::min(predicted(*m, {t, a, t}, 2).first, predicted(*m, {t, i, t}, 2).first);
	EXPECT_LT(predicted(*m, {a, p, a}, 2).first, open - 0.2);
	EXPECT_LT(predicted(*m, {a, f, a}, 2).first, open - 0.2);
	EXPECT_LT(predicted(*m, {a, w, a}, 2).second, predicted(*m, {a, t, a}, 2).second - 0.05);
	// D106: its companion for recognised phones (grid-recognised.tsv, the same clips' recognised phones):
	// no visual lead (recognised phones are not late), the same mouths for clear contexts.
	ASSERT_TRUE(m->recognised);
	const CoarticulationModel& r = *m->recognised;
	EXPECT_FALSE(r.recognised);
	EXPECT_EQ(r.features, coarticulationFeatureNames());
	EXPECT_GT(r.samples, 1000u);
	EXPECT_FALSE(r.visualLead);
	ASSERT_TRUE(m->visualLead);
	EXPECT_NE(r.weights, m->weights);
	EXPECT_LT(predicted(r, {a, p, a}, 2).first, predicted(r, {t, a, t}, 2).first - 0.2);
}

TEST(Coarticulation, recognisedPhonesArePlannedWithTheModelLearnedFromRecognisedPhones) {
	// D106: a plan of recognised phones (PhoneTiming::Recognised) takes the model's `recognised` companion;
	// given and aligned phones the model itself; a model without a companion (a file of one's own) plans
	// every timing.
	const Phone t = {"t", "t1"}, a = {"a", "a"}, d = {"d", "t1"};
	const auto ph = phones({t, a, d, a, t});
	CoarticulationModel main = *shippedCoarticulation(), heard = *shippedCoarticulation()->recognised;
	main.recognised.reset(), main.visualLead.reset();
	heard.intercept += 0.5;  // a companion that opens every mouth half a unit more: told apart at a glance
	PerformanceSpec spec;
	spec.phones = ph;
	spec.pauses = PauseStyle::Still;
	auto openings = [&](PhoneTiming timing, const CoarticulationModel& model) {
		spec.timing = timing;
		spec.coarticulation = std::make_shared<const CoarticulationModel>(model);
		std::vector<std::optional<double>> o;
		for (const Keypose& k : planPerformance(spec).timeline.keys) o.push_back(k.mouthOpening);
		return o;
	};
	const auto alone = openings(PhoneTiming::Recognised, main), heardAlone = openings(PhoneTiming::Given, heard);
	CoarticulationModel pair = main;
	pair.recognised = std::make_shared<const CoarticulationModel>(heard);
	EXPECT_EQ(openings(PhoneTiming::Recognised, pair), heardAlone);
	EXPECT_EQ(openings(PhoneTiming::Given, pair), alone);
	EXPECT_EQ(openings(PhoneTiming::Aligned, pair), alone);
	EXPECT_NE(alone, heardAlone);
}

TEST(Coarticulation, aBilabialIsHeldShutForAFrameWhereThereIsRoom) {
	// D90: /p/ between two vowels 80 ms away on each side: two copies at ±half a frame (25 fps: ±20 ms);
	// a /p/ whose neighbours are closer than a frame and a half keeps its single keypose.
	const Phone a = {"a", "a"}, p = {"p", "p1"};
	const auto ph = phones({a, p, a});
	auto keys = keyposes(ph, ms(40));
	std::vector<Ticks> before;
	for (const Keypose& k : keys) before.push_back(k.time);
	holdBilabials(ph, keys, ms(40));
	std::vector<std::pair<std::string, Ticks>> got;
	for (const Keypose& k : keys) got.push_back({k.cdv.label(), k.time});
	ASSERT_EQ(keys.size(), before.size() + 1);
	std::size_t at = 0;
	while (at < keys.size() && keys[at].cdv.label() != "p1") ++at;
	ASSERT_LT(at + 1, keys.size());
	EXPECT_EQ(keys[at + 1].cdv.label(), "p1");
	EXPECT_EQ(keys[at + 1].time - keys[at].time, ms(40));
	EXPECT_EQ(keys[at].time + ms(20), before[at]);  // centred on the bilabial's keypose
	EXPECT_EQ(keys[at].first, keys[at + 1].first);
	// No room: keyposes 30 ms apart at 25 fps.
	std::vector<Keypose> tight = keys;
	tight.erase(tight.begin() + long(at) + 1);
	tight[at].time = tight[at - 1].time + ms(30);
	const std::size_t n = tight.size();
	holdBilabials(ph, tight, ms(40));
	EXPECT_EQ(tight.size(), n);
}

TEST(Coarticulation, savedAndLoadedExactlyAndADamagedOrMissingFileIsOneClearError) {
	const CoarticulationModel m = trainCoarticulation(clips(), ms(40), 1.0);
	const std::string path = (std::filesystem::temp_directory_path() / "talkhead-coarticulation-test.tsv").string();
	saveCoarticulation(m, path);
	const CoarticulationModel back = loadCoarticulation(path);
	EXPECT_EQ(back.features, m.features);
	EXPECT_LT((back.weights - m.weights).cwiseAbs().maxCoeff(), 1e-8);
	EXPECT_LT((back.widthWeights - m.widthWeights).cwiseAbs().maxCoeff(), 1e-8);
	EXPECT_NEAR(back.intercept, m.intercept, 1e-8);
	auto error = [&](const std::string& expected) { expectLoadError(path, expected); };
	std::string text;
	{
		std::ifstream in(path);
		text.assign(std::istreambuf_iterator<char>(in), {});
	}
	std::ofstream(path) << text.substr(0, text.size() / 2);  // cut mid-way: a feature line lost, or half a number
	error("");
	std::ofstream(path) << text.substr(0, text.find("\nintercept") + 1);
	error("no intercept line");
	std::ofstream(path) << "not a model\n";
	error("not a talkhead coarticulation model");
	std::string other = text;
	other.replace(other.find("feature\topen-2"), 14, "feature\tcolour");
	std::ofstream(path) << other;
	error("made for other features");
	for (const char* count : {"8.88889e+30", "-3", "2.5"}) {  // a count, not a number to cast (the fuzzer's 1e31 was undefined behaviour)
		std::string bad = text;
		const std::size_t at = bad.find("samples\t") + 8;
		bad.replace(at, bad.find('\n', at) - at, count);
		std::ofstream(path) << bad;
		error("samples: not a count");
	}
	std::filesystem::remove(path);
	error("cannot open");
}

// D70: the lips before the first words are learned as the speakers' mean there (each clip in its own
// units), held by PauseStyle::Still's hold keyposes, kept by the file (version 2); a version-1 file has
// none (the rest mouth then), and a damaged lead line is one clear error naming the file.
TEST(Coarticulation, theLipsBeforeTheFirstWordsAreTheSpeakersMeanHeldAndSaved) {
	std::vector<CoarticulationClip> cs = clips();
	for (std::size_t k = 0; k < cs.size(); ++k) {  // half of the clips part their lips 0.3 of their /a/, half 0.7
		CoarticulationClip& c = cs[k];
		for (std::size_t f = 0; f < c.times.size(); ++f)
			if (c.times[f] < 0.25) c.openings[f] = 0.1 * (k % 2 ? 0.7 : 0.3), c.widths[f] = 0.5 * 0.9;
	}
	// A clip's own units: its 90th percentile of the opening in speech (here its /a/s, half of it) and its
	// median width there.
	const Phone t = {"t", "t1"}, a = {"a", "a"};
	CoarticulationClip ta = clip({t, a, t, a, t, a}, 3);
	for (std::size_t f = 0; f < ta.times.size(); ++f)
		if (ta.times[f] < 0.25) ta.openings[f] = 0.1 * 0.3, ta.widths[f] = 0.5 * 0.9;
	const auto own = leadingPauseMouth(ta);
	ASSERT_TRUE(own);
	EXPECT_NEAR(own->first, 0.3, 1e-9);
	EXPECT_NEAR(own->second, 0.9, 1e-9);
	EXPECT_FALSE(leadingPauseMouth(clip({}, 0)));  // no speech: nothing before it
	// The model's: the mean of its clips'.
	CoarticulationModel m = trainCoarticulation(cs, ms(40), 1.0);
	double open = 0, width = 0;
	for (const CoarticulationClip& c : cs) open += leadingPauseMouth(c)->first / double(cs.size()), width += leadingPauseMouth(c)->second / double(cs.size());
	ASSERT_TRUE(m.leadOpening && m.leadWidth);
	EXPECT_NEAR(*m.leadOpening, open, 1e-12);
	EXPECT_NEAR(*m.leadWidth, width, 1e-12);
	EXPECT_GT(open, 0.4);
	EXPECT_LT(open, 0.8);
	EXPECT_EQ(m.leadClips, cs.size());
	EXPECT_NEAR(*trainCoarticulation(clips(), ms(40), 1.0).leadOpening, 0.0, 1e-9);  // shut in the plain clips

	const auto ph = phones({t, a, t});
	auto keys = keyposes(ph, ms(40), PauseStyle::Still);
	predictMouthOpenings(m, ph, keys);
	std::vector<long> held;
	for (const Keypose& k : keys)
		if (k.hold) {
			held.push_back(long(k.time / ms(1)));
			EXPECT_NEAR(k.mouthOpening.value_or(-1), open, 1e-9);
			EXPECT_NEAR(k.mouthWidth.value_or(-1), width, 1e-9);
		}
	EXPECT_EQ(held, (std::vector<long>{0, 250}));  // from the start until kStillLead before the first phone (400 ms)

	const std::string path = (std::filesystem::temp_directory_path() / "talkhead-coarticulation-lead.tsv").string();
	saveCoarticulation(beforeRest(m), path);  // a version-2 file's lines
	const CoarticulationModel back = loadCoarticulation(path);
	ASSERT_TRUE(back.leadOpening && back.leadWidth);
	EXPECT_NEAR(*back.leadOpening, open, 1e-8);
	EXPECT_NEAR(*back.leadWidth, width, 1e-8);
	EXPECT_EQ(back.leadClips, cs.size());
	const SavedLine saved(path, "lead");
	ASSERT_TRUE(saved.found());
	saved.write("1", "");  // a version-1 file: no lead, the rest mouth
	EXPECT_FALSE(loadCoarticulation(path).leadOpening);
	auto error = [&](const std::string& expected) { expectLoadError(path, expected); };
	saved.write("1", saved.line());
	error("unexpected line");  // version 1 has no lead
	saved.write("2", saved.line() + saved.line());
	error("unexpected line");  // twice
	saved.write("2", "lead\t-0.5\t0.9\t24\n");
	error("lead: an opening or width out of range");
	saved.write("2", "lead\t0.5\t0.9\t0\n");
	error("lead: not a count of clips");
	saved.write("2", "lead\t0.5\tnan\t3\n");
	error("");
	std::filesystem::remove(path);
}

// D107: the lips at rest after speech are learned as the speakers' mean from kRestAfter after their last
// words (each clip in its own units), given to a pause's rest keyposes (not the held lead, not the in-breath),
// kept by the file (version 5); a face's rest caught with the lips apart is drawn closed to it, a shut rest
// (or a rest asked wider than it is) stays the face's own.
TEST(Coarticulation, theLipsAtRestAfterSpeechAreTheSpeakersMeanAndARestCaughtOpenClosesToIt) {
	std::vector<CoarticulationClip> cs = clips();
	auto restAfter = [](CoarticulationClip& c, double open) {  // the clip's last 400-ms pause, from kRestAfter on
		const double from = toSeconds(c.phones.back().start + kRestAfter);
		for (std::size_t f = 0; f < c.times.size(); ++f)
			if (c.times[f] >= from) c.openings[f] = 0.1 * open, c.widths[f] = 0.5 * 0.9;
			else if (c.times[f] >= toSeconds(c.phones.back().start)) c.openings[f] = 0.1 * 0.8;  // closing: not counted
	};
	for (std::size_t k = 0; k < cs.size(); ++k) restAfter(cs[k], k % 2 ? 0.3 : 0.1);
	const Phone t = {"t", "t1"}, a = {"a", "a"};
	CoarticulationClip ta = clip({t, a, t, a, t, a}, 3);
	restAfter(ta, 0.2);
	const auto own = trailingPauseMouth(ta);
	ASSERT_TRUE(own);
	EXPECT_NEAR(own->first, 0.2, 1e-9);  // in units of its 90th percentile in speech (its /a/s)
	EXPECT_NEAR(own->second, 0.9, 1e-9);
	EXPECT_FALSE(trailingPauseMouth(clip({}, 0)));  // no speech: nothing after it
	CoarticulationModel m = trainCoarticulation(cs, ms(40), 1.0);
	double open = 0;
	for (const CoarticulationClip& c : cs) open += trailingPauseMouth(c)->first / double(cs.size());
	ASSERT_TRUE(m.restOpening && m.restWidth);
	EXPECT_NEAR(*m.restOpening, open, 1e-12);
	EXPECT_NEAR(open, 0.2, 0.02);
	EXPECT_NEAR(*m.restWidth, 0.9, 0.05);
	EXPECT_EQ(m.restClips, cs.size());
	EXPECT_NEAR(*trainCoarticulation(clips(), ms(40), 1.0).restOpening, 0.0, 1e-9);  // shut in the plain clips

	// Planned: the rest after the words takes it; the held lead and the phones keep theirs.
	const auto ph = phones({t, a, t});
	auto keys = keyposes(ph, ms(40), PauseStyle::Still);
	predictMouthOpenings(m, ph, keys);
	std::size_t rests = 0;
	for (const Keypose& k : keys) {
		ASSERT_TRUE(k.mouthOpening) << k.cdv.label() << " at " << toSeconds(k.time);
		if (k.cdv.isSilence() && !k.hold) {
			EXPECT_NEAR(*k.mouthOpening, *m.restOpening, 1e-12);
			EXPECT_GT(k.time, ph.back().start);  // the last pause's (400 ms: one keypose at its middle)
			++rests;
		} else if (k.hold) {
			EXPECT_NEAR(*k.mouthOpening, *m.leadOpening, 1e-12);
		}
	}
	EXPECT_EQ(rests, 1u);

	// Saved as version 5; a file before it has no rest; a damaged rest line is one clear error.
	const std::string path = (std::filesystem::temp_directory_path() / "talkhead-coarticulation-rest.tsv").string();
	saveCoarticulation(m, path);
	const CoarticulationModel back = loadCoarticulation(path);
	ASSERT_TRUE(back.restOpening && back.restWidth);
	EXPECT_NEAR(*back.restOpening, *m.restOpening, 1e-8);
	EXPECT_EQ(back.restClips, cs.size());
	const SavedLine saved(path, "rest");
	ASSERT_NO_FATAL_FAILURE(expectLineOfVersion(saved, "4", "5", [](const CoarticulationModel& x) { return bool(x.restOpening); }));
	saved.write("5", "rest\t11\t0.9\t24\n");
	expectLoadError(path, "rest: an opening or width out of range");
	saved.write("5", "rest\t0.2\t0.9\tmany\n");
	expectLoadError(path, "rest: not a count of clips");
	std::filesystem::remove(path);

	// Chosen: the small face's rest is shut and stays its own (the synthesizer's, unpredicted); a face whose
	// rest was caught with the lips apart (here its mid-open /i/ taken for its rest) shows that rest, drawn
	// closed to the speakers' rest on the face's unit — and never opened wider than it is.
	FaceModel caught = smallFace();
	const long sil = caught.findSample("neutral", "sil"), mid = caught.findSample("neutral", "i1");
	ASSERT_GE(sil, 0);
	ASSERT_GE(mid, 0);
	std::swap(caught.samples[std::size_t(sil)].cdv, caught.samples[std::size_t(mid)].cdv);
	Scheme scheme;
	ASSERT_TRUE(mouthScheme(caught, scheme));
	const std::vector<MouthSize> size = sampleMouths(caught, scheme);
	const MouthPool pool = mouthPool(caught, size, "neutral");
	const double unit = openingUnit(pool, pool), restSize = size[std::size_t(mid)].opening;
	ASSERT_GT(restSize, 0.5 * unit);
	auto restOf = [&](const FaceModel& face, double asked) {
		auto ks = keys;
		for (Keypose& k : ks)
			if (k.cdv.isSilence() && !k.hold) k.mouthOpening = asked;
		chooseMouthExemplars(face, Emotion::of("neutral"), ks);
		for (const Keypose& k : ks)
			if (k.cdv.isSilence() && !k.hold) return k;
		return Keypose{};
	};
	const Keypose shutRest = restOf(smallFace(), 0.2);
	EXPECT_EQ(shutRest.sample, -1);
	EXPECT_FALSE(shutRest.mouthOpening || shutRest.drawnOpening);
	const Keypose closed = restOf(caught, 0.2);
	EXPECT_EQ(closed.sample, mid);
	ASSERT_TRUE(closed.drawnOpening);
	EXPECT_NEAR(*closed.drawnOpening, 0.2 * unit, 1e-12);
	const Keypose wider = restOf(caught, 2 * restSize / unit);
	EXPECT_EQ(wider.sample, -1);
	EXPECT_FALSE(wider.mouthOpening || wider.drawnOpening);
	// An emotion's rest keeps what the expression adds: here fear's rest is the open /a/ (its /u/ gives it a
	// pool); it is drawn less open by what the neutral rest opens beyond the target, no more.
	FaceModel fearful = caught;
	const long wide = fearful.findSample("neutral", "a"), round = fearful.findSample("neutral", "u");
	ASSERT_GE(wide, 0);
	ASSERT_GE(round, 0);
	fearful.samples[std::size_t(wide)].emotion = fearful.samples[std::size_t(round)].emotion = "fear";
	fearful.samples[std::size_t(wide)].cdv = "sil";
	const std::vector<MouthSize> fearSize = sampleMouths(fearful, scheme);
	const MouthPool calm = mouthPool(fearful, fearSize, "neutral");
	const double excess = fearSize[std::size_t(mid)].opening - 0.2 * openingUnit(calm, calm);
	ASSERT_GT(excess, 0.0);
	auto feared = keys;
	for (Keypose& k : feared)
		if (k.cdv.isSilence() && !k.hold) k.mouthOpening = 0.2;
	chooseMouthExemplars(fearful, Emotion::of("fear"), feared);
	std::size_t fearRests = 0;
	for (const Keypose& k : feared)
		if (k.cdv.isSilence() && !k.hold) {
			EXPECT_EQ(k.sample, wide);
			ASSERT_TRUE(k.drawnOpening);
			EXPECT_NEAR(*k.drawnOpening, fearSize[std::size_t(wide)].opening - excess, 1e-12);
			++fearRests;
		}
	EXPECT_EQ(fearRests, 1u);
	// Rendered, the rest's points show the drawn opening.
	auto ks = keys;
	for (Keypose& k : ks)
		if (k.cdv.isSilence() && !k.hold) k.mouthOpening = 0.2;
	chooseMouthExemplars(caught, Emotion::of("neutral"), ks);
	SynthOptions o;
	Synthesizer synth(caught, o);
	synth.prepare(ks);
	Synthesizer::Workspace ws;
	Image8 frame;
	Points pts;
	synth.renderFrame(closed.time, ks, ws, frame, pts);
	EXPECT_NEAR(mouthSize(scheme, pts).opening, 0.2 * unit, 0.6 * 0.004);
	// A live session (serve, talkhead live) idles at the same drawn rest before it says anything.
	const Face face(caught, std::make_shared<const CoarticulationModel>(m));
	LiveOptions lo;
	lo.render.synth.width = 160;
	lo.render.synth.height = 90;
	LiveSession live(face, lo);
	ASSERT_FALSE(live.keyposes().empty());
	const Keypose& idle = live.keyposes().front();
	EXPECT_EQ(idle.sample, mid);
	ASSERT_TRUE(idle.drawnOpening);
	EXPECT_NEAR(*idle.drawnOpening, *m.restOpening * unit, 1e-12);
	LiveSession plain(caught, lo);  // no model: the rest as it is
	EXPECT_EQ(plain.keyposes().front().sample, -1);
	EXPECT_FALSE(plain.keyposes().front().drawnOpening);
}

TEST(Coarticulation, bilabialsShutAsEarlyAsTheSpeakersDoKeptAFrameFromTheirNeighbours) {
	// Clips of "t a p a m a t": the lips shut 20 ms before each bilabial's midpoint (tracked at 100 frames/s).
	const Phone t = {"t", "t1"}, a = {"a", "a"}, p = {"p", "p1"}, m = {"m", "p1"};
	std::vector<CoarticulationClip> cs = clips();
	for (int k = 0; k < 6; ++k) {
		CoarticulationClip c = clip({t, a, p, a, m, a, t}, 100 + k);
		for (const PhoneSegment& s : c.phones) {
			if (s.cdv != "p1") continue;
			const double mid = 0.5 * (toSeconds(s.start) + toSeconds(s.end)), shut = mid - 0.02;
			for (std::size_t f = 0; f < c.times.size(); ++f)
				if (std::abs(c.times[f] - mid) < 0.065) c.openings[f] = 0.1 * (0.1 + std::abs(c.times[f] - shut));  // least at `shut`
		}
		const auto offsets = bilabialClosureOffsets(c, ms(10));
		ASSERT_EQ(offsets.size(), 2u);
		for (double o : offsets) EXPECT_NEAR(o, -0.02, 0.0051);  // keyposes sit on the 10-ms frames, as the tracking
		cs.push_back(c);
	}
	CoarticulationModel model = trainCoarticulation(cs, ms(10), 1.0);
	ASSERT_TRUE(model.bilabialLead);
	EXPECT_NEAR(*model.bilabialLead, -0.02, 0.005);
	EXPECT_EQ(model.bilabialCount, 12u);
	EXPECT_FALSE(trainCoarticulation(clips(), ms(10), 1.0).bilabialLead);  // no bilabial: no lead
	// The keyposes: each bilabial's moves by the lead, the others stay; with no room it is kept a frame from
	// its neighbours.
	model.bilabialLead = -0.02;
	const auto ph = phones({t, a, p, a, m, a, t});
	const auto before = keyposes(ph, ms(40));
	auto keys = before;
	applyBilabialLead(model, ph, keys, ms(40));
	ASSERT_EQ(keys.size(), before.size());
	int moved = 0;
	for (std::size_t i = 0; i < keys.size(); ++i) {
		if (keys[i].cdv == "p1") {
			EXPECT_EQ(keys[i].time, before[i].time - ms(20));
			++moved;
		} else {
			EXPECT_EQ(keys[i].time, before[i].time);
		}
	}
	EXPECT_EQ(moved, 2);
	model.bilabialLead = -0.1;  // further than the room before it: a frame after the keypose before
	keys = before;
	applyBilabialLead(model, ph, keys, ms(40));
	for (std::size_t i = 1; i < keys.size(); ++i)
		if (keys[i].cdv == "p1") {
			EXPECT_EQ(keys[i].time, std::max(before[i].time - ms(100), before[i - 1].time + ms(40)));
		}
	model.bilabialLead.reset();  // no lead: nothing moves
	keys = before;
	applyBilabialLead(model, ph, keys, ms(40));
	for (std::size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(keys[i].time, before[i].time);

	// Saved and read back (version 3); a version-2 file has no such line; damage is one clear error.
	model.bilabialLead = -0.0213;
	const std::string path = (std::filesystem::temp_directory_path() / "talkhead-coarticulation-bilabial.tsv").string();
	saveCoarticulation(beforeRest(model), path);
	const CoarticulationModel back = loadCoarticulation(path);
	ASSERT_TRUE(back.bilabialLead);
	EXPECT_NEAR(*back.bilabialLead, -0.0213, 1e-9);
	EXPECT_EQ(back.bilabialCount, 12u);
	const SavedLine saved(path, "bilabial");
	expectLineOfVersion(saved, "2", "3", [](const CoarticulationModel& m) { return m.bilabialLead.has_value(); });
	saved.write("3", "bilabial\t-0.5\t12\n");
	expectLoadError(path, "bilabial: a lead out of range");
	saved.write("3", "bilabial\t-0.02\t0\n");
	expectLoadError(path, "bilabial: not a count of closures");
	std::filesystem::remove(path);
}

TEST(Coarticulation, theVisualLeadMovesEveryKeyposeKeepingTheirGapsAndNoneBeforeTheStart) {
	const Phone t = {"t", "t1"}, a = {"a", "a"}, p = {"p", "p1"};
	const auto ph = phones({t, a, p, a, t});
	const auto before = keyposes(ph, ms(40), PauseStyle::Still, true);
	ASSERT_GE(before.size(), 6u);
	ASSERT_EQ(before[0].time, Ticks(0));
	CoarticulationModel m = trainCoarticulation(clips(), ms(10), 1.0);
	auto keys = before;
	applyVisualLead(m, keys, ms(40));  // no lead: nothing moves
	for (std::size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(keys[i].time, before[i].time);
	m.visualLead = -0.025;
	applyVisualLead(m, keys, ms(40));
	EXPECT_EQ(keys[0].time, Ticks(0));  // the keypose at the start stays there
	for (std::size_t i = 1; i < keys.size(); ++i) {
		EXPECT_EQ(keys[i].time, before[i].time - ms(25)) << i;
		EXPECT_EQ(keys[i].cdv, before[i].cdv);
	}
	// A lead longer than the first gap: the keypose after the start keeps its gap up to a frame, the rest follow.
	m.visualLead = -0.2;
	keys = before;
	applyVisualLead(m, keys, ms(40));
	for (std::size_t i = 1; i < keys.size(); ++i) {
		EXPECT_GE(keys[i].time - keys[i - 1].time, std::min(before[i].time - before[i - 1].time, ms(40))) << i;
		EXPECT_LE(keys[i].time, std::max(before[i].time - ms(200), keys[i - 1].time + ms(40))) << i;
	}
	// Later (a positive lead): all but the start move.
	m.visualLead = 0.01;
	keys = before;
	applyVisualLead(m, keys, ms(40));
	EXPECT_EQ(keys[0].time, Ticks(0));
	for (std::size_t i = 1; i < keys.size(); ++i) EXPECT_EQ(keys[i].time, before[i].time + ms(10)) << i;

	// In a plan of phones timed by talkhead's aligner: every keypose of the model without a lead, 25 ms
	// earlier. Given times (a transcript, espeak-ng's, a TTS engine's) and recognised ones stay as they are.
	PerformanceSpec spec;
	spec.phones = ph;
	spec.pauses = PauseStyle::Still;
	spec.timing = PhoneTiming::Aligned;
	CoarticulationModel none = m;
	none.visualLead.reset();
	spec.coarticulation = std::make_shared<const CoarticulationModel>(none);
	const Performance without = planPerformance(spec);
	m.visualLead = -0.025;
	spec.coarticulation = std::make_shared<const CoarticulationModel>(m);
	const Performance with = planPerformance(spec);
	ASSERT_EQ(with.timeline.keys.size(), without.timeline.keys.size());
	for (std::size_t i = 1; i < with.timeline.keys.size(); ++i) {
		EXPECT_EQ(with.timeline.keys[i].time, without.timeline.keys[i].time - ms(25)) << i;
		EXPECT_EQ(with.timeline.keys[i].mouthOpening, without.timeline.keys[i].mouthOpening) << i;
	}
	spec.timing = PhoneTiming::Given;
	const Performance given = planPerformance(spec);
	ASSERT_EQ(given.timeline.keys.size(), without.timeline.keys.size());
	for (std::size_t i = 0; i < given.timeline.keys.size(); ++i) EXPECT_EQ(given.timeline.keys[i].time, without.timeline.keys[i].time) << i;

	// Saved (version 4) and read back; a version-3 file has no such line; damage is one clear error.
	const std::string path = (std::filesystem::temp_directory_path() / "talkhead-coarticulation-visual.tsv").string();
	saveCoarticulation(beforeRest(m), path);
	const CoarticulationModel back = loadCoarticulation(path);
	ASSERT_TRUE(back.visualLead);
	EXPECT_EQ(*back.visualLead, -0.025);
	saveCoarticulation(beforeRest(none), path);  // without a lead: written as version 3, as before
	{
		std::ifstream in(path);
		std::string text((std::istreambuf_iterator<char>(in)), {});
		EXPECT_NE(text.find("talkhead-coarticulation\t3\n"), std::string::npos);
		EXPECT_EQ(text.find("\nvisual\t"), std::string::npos);
	}
	saveCoarticulation(beforeRest(m), path);
	const SavedLine saved(path, "visual");
	expectLineOfVersion(saved, "3", "4", [](const CoarticulationModel& m) { return m.visualLead.has_value(); });
	saved.write("4", "visual\t-0.5\n");
	expectLoadError(path, "visual: a lead out of range");
	saved.write("4", "visual\tsoon\n");
	expectLoadError(path, "not a number");
	saved.write("6", saved.line());
	expectLoadError(path, "version 6");
	std::filesystem::remove(path);
}

TEST(Coarticulation, bilabialsShutAndTheOtherKeyposesShowTheExemplarNearestThePrediction) {
	const FaceModel& model = smallFace();
	Scheme scheme;
	ASSERT_TRUE(mouthScheme(model, scheme));
	auto sampleOf = [&](const std::string& cdv) { return model.findSample("neutral", cdv); };
	const double open = mouthSize(scheme, model.alignedShapes[std::size_t(sampleOf("a"))]).opening;
	// "p a p": the regression (wrongly) asks the /p/s to be half open and the /a/ barely open.
	const auto ph = phones({{"p", "p1"}, {"a", "a"}, {"p", "p1"}});
	auto keys = keyposes(ph, ms(40));
	for (Keypose& k : keys)
		if (isPhoneKeypose(ph, k)) k.mouthOpening = k.cdv == "p1" ? 0.5 : 0.05, k.mouthWidth = 1.0;
	EXPECT_EQ(chooseMouthExemplars(model, Emotion::of("neutral"), keys), 3u);
	for (const Keypose& k : keys) {
		if (!k.mouthOpening) {
			EXPECT_EQ(k.sample, -1);  // pauses keep the synthesizer's choice
			continue;
		}
		const double gap = mouthSize(scheme, model.alignedShapes[std::size_t(k.sample)]).opening;
		if (k.cdv == "p1") {
			EXPECT_LE(gap, 0.1 * open) << "a bilabial shuts";
		} else {
			EXPECT_LT(gap, 0.5 * open) << "the /a/ takes a nearly closed exemplar, as asked";
		}
	}
	// Asked wide open (4 × the face's 90th percentile: this small corpus has one open vowel), the /a/ takes
	// the open exemplar; the same keys
	// give the same choice (determinism).
	for (Keypose& k : keys)
		if (k.cdv == "a") k.mouthOpening = 4.0, k.sample = -1;
	auto again = keys;
	chooseMouthExemplars(model, Emotion::of("neutral"), keys);
	chooseMouthExemplars(model, Emotion::of("neutral"), again);
	for (std::size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(keys[i].sample, again[i].sample);
	for (const Keypose& k : keys) {
		if (k.cdv == "a") {
			EXPECT_EQ(k.sample, sampleOf("a"));
		}
	}
}

namespace {
// The small face's mouth scheme and its neutral open /a/ and shut /p/ samples.
void openAndShut(Scheme& scheme, long& open, long& shut) {
	const FaceModel& model = smallFace();
	ASSERT_TRUE(mouthScheme(model, scheme));
	open = model.findSample("neutral", "a"), shut = model.findSample("neutral", "p1");
	ASSERT_GE(open, 0);
	ASSERT_GE(shut, 0);
}
}  // namespace

TEST(Coarticulation, aBilabialsChosenExemplarIsDrawnWithItsLipsShut) {
	// D99: a real face's bilabial exemplar is often a frame caught a little before or after the closure
	// (GRID s4's: 0.019 eye distances apart); the learned mouth draws it shut.
	const FaceModel& model = smallFace();
	Scheme scheme;
	long open = -1, shut = -1;
	ASSERT_NO_FATAL_FAILURE(openAndShut(scheme, open, shut));
	const Points& a = model.alignedShapes[std::size_t(open)];
	ASSERT_GT(mouthSize(scheme, a).opening, 0.05);
	Points s = a;
	shutLips(scheme, s);
	EXPECT_LT(mouthSize(scheme, s).opening, 1e-12);
	std::vector<bool> inner(std::size_t(a.rows()), false);
	for (const auto& [up, down] : scheme.mouth.inner) {
		inner[std::size_t(up)] = inner[std::size_t(down)] = true;
		EXPECT_LT((s.row(up) - s.row(down)).norm(), 1e-9) << "the pair meets";
		EXPECT_LT(((s.row(up) + s.row(down)) - (a.row(up) + a.row(down))).norm(), 1e-9) << "at its middle";
	}
	for (Eigen::Index i = 0; i < a.rows(); ++i)
		if (!inner[std::size_t(i)]) EXPECT_EQ(s.row(i), a.row(i)) << "point " << i << " stays";
	Points again = s;
	shutLips(scheme, again);
	EXPECT_EQ(again, s);
	// Drawn: a /p/ keypose given an open exemplar (as the learned mouth could bind one) shows it shut; the
	// same keypose without a chosen exemplar (the thesis's path) draws its sample's shape as before.
	SynthOptions o;
	Synthesizer synth(model, o);
	std::vector<PhoneSegment> ph;
	const std::vector<Cdv> order = {"sil", "a", "p1", "a", "sil"};
	for (std::size_t i = 0; i < order.size(); ++i) ph.push_back({ms(200 * long(i)), ms(200 * long(i) + 200), "", "", order[i], 0});
	auto keys = keyposes(ph, Ticks(kTicksPerSecond / 30));
	ASSERT_EQ(keys.size(), order.size());
	auto thesis = keys;
	keys[2].sample = open;
	synth.prepare(keys);
	synth.prepare(thesis);
	Synthesizer::Workspace ws;
	Image8 frame;
	Points pts;
	synth.renderFrame(keys[2].time, keys, ws, frame, pts);
	EXPECT_LT(mouthSize(scheme, pts).opening, 1e-9);
	EXPECT_LT((pts.row(scheme.mouth.corner0) - a.row(scheme.mouth.corner0)).norm(), 1e-9) << "the exemplar's own corners";
	synth.renderFrame(thesis[2].time, thesis, ws, frame, pts);
	EXPECT_LT((pts - model.alignedShapes[std::size_t(shut)]).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Coarticulation, aPredictedOpeningIsDrawnOnItsExemplar) {
	// D100: the learned mouth's exemplar is the nearest sample, and its mouth is drawn at the predicted
	// opening — the lower lip and jaw moved, the upper lip and the corners where they were.
	const FaceModel& model = smallFace();
	Scheme scheme;
	long open = -1, shut = -1;
	ASSERT_NO_FATAL_FAILURE(openAndShut(scheme, open, shut));
	const Points& a = model.alignedShapes[std::size_t(open)];
	const MouthFrame f = mouthFrame(scheme, a);
	const double was = mouthSize(scheme, a).opening;
	ASSERT_GT(was, kMinStretchOpening);
	std::vector<bool> upper(std::size_t(a.rows()), false);
	for (const auto& pair : scheme.mouth.inner) upper[std::size_t(pair.first)] = true;
	upper[std::size_t(scheme.mouth.corner0)] = upper[std::size_t(scheme.mouth.corner1)] = true;
	for (const double asked : {1.3 * was, 0.5 * was, 0.0}) {
		Points s = a;
		drawOpening(scheme, s, asked);
		EXPECT_NEAR(mouthSize(scheme, s).opening, asked, 1e-9);
		for (Eigen::Index i = 0; i < a.rows(); ++i) {
			const double below = (a.row(i) - f.centre).dot(f.down);
			if (upper[std::size_t(i)] || below <= 0) EXPECT_EQ(s.row(i), a.row(i)) << "point " << i << " (above the mouth, an upper lip or a corner) stays";
			else EXPECT_LT(std::abs((s.row(i) - a.row(i)).dot(f.across)), 1e-9) << "point " << i << " moves along the face's vertical only";
		}
		// The lower lip's middle carries the jaw: the points below the mouth's centre move as it does.
		const auto& middle = scheme.mouth.inner[scheme.mouth.inner.size() / 2];
		const double lip = (s.row(middle.second) - a.row(middle.second)).dot(f.down);
		EXPECT_NEAR(lip, (asked - was) * f.iod * ((a.row(middle.second) - a.row(middle.first)).dot(f.down) / (was * f.iod)), 1e-9);
	}
	Points wide = a;
	drawOpening(scheme, wide, 3 * was);
	EXPECT_NEAR(mouthSize(scheme, wide).opening, kMaxLipStretch * was, 1e-9) << "a warp opens a mouth only a little wider";
	Points closed = model.alignedShapes[std::size_t(shut)];
	ASSERT_LT(mouthSize(scheme, closed).opening, kMinStretchOpening);
	const Points before = closed;
	drawOpening(scheme, closed, was);
	EXPECT_EQ(closed, before) << "a shut mouth has no inside to show";
	// Planned: a predicted keypose's exemplar carries the predicted opening (in eye distances), and the
	// rendered points show it; a bilabial's is drawn shut instead (D99).
	SynthOptions o;
	Synthesizer synth(model, o);
	const auto ph = phones({{"x", "a"}, {"t", "t1"}, {"x", "a"}, {"p", "p1"}, {"x", "a"}});
	auto keys = keyposes(ph, Ticks(kTicksPerSecond / 30));
	for (Keypose& k : keys) k.mouthOpening = 0.6, k.mouthWidth = 1.0;
	ASSERT_GT(chooseMouthExemplars(model, Emotion::of("neutral"), keys), 0u);
	std::size_t drawn = 0;
	synth.prepare(keys);
	Synthesizer::Workspace ws;
	Image8 frame;
	Points pts;
	for (const Keypose& k : keys) {
		if (k.sample < 0 || bilabial(k.cdv.label())) {
			EXPECT_FALSE(k.drawnOpening) << k.cdv.label();
			continue;
		}
		ASSERT_TRUE(k.drawnOpening) << k.cdv.label();
		const double own = mouthSize(scheme, model.alignedShapes[std::size_t(k.sample)]).opening;
		const double expected = own < kMinStretchOpening ? std::min(own, *k.drawnOpening) : std::min(*k.drawnOpening, kMaxLipStretch * own);
		synth.renderFrame(k.time, keys, ws, frame, pts);
		EXPECT_NEAR(mouthSize(scheme, pts).opening, expected, 0.6 * 0.004) << k.cdv.label() << ": drawn at the prediction (in steps of 0.004 eye distances)";
		++drawn;
	}
	EXPECT_GE(drawn, 3u);
}

TEST(Coarticulation, aFaceThatOpensWiderThanSpeakersIsScaledToThemAndItsEmotionsWithIt) {
	// D105: a predicted opening is in units of a speaker's 90th percentile; a face's is its widest × 0.87
	// (D90), but never more than the speakers' own (0.148 eye distances). The synthetic face's drawn /a/
	// (0.29) made it speak 1.39 × wider than the GRID speakers.
	MouthPool neutral, happy;
	neutral.widest = 0.12, happy.widest = 0.15;
	EXPECT_NEAR(openingUnit(neutral, neutral), 0.87 * 0.12, 1e-12) << "a face within the speakers' opening keeps its own";
	EXPECT_NEAR(openingUnit(happy, neutral), 0.87 * 0.15, 1e-12);
	neutral.widest = 0.29, happy.widest = 0.348;
	EXPECT_NEAR(openingUnit(neutral, neutral), kSpeakersOpening, 1e-12) << "a posed extreme is scaled to the speakers";
	EXPECT_NEAR(openingUnit(happy, neutral), 1.2 * kSpeakersOpening, 1e-12) << "an emotion keeps its size against neutral";
	MouthPool none;  // a face with no neutral mouth: the emotion's own pool is its norm
	EXPECT_NEAR(openingUnit(happy, none), kSpeakersOpening, 1e-12);
	// Chosen: every predicted keypose is drawn at its prediction × the unit of its pool.
	const FaceModel& model = smallFace();
	Scheme scheme;
	ASSERT_TRUE(mouthScheme(model, scheme));
	const std::vector<MouthSize> size = sampleMouths(model, scheme);
	const MouthPool pool = mouthPool(model, size, "neutral");
	const auto ph = phones({{"x", "a"}, {"t", "t1"}, {"x", "a"}});
	auto keys = keyposes(ph, ms(40));
	for (Keypose& k : keys)
		if (isPhoneKeypose(ph, k)) k.mouthOpening = 0.8, k.mouthWidth = 1.0;
	ASSERT_EQ(chooseMouthExemplars(model, Emotion::of("neutral"), keys), 3u);
	for (const Keypose& k : keys)
		if (k.mouthOpening) {
			ASSERT_TRUE(k.drawnOpening) << k.cdv.label();
			EXPECT_NEAR(*k.drawnOpening, 0.8 * openingUnit(pool, pool), 1e-12) << k.cdv.label();
			EXPECT_LE(*k.drawnOpening, 0.8 * kSpeakersOpening + 1e-12);
		}
}

TEST(Coarticulation, aCdvTheFaceHasNoSampleOfTakesTheExemplarNearestThePrediction) {
	// Issue 47: a face from short takes lacks most CDVs. A predicted mouth for one it lacks is chosen from the
	// emotion's whole pool like any other (before, it kept no exemplar and renderPerformance refused the plan).
	const FaceModel& model = smallFace();
	Scheme scheme;
	ASSERT_TRUE(mouthScheme(model, scheme));
	std::string missing;
	for (const char* c : {"u", "o", "e", "ɔ", "ɛ", "i1", "s1", "f1", "k1"})
		if (missing.empty() && model.findSample("neutral", c) < 0) missing = c;
	ASSERT_FALSE(missing.empty()) << "the small face lacks some CDVs";
	const double open = mouthSize(scheme, model.alignedShapes[std::size_t(model.findSample("neutral", "a"))]).opening;
	const auto ph = phones({{"x", missing.c_str()}, {"t", "t1"}, {"x", missing.c_str()}});
	for (double asked : {4.0, 0.05}) {
		auto keys = keyposes(ph, ms(40));
		for (Keypose& k : keys)
			if (isPhoneKeypose(ph, k)) k.mouthOpening = asked, k.mouthWidth = 1.0;
		EXPECT_EQ(chooseMouthExemplars(model, Emotion::of("neutral"), keys), 3u);
		for (const Keypose& k : keys) {
			if (!k.mouthOpening || k.cdv == "t1") continue;
			ASSERT_GE(k.sample, 0);
			const double gap = mouthSize(scheme, model.alignedShapes[std::size_t(k.sample)]).opening;
			if (asked > 1) {
				EXPECT_EQ(k.sample, model.findSample("neutral", "a")) << "wide open: the open exemplar";
			} else {
				EXPECT_LT(gap, 0.5 * open) << "barely open: a nearly closed exemplar";
			}
		}
	}
}

// Live sessions (serve, talkhead live) plan with the model too: an utterance's keyposes get the exemplars a
// render of the same phones gets, bilabials shut, and an emotion change mid-utterance chooses them again.
TEST(Coarticulation, aLiveSessionShowsTheExemplarsARenderOfTheSamePhonesShows) {
	const FaceModel& model = smallFace();
	const auto m = std::make_shared<const CoarticulationModel>(trainCoarticulation(clips(), ms(10)));
	Scheme scheme;
	ASSERT_TRUE(mouthScheme(model, scheme));
	const double open = mouthSize(scheme, model.alignedShapes[std::size_t(model.findSample("neutral", "a"))]).opening;
	LiveOptions o;
	o.render.synth.width = 160;
	o.render.synth.height = 90;
	o.pauses = PauseStyle::Still;
	Utterance u;
	u.id = "u";
	u.phones = phones({{"p", "p1"}, {"a", "a"}, {"p", "p1"}, {"u", "u"}, {"t", "t1"}, {"i", "i1"}});
	PerformanceSpec spec;
	spec.phones = u.phones;
	spec.rate = o.rate;
	spec.pauses = o.pauses;
	spec.coarticulation = m;
	spec.face = &model;  // planning's last step: each predicted mouth bound to the face's exemplar
	Performance rendered = planPerformance(spec);
	auto predicted = [](const std::vector<Keypose>& keys) {
		std::vector<std::pair<std::string, long>> out;
		for (const Keypose& k : keys)
			if (k.mouthOpening) out.emplace_back(k.cdv.label(), k.sample);
		return out;
	};
	const auto rendered8 = predicted(rendered.timeline.keys);
	// The six phones, each /p/ held shut for a frame (D90: two keyposes), and before them the lips held
	// still (D70): two keyposes.
	ASSERT_EQ(rendered8.size(), 10u);
	EXPECT_TRUE(rendered.timeline.keys[0].hold && rendered.timeline.keys[1].hold);
	// A live session holds the pose it shows until the utterance starts (its own keypose there, not the
	// utterance's first), then goes to the held lips as the render does.
	const std::vector<std::pair<std::string, long>> want(rendered8.begin() + 1, rendered8.end());

	const Face face(model, m);  // the face with its coarticulation model
	LiveSession live(face, o);
	live.enqueue(u);
	EXPECT_EQ(predicted(live.keyposes()), want);
	for (const auto& [cdv, sample] : predicted(live.keyposes())) {
		ASSERT_GE(sample, 0) << cdv;
		if (cdv == "p1") {
			EXPECT_LE(mouthSize(scheme, model.alignedShapes[std::size_t(sample)]).opening, 0.1 * open) << "a bilabial shuts";
		}
	}
	// An emotion change while it speaks: the keys ahead take the new emotion and an exemplar again (this
	// face has neutral only: neutral's, the same ones).
	YuvImage frame;
	Points points;
	std::vector<LiveEvent> events;
	live.drawNext(frame, points, events);
	live.setEmotion(Expression(Emotion::of("joy")), Ticks(0));
	std::size_t joyful = 0;
	for (const Keypose& k : live.keyposes())
		if (k.mouthOpening) {
			EXPECT_GE(k.sample, 0);
			joyful += k.emotion == Emotion::of("joy");
		}
	EXPECT_GT(joyful, 0u);
	EXPECT_EQ(predicted(live.keyposes()), want);

	// Without the model: the thesis's keyposes, no predicted mouth.
	LiveSession plain(model, o);
	plain.enqueue(u);
	EXPECT_TRUE(predicted(plain.keyposes()).empty());
}
