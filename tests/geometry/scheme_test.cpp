// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"
#include "geometry/scheme.h"

using namespace talkhead;

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
	auto message = [](const std::string& text) {
		try {
			parseScheme(text, "x.scheme");
		} catch (const Error& e) {
			return std::string(e.what());
		}
		return std::string("no error");
	};
	EXPECT_EQ(message("scheme s\nclass a 1\npoint P b\n"), "x.scheme:3: unknown weight class 'b' (declare it with 'class' first)");
	EXPECT_EQ(message("scheme s\nclass a 1\npoint P a\npoint Q a\npoint R a\nregion r : P Q Z\n"), "x.scheme:6: region 'r': unknown point 'Z'");
	EXPECT_EQ(message("scheme s\nclass a 1\npoint P a\npoint P a\n"), "x.scheme:4: duplicate point name 'P'");
	EXPECT_EQ(message("scheme s\nbogus\n"), "x.scheme:2: unknown keyword 'bogus' (expected scheme, class, point, region or eye)");
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
	EXPECT_NE(message("class a x\n").find("x.scheme:1:"), std::string::npos);
	EXPECT_THROW(loadScheme("no-such-scheme"), Error);
}
