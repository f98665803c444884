// SPDX-License-Identifier: GPL-3.0-or-later
// Faces from real video (issue 10): one-euro filter, .pts round trip, mouth measures, lip-sync measures,
// and dlib on the franck stills (skipped without ../shared/data).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "base/error.h"
#include "corpus/corpus.h"
#include "media/image_io.h"
#include "test_support.h"
#include "track/compare.h"
#include "track/from_video.h"
#include "geometry/scheme.h"
#include "track/landmarks.h"

using namespace talkhead;

namespace {

// A plausible frontal 68-point face: eye corners 100 px apart, a mouth whose inner gap is `gap` px.
Points face(double gap, double dx = 0, double dy = 0) {
	Points p(68, 2);
	for (int i = 0; i < 68; ++i) p(i, 0) = 200 + 3 * i, p(i, 1) = 200;  // filler
	for (int i = 0; i <= 16; ++i) p(i, 0) = 120 + 10 * i, p(i, 1) = 200 + 60 * std::sin(M_PI * i / 16);
	p(36, 0) = 150, p(36, 1) = 180, p(45, 0) = 250, p(45, 1) = 180, p(39, 0) = 180, p(39, 1) = 180, p(42, 0) = 220, p(42, 1) = 180;
	p(30, 0) = 200, p(30, 1) = 220, p(33, 0) = 200, p(33, 1) = 230;
	p(8, 0) = 200, p(8, 1) = 300;
	// Outer lip 48–59, inner 60–67 around (200, 255).
	for (int k = 0; k < 12; ++k) {
		const double a = M_PI - 2 * M_PI * k / 12;
		p(48 + k, 0) = 200 + 30 * std::cos(a), p(48 + k, 1) = 255 - (10 + gap / 2) * std::sin(a);
	}
	for (int k = 0; k < 8; ++k) {
		const double a = M_PI - 2 * M_PI * k / 8;
		p(60 + k, 0) = 200 + 22 * std::cos(a), p(60 + k, 1) = 255 - (gap / 2) * std::sin(a);
	}
	p.col(0).array() += dx;
	p.col(1).array() += dy;
	return p;
}

LandmarkTrack trackOf(const std::vector<double>& gaps, double fps = 25) {
	LandmarkTrack t;
	t.info.fpsNum = int(fps), t.info.fpsDen = 1;
	for (std::size_t i = 0; i < gaps.size(); ++i) {
		FrameLandmarks f;
		f.frame = std::int64_t(i);
		f.time = ticksFromSeconds(double(i) / fps);
		f.found = true;
		f.confidence = 1;
		f.points = f.raw = face(gaps[i]);
		t.frames.push_back(f);
	}
	return t;
}

// Both eyes 30 px wide at y 180, the lids `half` px above and below it (eye aspect 2 × half / 30).
void lids(Points& p, double half) {
	for (const auto& [first, x0] : {std::pair{36, 150.0}, std::pair{42, 220.0}}) {
		p(first, 0) = x0, p(first + 3, 0) = x0 + 30;
		p(first, 1) = p(first + 3, 1) = 180;
		p(first + 1, 0) = p(first + 5, 0) = x0 + 10, p(first + 2, 0) = p(first + 4, 0) = x0 + 20;
		p(first + 1, 1) = p(first + 2, 1) = 180 - half, p(first + 5, 1) = p(first + 4, 1) = 180 + half;
	}
}

}  // namespace

TEST(OneEuroFilter, passesAConstantAndFollowsAStepWithLittleLagWhenFast) {
	OneEuroFilter f(1.0, 0.0, 1.0);
	for (int i = 0; i < 10; ++i) EXPECT_DOUBLE_EQ(f(3.0, 0.04), 3.0);
	// beta = 0: a first-order low-pass at 1 Hz; after 1 s of a unit step the output is 1 − (1 − α)^25.
	OneEuroFilter lp(1.0, 0.0, 1.0);
	lp(0.0, 0.04);
	double y = 0;
	for (int i = 0; i < 25; ++i) y = lp(1.0, 0.04);
	const double alpha = 1.0 / (1.0 + 1.0 / (2 * M_PI * 1.0) / 0.04);
	EXPECT_NEAR(y, 1 - std::pow(1 - alpha, 25), 1e-12);
	// A large beta lets a fast step through almost at once.
	OneEuroFilter fast(1.0, 100.0, 1.0);
	fast(0.0, 0.04);
	fast(1.0, 0.04);
	EXPECT_GT(fast(1.0, 0.04), 0.9);
}

TEST(OneEuroFilter, removesJitterFromANoisyConstant) {
	std::mt19937 rng(3);
	std::normal_distribution<double> noise(0, 1);
	OneEuroFilter f(1.0, 0.0, 1.0);
	double rawVar = 0, outVar = 0;
	for (int i = 0; i < 2000; ++i) {
		const double x = 10 + noise(rng), y = f(x, 0.04);
		if (i > 100) rawVar += (x - 10) * (x - 10), outVar += (y - 10) * (y - 10);
	}
	EXPECT_LT(outVar, 0.3 * rawVar);
}

TEST(PtsWriter, roundTripsExactly) {
	Points p = face(7.25, 0.125, -3.5);
	p(5, 0) = 0.001;
	const std::string dir = test::tempDir("pts");
	writePts(dir + "/a.pts", p);
	writeImage(dir + "/a.png", test::testPattern(400, 400));  // readPts wants the image beside
	std::ifstream in(dir + "/a.pts");
	const std::string first((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
	EXPECT_EQ(first.substr(0, 26), "version: 1\nn_points: 68\n{\n");
	const CorpusEntry e = readPts(dir + "/a.pts");
	ASSERT_EQ(e.points.rows(), 68);
	EXPECT_EQ(ptsText(e.points), first);
	EXPECT_NEAR(e.points(5, 0), 0.001, 1e-9);
}

TEST(MouthMeasures, areInEyeDistancesAndIgnoreRollAndPosition) {
	const MouthMeasures m = mouthMeasures(face(10));
	EXPECT_NEAR(m.width, 60.0 / 100, 1e-9);
	EXPECT_NEAR(m.jaw, (300.0 - 230) / 100, 1e-9);
	EXPECT_GT(m.opening, 0.05);
	EXPECT_LT(mouthMeasures(face(0)).opening, 1e-9);
	// Rotated by 10° and moved: the same measures.
	Points r = face(10, 40, -20);
	const double c = std::cos(0.17), s = std::sin(0.17);
	for (Eigen::Index i = 0; i < r.rows(); ++i) {
		const double x = r(i, 0), y = r(i, 1);
		r(i, 0) = c * x - s * y, r(i, 1) = s * x + c * y;
	}
	const MouthMeasures q = mouthMeasures(r);
	for (int k = 0; k < 4; ++k) EXPECT_NEAR(q[k], m[k], 1e-9);
	EXPECT_NEAR(headRoll(r), 0.17, 1e-9);
}

TEST(LipSync, aTrackAgainstItselfCorrelatesFullyAndAShiftedOneAtItsLag) {
	std::vector<double> gaps;
	for (int i = 0; i < 100; ++i) gaps.push_back(10 + 8 * std::sin(i * 0.4) + 3 * std::sin(i * 1.3));
	const LandmarkTrack a = trackOf(gaps);
	LipSyncReport r = compareLipSync(a, a);
	EXPECT_NEAR(r.r0, 1.0, 1e-9);
	EXPECT_NEAR(r.lmd, 0.0, 1e-9);
	EXPECT_DOUBLE_EQ(r.coverageSynth, 1.0);
	EXPECT_EQ(r.samples, std::size_t(400));  // 4 s at 100 Hz
	// The synthesized mouth 2 frames (80 ms) late: r at lag 0 drops, the best lag is +80 ms.
	std::vector<double> late(gaps);
	late.insert(late.begin(), 2, gaps.front());
	late.resize(gaps.size());
	r = compareLipSync(trackOf(late), a);
	EXPECT_LT(r.r0, 0.9);
	EXPECT_NEAR(r.bestLagMs, 80, 10);
	EXPECT_GT(r.bestR, 0.97);
}

TEST(LipSync, lostFramesAreLeftOutNotInvented) {
	std::vector<double> gaps;
	for (int i = 0; i < 50; ++i) gaps.push_back(10 + 8 * std::sin(i * 0.5));
	LandmarkTrack a = trackOf(gaps);
	for (int i = 20; i < 30; ++i) a.frames[std::size_t(i)].found = false, a.frames[std::size_t(i)].points.resize(0, 2);
	const LipSyncReport r = compareLipSync(a, trackOf(gaps));
	EXPECT_NEAR(r.coverageSynth, 0.8, 1e-12);
	EXPECT_LT(r.samples, std::size_t(200 - 35));
	EXPECT_NEAR(r.r0, 1.0, 1e-9);
}

TEST(Pearson, knownValues) {
	EXPECT_NEAR(pearson({1, 2, 3, 4}, {2, 4, 6, 8}), 1.0, 1e-12);
	EXPECT_NEAR(pearson({1, 2, 3, 4}, {8, 6, 4, 2}), -1.0, 1e-12);
	EXPECT_NEAR(pearson({1, 2, 3, 4, 5}, {1, 3, 2, 5, 4}), 0.8, 1e-12);
	EXPECT_TRUE(std::isnan(pearson({1, 1, 1}, {1, 2, 3})));
}

TEST(DlibLandmarks, findsAFaceAnd68PointsInEveryFranckStill) {
	const std::string dir = test::sharedData() + "/franck";
	if (!std::filesystem::exists(dir)) GTEST_SKIP() << "franck stills not found in " << dir;
	NullProgress quiet;
	const LandmarkTrack t = landmarkImages(dir, TrackOptions{}, quiet);
	ASSERT_EQ(t.frames.size(), 11u);
	FaceLandmarker lm;
	for (const auto& f : t.frames) {
		ASSERT_TRUE(f.found) << f.name;
		ASSERT_EQ(f.points.rows(), 68);
		EXPECT_GT(f.confidence, 0.5) << f.name;
		// The mouth lies inside the face box the detector finds, below the eyes.
		const auto boxes = lm.detect(toGrey(readImage(dir + "/" + f.name)), 0);
		ASSERT_FALSE(boxes.empty()) << f.name;
		const FaceBox& b = boxes.front();
		for (int i = 48; i < 68; ++i) {
			EXPECT_GT(f.points(i, 0), b.left) << f.name << " point " << i;
			EXPECT_LT(f.points(i, 0), b.right) << f.name << " point " << i;
			EXPECT_GT(f.points(i, 1), 0.5 * (f.points(36, 1) + f.points(45, 1))) << f.name;
			EXPECT_LT(f.points(i, 1), b.bottom + 0.1 * b.height()) << f.name;
		}
	}
}

TEST(DlibLandmarks, aMissingModelIsOneClearError) {
	TrackOptions o;
	o.modelPath = "/nonexistent/shape_predictor_68_face_landmarks.dat";
	const std::string e = test::errorOf([&] { FaceLandmarker lm(o.modelPath); });
	EXPECT_NE(e.find("/nonexistent/shape_predictor_68_face_landmarks.dat"), std::string::npos) << e;
	EXPECT_NE(e.find("libdlib-data"), std::string::npos) << e;
}

TEST(LandmarksTsv, roundTripsAndNamesFileAndLineOfBadRows) {
	LandmarkTrack t;
	for (int i = 0; i < 3; ++i) {
		FrameLandmarks f;
		f.frame = 10 + i;
		f.time = ticksFromSeconds(0.04 * (10 + i));
		f.found = i != 1;
		f.detected = i == 0;
		f.confidence = f.found ? 0.875 : 0;
		if (f.found) f.points = f.raw = face(4 + i);
		t.frames.push_back(f);
	}
	const std::string dir = test::tempDir("lmtsv");
	const std::string text = landmarksTsv(t);
	std::ofstream(dir + "/a.tsv") << text;
	const LandmarkTrack back = readLandmarksTsv(dir + "/a.tsv");
	ASSERT_EQ(back.frames.size(), 3u);
	EXPECT_FALSE(back.frames[1].found);
	EXPECT_TRUE(back.frames[0].detected);
	EXPECT_EQ(landmarksTsv(back), text);
	std::ofstream(dir + "/b.tsv") << "frame\ttime\n";
	EXPECT_NE(test::errorOf([&] { readLandmarksTsv(dir + "/b.tsv"); }).find(dir + "/b.tsv:1: not a talkhead landmarks.tsv"), std::string::npos);
	std::ofstream(dir + "/c.tsv") << text.substr(0, text.find('\n') + 1) << "1\t0.04\ttracked\t0.9\t1\t2\n";
	EXPECT_NE(test::errorOf([&] { readLandmarksTsv(dir + "/c.tsv"); }).find(dir + "/c.tsv:2: expected 140 columns, found 6"), std::string::npos);
	std::ofstream(dir + "/d.tsv") << text.substr(0, text.find('\n') + 1) << "x\t0.04\tlost\t0" << std::string(136, '\t') << "\n";
	EXPECT_NE(test::errorOf([&] { readLandmarksTsv(dir + "/d.tsv"); }).find(dir + "/d.tsv:2: malformed number"), std::string::npos);
	// Not-a-number and absurd coordinates (found by fuzzing, issue 15): errors, not values written back cut off.
	const std::string header = text.substr(0, text.find('\n') + 1);
	const std::string row = text.substr(header.size(), text.find('\n', header.size()) + 1 - header.size());
	for (const std::string& bad : {std::string("nan"), std::string("1e113"), std::string("12abc")}) {
		std::string r = row;
		const std::size_t at = [&] {  // the first point's x: after frame, time, state, confidence
			std::size_t p = 0;
			for (int k = 0; k < 4; ++k) p = r.find('\t', p) + 1;
			return p;
		}();
		r.replace(at, r.find('\t', at) - at, bad);
		std::ofstream(dir + "/e.tsv") << header << r;
		const std::string e = test::errorOf([&] { readLandmarksTsv(dir + "/e.tsv"); });
		EXPECT_TRUE(e.find(dir + "/e.tsv:2: malformed number") != std::string::npos || e.find(dir + "/e.tsv:2: number out of range") != std::string::npos)
		    << bad << ": " << e;
	}
}

// Issue 46: one dialect written (points named as ibug-68.scheme names them), the older ones still read: a
// tracker's x0 y0 … and a render's --landmarks-out without status and confidence (of an ibug-68 face);
// a render of another scheme cannot drive a tracker's reader.
TEST(LandmarksTsv, oneDialectWrittenTheOlderOnesRead) {
	LandmarkTrack t;
	FrameLandmarks f;
	f.frame = 3, f.time = ticksFromSeconds(0.12), f.found = true, f.confidence = 0.5;
	f.points = f.raw = face(5);
	t.frames.push_back(f);
	const std::string text = landmarksTsv(t);
	EXPECT_EQ(text.rfind("frame\ttime\tstatus\tconfidence\tJAW0_x\tJAW0_y\tJAW1_x", 0), 0u) << text.substr(0, 80);
	const std::string dir = test::tempDir("lmdialects");
	const std::string row = text.substr(text.find('\n') + 1);
	// The older tracker dialect: the same rows under x0 y0 … x67 y67.
	std::string old = "frame\ttime\tstatus\tconfidence";
	for (int i = 0; i < kIbugPoints; ++i) old += "\tx" + std::to_string(i) + "\ty" + std::to_string(i);
	std::ofstream(dir + "/old.tsv") << old << "\n" << row;
	EXPECT_EQ(landmarksTsv(readLandmarksTsv(dir + "/old.tsv")), text);
	// An older render's: no status or confidence, the points named, here in another column order.
	const Scheme ibug = loadScheme("ibug-68");
	std::string render = "frame\ttime";
	for (int i = kIbugPoints - 1; i >= 0; --i) render += "\t" + ibug.pointNames[std::size_t(i)] + "_x\t" + ibug.pointNames[std::size_t(i)] + "_y";
	render += "\n3\t0.120000";
	for (int i = kIbugPoints - 1; i >= 0; --i) render += "\t" + std::to_string(f.points(i, 0)) + "\t" + std::to_string(f.points(i, 1));
	std::ofstream(dir + "/render.tsv") << render << "\n";
	const LandmarkTrack r = readLandmarksTsv(dir + "/render.tsv");
	ASSERT_EQ(r.frames.size(), 1u);
	EXPECT_TRUE(r.frames[0].found);
	EXPECT_NEAR(r.frames[0].points(30, 0), f.points(30, 0), 1e-3);
	EXPECT_NEAR(r.frames[0].points(67, 1), f.points(67, 1), 1e-3);
	std::ofstream(dir + "/other.tsv") << "frame\ttime\tCIUM_x\tCIUM_y\n0\t0\t1\t2\n";
	EXPECT_NE(test::errorOf([&] { readLandmarksTsv(dir + "/other.tsv"); }).find(dir + "/other.tsv:1: has no column for the iBUG point JAW0"), std::string::npos);
}

TEST(FromVideo, framesWithTheEyesHalfShutAreNeverChosen) {
	// D71: 40 frames, the lids 10 px apart (eye aspect 0.33); frames 0–11 hold the lips shut and still,
	// the mouth a baseface wants, and in 0–5 the eyes are mid-blink (people blink where the mouth is
	// still); then the mouth opens and closes.
	auto blink = [](std::size_t i) { return i <= 5; };
	std::vector<double> gaps;
	for (std::size_t i = 0; i < 40; ++i) gaps.push_back(i <= 11 ? 0 : 4 + 8 * double(i % 5));
	LandmarkTrack t = trackOf(gaps);
	for (std::size_t i = 0; i < t.frames.size(); ++i) {
		lids(t.frames[i].points, blink(i) ? 1 : 5);
		t.frames[i].raw = t.frames[i].points;
	}
	EXPECT_NEAR(eyeAspect(t.frames[20].points), 10.0 / 30, 1e-12);
	EXPECT_NEAR(eyeAspect(t.frames[3].points), 2.0 / 30, 1e-12);
	FromVideoOptions o;
	const std::int64_t rest = mostNeutralFrame(t, o);
	EXPECT_FALSE(blink(std::size_t(rest))) << rest;
	EXPECT_EQ(gaps[std::size_t(rest)], 0) << rest;  // the shut lips with the eyes open
	for (const ChosenFrame& c : selectByShape(t, loadCdvMouthTargets(), o).entries) EXPECT_FALSE(blink(std::size_t(c.frame))) << c.cdv;
	o.minEyeOpening = 0;  // any eyes: the mid-blink frames become candidates, but their lids still cost (issue 47)
	const std::int64_t any = mostNeutralFrame(t, o);
	EXPECT_FALSE(blink(std::size_t(any))) << any;
	EXPECT_EQ(gaps[std::size_t(any)], 0) << any;
}

TEST(FromVideo, theUsualCornerLiftIsTheMedianAtThatOpeningWithEqualOpeningsTogether) {
	// D73: 100 frames, the corners rising with the opening (lift = opening / 2) but every 4th lifted 0.05
	// more (a smile): the usual lift at an opening is the plain one, and the scale is half the 5th–95th
	// percentile range of the lifts off it (the smiles are a quarter: 95th 0.05, 5th 0).
	std::vector<double> o, l;
	for (int i = 0; i < 100; ++i) o.push_back(0.002 * i), l.push_back(0.001 * i + (i % 4 == 0 ? 0.05 : 0));
	const UsualLift u(o, l);
	EXPECT_NEAR(u.at(0.1), 0.05, 0.005);  // a quarter of the window smiles: the median moves up a little
	EXPECT_NEAR(u.at(0.15), 0.075, 0.005);
	EXPECT_NEAR(u.spread(), 0.025, 0.003);
	// 60 shut mouths (opening 0) whose lifts run 0 … 0.059, and open ones: the shut mouths' usual is their
	// median, not the lowest 25 of them.
	std::vector<double> so(60, 0.0), sl;
	for (int i = 0; i < 60; ++i) sl.push_back(0.001 * i);
	for (int i = 0; i < 100; ++i) so.push_back(0.1 + 0.001 * i), sl.push_back(-0.2);
	EXPECT_NEAR(UsualLift(so, sl).at(0), 0.0295, 1e-9);
	// The measure itself: corners 5 px above the inner lips' centre, eye corners 100 px apart.
	Points p = face(0);
	EXPECT_NEAR(cornerLift(p), 0, 1e-9);
	p(48, 1) -= 5, p(54, 1) -= 5;
	EXPECT_NEAR(cornerLift(p), 0.05, 1e-9);
	EXPECT_THROW(UsualLift({0.1}, {}), std::logic_error);
}

TEST(FromVideo, aSmileCaughtInAFrameIsNotChosenOverTheSameMouthWithoutIt) {
	// D73: 80 frames whose mouths open and close; every 4th has the same mouth with its corners 5 px up (a
	// smile: 0.05 eye distances above this person's usual) and a more confident track, so without the
	// corners' cost it wins every tie. No open CDV takes a smiling frame; a shut one (/p b m/, the rest)
	// chooses by closure alone.
	std::vector<double> gaps;
	for (std::size_t i = 0; i < 80; ++i) gaps.push_back(i % 8 == 1 ? 0 : 2 + 3 * double(i % 8));
	LandmarkTrack t = trackOf(gaps);
	auto smiles = [](std::int64_t i) { return i % 4 == 0; };
	for (FrameLandmarks& f : t.frames) {
		f.confidence = smiles(f.frame) ? 1.0 : 0.9;
		if (smiles(f.frame)) f.points(48, 1) -= 5, f.points(54, 1) -= 5;
		f.raw = f.points;
	}
	std::size_t open = 0;
	for (const ChosenFrame& c : selectByShape(t, loadCdvMouthTargets(), FromVideoOptions{}).entries) {
		if (c.cdv == "p1" || c.cdv == "p2" || c.cdv == "sil") continue;
		++open;
		EXPECT_FALSE(smiles(c.frame)) << c.cdv << " took frame " << c.frame;
	}
	EXPECT_GT(open, 20u);
}

TEST(FromVideo, theBlinkKeptIsTheMostShutFrontalFrameWithTheMouthAtRestAndNoneWithout) {
	// Issue 47: 60 frames, the lids 10 px apart (eye aspect 0.33) but for three blinks — frames 4–6 with the
	// mouth shut (frame 5 the most shut), 21–23 while speaking, 40–42 with the head turned.
	std::vector<double> gaps;
	for (std::size_t i = 0; i < 60; ++i) gaps.push_back(i < 12 ? 0 : 4 + 8 * double(i % 5));
	auto trackWith = [&](const std::vector<std::pair<std::size_t, double>>& shut, bool turnAt40) {
		LandmarkTrack t = trackOf(gaps);
		for (std::size_t i = 0; i < t.frames.size(); ++i) {
			double half = 5;
			for (const auto& [f, h] : shut)
				if (f == i) half = h;
			lids(t.frames[i].points, half);
			if (turnAt40 && i >= 38 && i <= 44) t.frames[i].points(30, 0) += 30, t.frames[i].points(33, 0) += 30;  // nose: the head turned
			t.frames[i].raw = t.frames[i].points;
		}
		return t;
	};
	FromVideoOptions o;
	const LandmarkTrack blinks = trackWith({{4, 1.5}, {5, 0.5}, {6, 1.5}, {21, 0.2}, {22, 0.2}, {23, 0.2}, {40, 0.1}, {41, 0.1}, {42, 0.1}}, true);
	const std::int64_t rest = mostNeutralFrame(blinks, o);
	const auto shut = closedEyesFrame(blinks, rest, o);
	ASSERT_TRUE(shut.has_value());
	EXPECT_EQ(shut->frame, 5);  // not the more shut ones while speaking or turned
	EXPECT_EQ(shut->emotion, "-");
	EXPECT_EQ(shut->cdv, "closed-eyes");
	EXPECT_NEAR(eyeAspect(shut->points), 1.0 / 30, 1e-12);
	// The plan keeps it beside its chosen frames, none of which is a blink.
	const VideoCorpusPlan plan = selectByShape(blinks, loadCdvMouthTargets(), o);
	ASSERT_TRUE(plan.closedEyes.has_value());
	EXPECT_EQ(plan.closedEyes->frame, 5);
	for (const ChosenFrame& c : plan.entries) EXPECT_GT(eyeAspect(c.points), 0.3) << c.frame;
	// With any eyes allowed (--min-eye-opening 0) a shut frame may be a viseme too: then it is not kept twice.
	FromVideoOptions any = o;
	any.minEyeOpening = 0;
	const VideoCorpusPlan anyPlan = selectByShape(blinks, loadCdvMouthTargets(), any);
	for (const ChosenFrame& c : anyPlan.entries) EXPECT_FALSE(anyPlan.closedEyes && anyPlan.closedEyes->frame == c.frame) << c.frame;
	// No usable blink: none kept (blinks then draw the lid); nor when asked for none.
	EXPECT_FALSE(closedEyesFrame(trackWith({{21, 0.2}, {22, 0.2}, {40, 0.1}}, true), rest, o).has_value());
	EXPECT_FALSE(closedEyesFrame(trackWith({{4, 2.5}}, false), rest, o).has_value());  // half shut (0.17 > 0.4 × 0.33)
	o.maxShutEyes = 0;
	EXPECT_FALSE(closedEyesFrame(blinks, rest, o).has_value());
}

TEST(FromVideo, theBasefaceIsAShutMouthWithoutASmileOrASquint) {
	// Issue 47: 80 frames; 0–11 hold the lips shut and still (what a baseface wants): 0–3 in a closed-mouth
	// smile (corners 5 px up), 4–7 with the eyes narrowed by a fifth (the lids 4 px from the eye line
	// instead of 5: a smile's squint, well above the 0.7 gate), both more confidently tracked than 8–11, so
	// without the corners' and the eyes' costs the baseface is one of them; then the mouth opens and closes.
	std::vector<double> gaps;
	for (std::size_t i = 0; i < 80; ++i) gaps.push_back(i <= 11 || i % 8 == 1 ? 0 : 2 + 3 * double(i % 8));
	LandmarkTrack t = trackOf(gaps);
	for (FrameLandmarks& f : t.frames) {
		lids(f.points, f.frame >= 4 && f.frame <= 7 ? 4 : 5);
		f.confidence = f.frame <= 7 ? 1.0 : 0.9;
		if (f.frame <= 3) f.points(48, 1) -= 5, f.points(54, 1) -= 5;
		f.raw = f.points;
	}
	const std::int64_t rest = mostNeutralFrame(t, FromVideoOptions{});
	EXPECT_GE(rest, 8);
	EXPECT_LE(rest, 11);
}
