// SPDX-License-Identifier: GPL-3.0-or-later
// Non-verbal tracks (issue 17, D55) from synthetic landmark tracks whose head motion, action units, blink
// and lost frames are known exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "base/error.h"
#include "geometry/scheme.h"
#include "synth/action_units.h"
#include "track/drive_mouth.h"
#include "track/nonverbal.h"

using namespace talkhead;

namespace {

// A frontal 68-point face: eye centres 70 px apart at y 180, brows at 160, the mouth around (200, 255).
Points face() {
	Points p(68, 2);
	for (int i = 0; i <= 16; ++i) p(i, 0) = 120 + 10 * i, p(i, 1) = 200 + 60 * std::sin(M_PI * i / 16);
	for (int k = 0; k < 5; ++k) p(17 + k, 0) = 140 + 11 * k, p(17 + k, 1) = 160 - 3 * std::sin(M_PI * k / 4);
	for (int k = 0; k < 5; ++k) p(22 + k, 0) = 216 + 11 * k, p(22 + k, 1) = 160 - 3 * std::sin(M_PI * k / 4);
	for (int k = 0; k < 4; ++k) p(27 + k, 0) = 200, p(27 + k, 1) = 178 + 14 * k;
	for (int k = 0; k < 5; ++k) p(31 + k, 0) = 188 + 6 * k, p(31 + k, 1) = 228 + (k == 2 ? 2 : 0);
	const double eye[6][2] = {{-15, 0}, {-5, -5}, {5, -5}, {15, 0}, {5, 5}, {-5, 5}};
	for (int k = 0; k < 6; ++k) p(36 + k, 0) = 165 + eye[k][0], p(36 + k, 1) = 180 + eye[k][1];
	for (int k = 0; k < 6; ++k) p(42 + k, 0) = 235 + eye[k][0], p(42 + k, 1) = 180 + eye[k][1];
	for (int k = 0; k < 12; ++k) {
		const double a = M_PI - 2 * M_PI * k / 12;
		p(48 + k, 0) = 200 + 30 * std::cos(a), p(48 + k, 1) = 255 - 10 * std::sin(a);
	}
	for (int k = 0; k < 8; ++k) {
		const double a = M_PI - 2 * M_PI * k / 8;
		p(60 + k, 0) = 200 + 22 * std::cos(a), p(60 + k, 1) = 255 - 1 * std::sin(a);
	}
	return p;
}

Points rotated(const Points& p, double degrees, double tx, double ty) {
	const double a = degrees * M_PI / 180, c = std::cos(a), s = std::sin(a);
	Points q = p;
	for (Eigen::Index i = 0; i < p.rows(); ++i) {
		const double x = p(i, 0) - 200, y = p(i, 1) - 200;
		q(i, 0) = 200 + c * x - s * y + tx, q(i, 1) = 200 + s * x + c * y + ty;
	}
	return q;
}

FrameLandmarks frame(std::int64_t n, const Points& p) {
	FrameLandmarks f;
	f.frame = n;
	f.time = ticksFromSeconds(n / 25.0);
	f.found = true;
	f.confidence = 1;
	f.points = f.raw = p;
	return f;
}

}  // namespace

TEST(NonVerbal, headActionUnitsBlinksAndGapsAreRecovered) {
	const Scheme scheme = loadScheme("ibug-68");
	const auto templates = findAuTemplates(scheme);
	ASSERT_TRUE(templates);
	const Points n = face();
	Points raised = n;
	applyActionUnits(raised, *templates, {{templates->find("AU1"), 0.8, 0}, {templates->find("AU2"), 0.5, 0}}, eyeFrame(scheme, n));
	LandmarkTrack t;
	t.source = "synthetic";
	t.info.fpsNum = 25;
	for (int k = 0; k < 200; ++k) {
		Points p = n;
		if (k >= 40 && k < 70) p = rotated(n, 5, 10, 5);   // 1.6–2.8 s: turned 5° and moved
		if (k >= 80 && k < 110) p = raised;                // 3.2–4.4 s: brows raised
		if (k >= 120 && k < 123) {                          // 4.8 s: a blink (three frames)
			const double closure = k == 121 ? 1.0 : 0.5;
			for (int e : {36, 42})
				for (auto [up, low] : {std::pair{1, 5}, std::pair{2, 4}}) p(e + up, 1) += closure * (p(e + low, 1) - p(e + up, 1)) * 0.95;
		}
		t.frames.push_back(frame(k, p));
		if (k >= 150 && k < 165) t.frames.back().found = false, t.frames.back().points.resize(0, 2), t.frames.back().raw.resize(0, 2);  // 6.0–6.6 s lost
	}
	const NonVerbalTrack nv = analyseNonVerbal(t);
	ASSERT_EQ(nv.frames.size(), 200u);
	EXPECT_EQ(nv.rate, 25);
	// The head: roll 5°, the point between the eyes (200, 180) moved by R(p − c) + c + t − p, per 70 px.
	const NonVerbalFrame& turned = nv.frames[55];
	EXPECT_NEAR(turned.roll * 180 / M_PI, 5, 1e-6);
	const double a = 5 * M_PI / 180;
	EXPECT_NEAR(turned.x, (200 - std::sin(a) * -20 + 10 - 200) / 70, 1e-6);
	EXPECT_NEAR(turned.y, (200 + std::cos(a) * -20 + 5 - 180) / 70, 1e-6);
	EXPECT_NEAR(turned.scale, 1, 1e-9);
	EXPECT_NEAR(nv.frames[20].roll, 0, 1e-9);
	// The brows: AU1 0.8 and AU2 0.5 on both sides (ridge shrinkage under 5 %), no AU4.
	auto weight = [&](std::size_t k, const std::string& au, int side) {
		for (std::size_t c = 0; c < nv.channels.size(); ++c)
			if (nv.channels[c].au == au && nv.channels[c].side == side) return nv.frames[k].au[c];
		ADD_FAILURE() << "no channel " << au;
		return -1.0;
	};
	for (int side : {-1, 1}) {
		EXPECT_NEAR(weight(95, "AU1", side), 0.8, 0.05);
		EXPECT_NEAR(weight(95, "AU2", side), 0.5, 0.05);
		EXPECT_NEAR(weight(95, "AU4", side), 0, 0.02);
		EXPECT_NEAR(weight(20, "AU1", side), 0, 1e-6);
	}
	// The blink: one. The eye opening is 0.333 open, 0.175 at frame 120 (half shut), 0.017 at 121: frame
	// 120 is the dip's middle, where the renderer's blink is half shut 37.5 ms after it starts.
	ASSERT_EQ(nv.blinks.size(), 1u);
	EXPECT_NEAR(toSeconds(nv.blinks[0]), 4.8 - 0.0375, 0.002);
	EXPECT_NEAR(weight(121, "AU43", -1), 0, 0.02);
	// The lost span: bridged between its ends (the face is neutral on both sides), one warning naming it.
	ASSERT_EQ(nv.bridged.size(), 1u);
	EXPECT_NEAR(toSeconds(nv.bridged[0].first), 6.0, 1e-9);
	EXPECT_NEAR(toSeconds(nv.bridged[0].second), 6.6, 1e-9);
	EXPECT_FALSE(nv.frames[155].valid);
	EXPECT_NEAR(nv.frames[155].roll, 0, 1e-9);
	ASSERT_EQ(nv.warnings.size(), 1u);
	EXPECT_EQ(nv.warnings[0], "no usable face from 6.00 s to 6.60 s (0.6 s): the head and face are bridged over it");
	// As controls: head channels and the AU curves at the video's rate.
	const ControlCurves c = nv.curves();
	EXPECT_EQ(c.rate, 25);
	ASSERT_EQ(c.roll.size(), 200u);
	EXPECT_NEAR(c.at(c.roll, ticksFromSeconds(55 / 25.0)), turned.roll, 1e-6);
	// No usable face: an error naming the source.
	LandmarkTrack none = t;
	for (auto& f : none.frames) f.found = false;
	try {
		analyseNonVerbal(none);
		ADD_FAILURE() << "no error";
	} catch (const Error& e) {
		EXPECT_STREQ(e.what(), "synthetic: too few frames with a face (0 of 200) to drive a face");
	}
}

TEST(NonVerbal, theMouthClassifierPicksTheNearestScaledTarget) {
	std::vector<CdvMouthTarget> targets(3);
	targets[0].cdv = "p1";  // closed
	targets[1].cdv = "a";   // open
	targets[1].delta.opening = 0.1, targets[1].delta.jaw = 0.1;
	targets[2].cdv = "u";   // rounded
	targets[2].delta.opening = 0.02, targets[2].delta.width = -0.1;
	MouthClassifier c = MouthClassifier::fromTargets(targets);
	MouthMeasures rest;
	rest.opening = 0.01, rest.width = 0.5, rest.height = 0.2, rest.jaw = 0.9;
	// A speaker whose range is twice the targets': an opening of +0.2 is the open class.
	std::vector<MouthMeasures> frames(50, rest);
	for (int k = 0; k < 10; ++k) frames[std::size_t(k)].opening += 0.2, frames[std::size_t(k)].jaw += 0.2, frames[std::size_t(20 + k)].width -= 0.2;
	c.calibrate(rest, frames);
	EXPECT_NEAR(c.scale.opening, 2, 1e-9);
	auto label = [&](const MouthMeasures& m) { return c.classes[c.classify(m)]; };
	EXPECT_EQ(label(rest), "p1");
	EXPECT_EQ(label(frames[5]), "a");
	MouthMeasures rounded = rest;
	rounded.width -= 0.2, rounded.opening += 0.04;
	EXPECT_EQ(label(rounded), "u");
	// The modified Hausdorff distance: symmetric, 0 for the same set, the mean nearest distance otherwise.
	Points a(2, 2), b(3, 2);
	a << 0, 0, 1, 0;
	b << 0, 1, 1, 1, 5, 1;
	EXPECT_NEAR(modifiedHausdorff(a, a), 0, 1e-12);
	EXPECT_NEAR(modifiedHausdorff(a, b), (1 + 1 + std::hypot(4, 1)) / 3, 1e-12);
	EXPECT_NEAR(modifiedHausdorff(b, a), modifiedHausdorff(a, b), 1e-12);
}
