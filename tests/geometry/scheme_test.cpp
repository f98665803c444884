// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"
#include "geometry/scheme.h"

using namespace talkhead;

namespace {
// The error a scheme text gives, or "no error".
std::string message(const std::string& text) {
	try {
		parseScheme(text, "x.scheme");
	} catch (const Error& e) {
		return e.what();
	}
	return "no error";
}
}  // namespace

TEST(Scheme, shippedSchemesLoad) {
	struct Expect {
		const char* name;
		int points;
	} expect[] = {{"ch-unicamp-56", 56}, {"ibug-68", 68}, {"imm-73", 73}};
	for (const auto& e : expect) {
		Scheme s = loadScheme(e.name);
		EXPECT_EQ(s.name, e.name);
		EXPECT_EQ(s.pointCount(), e.points);
		ASSERT_EQ(s.regions.size(), 3u);
		EXPECT_EQ(s.regions[0].name, "face");
		EXPECT_EQ(s.regions[1].name, "cheeks_lips");
		EXPECT_EQ(s.regions[2].name, "lips");
	}
}

TEST(Scheme, chUnicampFollowsTheThesisColumnOrderAndWeights) {
	Scheme s = loadScheme("ch-unicamp-56");
	EXPECT_EQ(s.pointNames.front(), "RM2");
	EXPECT_EQ(s.pointNames[10], "REB1");
	EXPECT_EQ(s.pointNames[34], "HC");
	EXPECT_EQ(s.pointNames.back(), "LM5");
	// Thesis §4.1.1: anchors 1.0 (ears, nose tip, eye corners, top of head), mouth 0.2.
	EXPECT_EQ(s.weights(s.indexOf("REAR1")), 1.0);
	EXPECT_EQ(s.weights(s.indexOf("HC")), 1.0);
	EXPECT_EQ(s.weights(s.indexOf("REYE1")), 1.0);
	EXPECT_EQ(s.weights(s.indexOf("REB2")), 0.5);
	for (const char* mouth : {"RM1", "RM2", "RM3", "RM4", "RM5", "LM1", "CUM", "CLM", "VMR", "VML", "CIUM", "CILM"})
		EXPECT_EQ(s.weights(s.indexOf(mouth)), 0.2) << mouth;
}

TEST(Scheme, malformedFilesNameFileAndLine) {
	EXPECT_EQ(message("scheme s\nclass a 1\npoint P b\n"), "x.scheme:3: unknown weight class 'b' (declare it with 'class' first)");
	EXPECT_EQ(message("scheme s\nclass a 1\npoint P a\npoint Q a\npoint R a\nregion r : P Q Z\n"), "x.scheme:6: region 'r': unknown point 'Z'");
	EXPECT_EQ(message("scheme s\nclass a 1\npoint P a\npoint P a\n"), "x.scheme:4: duplicate point name 'P'");
	EXPECT_EQ(message("scheme s\nbogus\n"), "x.scheme:2: unknown keyword 'bogus' (expected scheme, class, point, region, eye, brow or mouth)");
	const std::string base = "scheme s\nclass a 1\npoint P a\npoint Q a\npoint R a\npoint S a\nregion r : P Q R\n";
	EXPECT_EQ(message(base + "eye e corners P Q upper R\n"), "x.scheme:8: eye 'e': needs 2 corners and at least one upper and one lower lid point");
	EXPECT_EQ(message(base + "eye e corners P Q upper R lower Z\n"), "x.scheme:8: eye 'e': unknown point 'Z'");
	const Scheme eyed = parseScheme(base + "eye e corners P Q upper R lower S\n", "x.scheme");
	ASSERT_EQ(eyed.eyes.size(), 1u);
	EXPECT_EQ(eyed.eyes[0].corner0, 0);
	EXPECT_EQ(eyed.eyes[0].upper, std::vector<int>{2});
	EXPECT_EQ(eyed.eyes[0].lower, std::vector<int>{3});
	// The shipped schemes name both eyes.
	for (const std::string name : {"ch-unicamp-56", "ibug-68", "imm-73"}) EXPECT_EQ(loadScheme(name).eyes.size(), 2u) << name;
	EXPECT_EQ(message(base + "brow b : P\n"), "x.scheme:8: brow 'b': needs at least 2 points");
	for (const std::string name : {"ch-unicamp-56", "ibug-68"}) EXPECT_EQ(loadScheme(name).brows.size(), 2u) << name;
	// The mouth (D62): facing inner-lip pairs and the corners; the shipped schemes have one, in the right order.
	EXPECT_EQ(message(base + "mouth inner P:Z corners Q R\n"), "x.scheme:8: mouth: bad inner pair 'P:Z' (expected UPPER:LOWER, two points of the scheme)");
	EXPECT_EQ(message(base + "mouth inner P:Q corners R\n"), "x.scheme:8: mouth: needs at least one inner pair and 2 corners");
	EXPECT_EQ(message(base + "mouth P:Q\n"), "x.scheme:8: expected 'mouth inner UPPER:LOWER … corners A B'");
	EXPECT_EQ(message(base + "mouth inner P:Q corners R S\nmouth inner P:Q corners R S\n"), "x.scheme:9: a second 'mouth' line");
	const Scheme mouthed = parseScheme(base + "mouth inner P:Q R:S corners Q R\n", "x.scheme");
	EXPECT_EQ(mouthed.mouth.inner, (std::vector<std::pair<int, int>>{{0, 1}, {2, 3}}));
	EXPECT_EQ(mouthed.mouth.corner1, 2);
	for (const std::string name : {"ch-unicamp-56", "ibug-68", "imm-73"}) {
		const Scheme sc = loadScheme(name);
		ASSERT_EQ(sc.mouth.inner.size(), 3u) << name;
		for (const auto& [up, down] : sc.mouth.inner) EXPECT_NE(up, down) << name;
	}
	EXPECT_EQ(loadScheme("ibug-68").mouth.inner[1], (std::pair<int, int>{62, 66}));  // IM2 over IM6
	EXPECT_NE(message("class a x\n").find("x.scheme:1:"), std::string::npos);
	EXPECT_THROW(loadScheme("no-such-scheme"), Error);
}

TEST(Scheme, regionBoundaryPointsBetweenTwoPoints) {
	const std::string base = "scheme s\nclass a 1\npoint P a\npoint Q a\npoint R a\n";
	const Scheme s = parseScheme(base + "region r : P Q>R@0.25 R>P@-0.5\n", "x.scheme");
	ASSERT_EQ(s.regions.size(), 1u);
	const RegionSpec& r = s.regions[0];
	EXPECT_EQ(r.boundary, (std::vector<int>{0, 1, 2}));
	EXPECT_EQ(r.towards, (std::vector<int>{-1, 2, 0}));
	Points shape(3, 2);
	shape << 0, 0, 10, 0, 10, 20;
	const Points b = regionBoundary(r, shape);
	ASSERT_EQ(b.rows(), 3);
	EXPECT_DOUBLE_EQ(b(0, 0), 0);
	EXPECT_DOUBLE_EQ(b(1, 1), 5);                          // a quarter of the way from Q (10,0) to R (10,20)
	EXPECT_DOUBLE_EQ(b(2, 0), 15);                         // half of R−P beyond R, away from P
	EXPECT_DOUBLE_EQ(b(2, 1), 30);
	EXPECT_EQ(message(base + "region r : P Q R>Z@0.5\n"), "x.scheme:6: region 'r': bad second point 'Z' in 'R>Z@0.5'");
	EXPECT_EQ(message(base + "region r : P Q R>R@0.5\n"), "x.scheme:6: region 'r': bad second point 'R' in 'R>R@0.5'");
	for (const char* bad : {"R>P", "R>P@", "R>P@0", "R>P@1", "R>P@4", "R>P@x", "R>P@nan"})
		EXPECT_EQ(message(base + "region r : P Q " + bad + "\n"),
		          "x.scheme:6: region 'r': bad boundary point '" + std::string(bad) + "' (expected A>B@T with −3 ≤ T ≤ 3, T not 0 or 1)")
		    << bad;
	EXPECT_EQ(message(base + "region r : P Q>R@0.5 Q>R@0.5\n"), "x.scheme:6: region 'r': point 'Q>R@0.5' repeated");
	// The default face's region runs over the forehead, below the hairline, between the head points and the brows.
	const Scheme ch = loadScheme("ch-unicamp-56");
	int between = 0;
	for (int t : ch.regions[0].towards) between += t >= 0;
	EXPECT_EQ(between, 3);
}
