// SPDX-License-Identifier: GPL-3.0-or-later
// The face's matte for video with alpha (render/matte.h, D65).
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/scheme.h"
#include "render/matte.h"

using namespace talkhead;

namespace {

// The ibug-68 scheme's points on a face: an ellipse of outline points (the jaw, ear to ear through the
// chin, the lower half), brows 40 px above the eye line, the rest inside.
Points ibugFace(const Scheme& s, double cx, double cy) {
	Points p(s.pointCount(), 2);
	for (int i = 0; i < s.pointCount(); ++i) p.row(i) << cx, cy;  // inner points at the centre
	for (int i = 0; i <= 16; ++i) {
		const double t = M_PI * i / 16;  // JAW0 at the subject's right ear root, JAW8 the chin
		p.row(s.indexOf("JAW" + std::to_string(i))) << cx - 80 * std::cos(t), cy + 100 * std::sin(t);
	}
	for (const BrowSpec& b : s.brows)
		for (std::size_t k = 0; k < b.points.size(); ++k) p.row(b.points[k]) << cx + (b.name == "right" ? -1 : 1) * (10 + 12.0 * double(k)), cy - 40;
	return p;
}

}  // namespace

TEST(FaceMatte, opaqueOnTheFaceTransparentAwayFromItFeatheredBetweenAndAForeheadWhereTheSchemeHasNone) {
	const Scheme ibug = loadScheme("ibug-68");
	ASSERT_EQ(ibug.brows.size(), 2u);
	const Points p = ibugFace(ibug, 160, 100);
	const FaceMatte matte(ibug);
	std::vector<std::uint8_t> a;
	matte.draw(p, 320, 240, a);
	ASSERT_EQ(a.size(), 320u * 240u);
	auto at = [&](int x, int y) { return int(a[std::size_t(y) * 320 + std::size_t(x)]); };
	const double sigma = matte.feather(160);
	EXPECT_NEAR(sigma, 3.2, 1e-9);  // 2 % of the face's width
	EXPECT_EQ(at(160, 100), 255);
	for (int i = 0; i <= 16; ++i) {  // the outline itself is opaque (pushed out by 2σ)
		const int x = int(std::lround(p(ibug.indexOf("JAW" + std::to_string(i)), 0))), y = int(std::lround(p(ibug.indexOf("JAW" + std::to_string(i)), 1)));
		EXPECT_GE(at(std::clamp(x, 0, 319), std::clamp(y, 0, 239)), 240) << "JAW" << i;
	}
	EXPECT_EQ(at(2, 2), 0);
	EXPECT_EQ(at(317, 237), 0);
	EXPECT_EQ(at(60, 100), 0);  // 20 px beyond the widest outline point, > 4σ past the pushed-out edge
	// A forehead: nothing of the scheme lies above the brows (y 60), so half the brow-to-chin height (140 px)
	// above them is face: y 60 − 70 = −10, out of the frame: the top row above the brows is opaque.
	EXPECT_EQ(at(160, 5), 255);
	EXPECT_EQ(at(160, 30), 255);
	// Feathered: along the row through the centre, from the face out, alpha falls monotonically over
	// several pixels (not a hard cut).
	int soft = 0;
	for (int x = 160; x > 0; --x) {
		EXPECT_LE(at(x - 1, 100), at(x, 100)) << x;
		soft += at(x, 100) > 5 && at(x, 100) < 250;
	}
	EXPECT_GE(soft, 6);
	EXPECT_LE(soft, 30);
	// The same points give the same matte; another feather another edge.
	std::vector<std::uint8_t> again;
	matte.draw(p, 320, 240, again);
	EXPECT_EQ(a, again);
	MatteOptions wide;
	wide.feather = 10;
	FaceMatte(ibug, wide).draw(p, 320, 240, again);
	int softWide = 0;
	for (int x = 160; x > 0; --x) softWide += again[100 * 320 + std::size_t(x)] > 5 && again[100 * 320 + std::size_t(x)] < 250;
	EXPECT_GT(softWide, 2 * soft);
	// A scheme without brows gets no forehead: the matte ends above the topmost point (the brows' y 60) within 4σ.
	Scheme bare = ibug;
	bare.brows.clear();
	FaceMatte(bare).draw(p, 320, 240, again);
	EXPECT_EQ(again[30 * 320 + 160], 0);
	EXPECT_EQ(again[100 * 320 + 160], 255);
}

TEST(FaceMatte, aFaceLeavingTheFrameOrTooFewPointsIsNoError) {
	const Scheme ibug = loadScheme("ibug-68");
	const FaceMatte matte(ibug);
	std::vector<std::uint8_t> a;
	matte.draw(ibugFace(ibug, -500, -500), 64, 48, a);  // far outside: all transparent
	EXPECT_EQ(a, std::vector<std::uint8_t>(64 * 48, 0));
	matte.draw(Points(2, 2), 64, 48, a);
	EXPECT_EQ(a, std::vector<std::uint8_t>(64 * 48, 0));
}

TEST(Scheme, aSchemeReadFromAModelGetsItsEyesBrowsAndMouthFromTheShippedSchemeOfItsNameAndPoints) {
	const Scheme shipped = loadScheme("ibug-68");
	Scheme s = shipped;
	s.eyes.clear(), s.brows.clear(), s.mouth = {};
	completeSchemeParts(s);
	EXPECT_EQ(s.eyes.size(), 2u);
	EXPECT_EQ(s.brows.size(), 2u);
	EXPECT_EQ(s.mouth.inner, shipped.mouth.inner);
	Scheme other = shipped;  // other points under the name: nothing taken
	other.eyes.clear(), other.brows.clear(), other.mouth = {};
	other.pointNames.back() = "EXTRA";
	completeSchemeParts(other);
	EXPECT_TRUE(other.eyes.empty() && other.brows.empty() && other.mouth.empty());
	Scheme path = other;  // a name that is a path is never read
	path.pointNames = shipped.pointNames;
	path.name = "../schemes/ibug-68";
	completeSchemeParts(path);
	EXPECT_TRUE(path.eyes.empty());
}
