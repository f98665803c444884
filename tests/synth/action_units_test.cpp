// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <random>

#include "base/error.h"
#include "geometry/scheme.h"
#include "synth/action_units.h"

using namespace talkhead;

namespace {
// Five points: two eyes (corners), a mouth corner on each side, a chin on the midline.
Scheme tinyScheme() {
	return parseScheme("scheme tiny\nclass rigid 1\nclass soft 0.2\n"
	                   "point R1 rigid\npoint R2 rigid\npoint L1 rigid\npoint L2 rigid\n"
	                   "point MR soft\npoint ML soft\npoint C soft\n"
	                   "region face : R1 L2 C\neye right corners R1 R2 upper R2 lower R1\neye left corners L1 L2 upper L1 lower L2\n",
	                   "tiny.scheme");
}
Points neutralShape() {
	Points p(7, 2);
	p << 100, 100, 140, 100, 180, 100, 220, 100, 130, 200, 190, 200, 160, 240;
	return p;
}
std::string failure(const std::string& text) {
	try {
		parseAuTemplates(text, "t.tsv", tinyScheme());
	} catch (const Error& e) {
		return e.what();
	}
	return "no error";
}
}  // namespace

TEST(ActionUnits, namesAreCanonical) {
	EXPECT_EQ(canonicalActionUnit("AU12"), std::optional<std::string>("AU12"));
	EXPECT_EQ(canonicalActionUnit("au4"), std::optional<std::string>("AU4"));
	EXPECT_EQ(canonicalActionUnit("26"), std::optional<std::string>("AU26"));
	EXPECT_EQ(canonicalActionUnit("AU3"), std::nullopt);
	EXPECT_EQ(canonicalActionUnit("AU"), std::nullopt);
	EXPECT_EQ(canonicalActionUnit("AU123"), std::nullopt);
	EXPECT_EQ(canonicalActionUnit("smile"), std::nullopt);
	// The emotion table's profiles: joy is 6+12+25+26, distress includes AU15.
	const auto& p = defaultAuProfiles();
	ASSERT_TRUE(p.count("joy"));
	EXPECT_EQ(p.at("joy").size(), 4u);
	EXPECT_TRUE(p.at("neutral").empty());
	bool au15 = false;
	for (const auto& [au, v] : p.at("distress")) au15 |= au == "AU15" && v == 1.0;
	EXPECT_TRUE(au15);
}

TEST(ActionUnits, templateFilesRoundTripAndBadOnesAreNamed) {
	const Scheme s = tinyScheme();
	AuTemplates t;
	t.names = {"AU12", "AU26"};
	t.offsets = {Points::Zero(7, 2), Points::Zero(7, 2)};
	t.offsets[0](4, 0) = -0.1, t.offsets[0](4, 1) = -0.05, t.offsets[0](5, 0) = 0.1, t.offsets[0](5, 1) = -0.05;
	t.offsets[1](6, 1) = 0.25;
	const std::string text = formatAuTemplates(t, s, "two lines\nof comment");
	EXPECT_EQ(text.substr(0, 29), "# two lines\n# of comment\nau\tp");
	const AuTemplates r = parseAuTemplates(text, "t.tsv", s);
	EXPECT_EQ(r.names, t.names);
	EXPECT_EQ(r.offsets[0], t.offsets[0]);
	EXPECT_EQ(r.offsets[1], t.offsets[1]);
	EXPECT_EQ(failure("au\tpoint\tdx\tdy\nAU99\tR1\t0\t0\n"), "t.tsv:2: unknown action unit 'AU99'");
	EXPECT_EQ(failure("au\tpoint\tdx\tdy\nAU12\tX\t0\t0\n"), "t.tsv:2: point 'X' is not in scheme tiny");
	EXPECT_EQ(failure("au\tpoint\tdx\tdy\nAU12\tR1\t0\t0\nAU12\tR1\t0\t0\n"), "t.tsv:3: AU12 R1 given twice");
	EXPECT_EQ(failure("au\tpoint\tdx\tdy\nAU12\tR1\t0\t0\n"), "t.tsv: AU12 has no row for point R2");
	EXPECT_EQ(failure("au\tpoint\tdx\n").substr(0, 6), "t.tsv:");
}

TEST(ActionUnits, applyingMovesPointsInEyeUnitsAndBySide) {
	const Scheme s = tinyScheme();
	AuTemplates t;
	t.names = {"AU12"};
	t.offsets = {Points::Zero(7, 2)};
	t.offsets[0](4, 1) = -0.1, t.offsets[0](5, 1) = -0.1, t.offsets[0](6, 1) = -0.1;
	const Points n = neutralShape();
	const EyeFrame f = eyeFrame(s, n);
	EXPECT_DOUBLE_EQ(f.iod, 80);  // eye centres (120, 100) and (200, 100)
	Points both = n, left = n;
	applyActionUnits(both, t, {{0, 1.0, 0}}, f);
	EXPECT_DOUBLE_EQ(both(4, 1), 192);  // 0.1 × 80 px up
	EXPECT_DOUBLE_EQ(both(5, 1), 192);
	applyActionUnits(left, t, {{0, 0.5, 1}}, f);  // +1: the image-right half only, the midline half
	EXPECT_DOUBLE_EQ(left(4, 1), 200);
	EXPECT_DOUBLE_EQ(left(5, 1), 196);
	EXPECT_DOUBLE_EQ(left(6, 1), 238);
	// A rotated face moves along its own axes.
	Points turned = n;
	for (Eigen::Index i = 0; i < turned.rows(); ++i) turned.row(i) = Eigen::RowVector2d(-n(i, 1), n(i, 0));  // 90°
	const EyeFrame g = eyeFrame(s, turned);
	Points moved = turned;
	applyActionUnits(moved, t, {{0, 1.0, 0}}, g);
	EXPECT_NEAR((moved.row(6) - turned.row(6)).norm(), 8, 1e-9);
}

TEST(ActionUnits, learningRecoversTheTemplatesThatMadeTheShapes) {
	const Scheme s = tinyScheme();
	// Truth: AU12 lifts and widens the corners, AU26 drops the chin, AU15 pulls the corners down.
	std::map<std::string, Points> truth;
	for (const char* au : {"AU12", "AU26", "AU15"}) truth[au] = Points::Zero(7, 2);
	truth["AU12"](4, 0) = -0.08, truth["AU12"](4, 1) = -0.1, truth["AU12"](5, 0) = 0.08, truth["AU12"](5, 1) = -0.1;
	truth["AU26"](6, 1) = 0.3, truth["AU26"](4, 1) = 0.05, truth["AU26"](5, 1) = 0.05;
	truth["AU15"](4, 1) = 0.09, truth["AU15"](5, 1) = 0.09;
	const std::map<std::string, AuProfile> profiles = {{"neutral", {}},
	                                                   {"joy", {{"AU12", 1.0}, {"AU26", 0.2}}},
	                                                   {"distress", {{"AU15", 1.0}}},
	                                                   {"fear", {{"AU26", 0.6}}},
	                                                   {"relief", {{"AU12", 0.5}, {"AU26", 0.1}}}};
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> u(-1, 1);
	std::vector<LabelledShape> shapes;
	for (const char* cdv : {"a", "e", "sil"}) {
		const Points n = neutralShape();
		shapes.push_back({"neutral", cdv, n});
		for (const auto& [emotion, profile] : profiles) {
			if (emotion == "neutral") continue;
			Points p = n;
			for (const auto& [au, v] : profile) p += v * 80.0 * truth.at(au);
			// Head jitter: the learner aligns it away on the rigid points.
			const Similarity j = Similarity::fromScaleAngle(1 + 0.02 * u(rng), 0.03 * u(rng), 5 * u(rng), 5 * u(rng));
			shapes.push_back({emotion, cdv, j.apply(p)});
		}
	}
	const AuFit fit = learnAuTemplates(s, shapes, profiles);
	EXPECT_EQ(fit.pairs, 12u);
	EXPECT_LT(fit.rmsResidual, 0.002);
	ASSERT_EQ(fit.templates.names.size(), 3u);
	for (const auto& [au, t] : truth) {
		const int a = fit.templates.find(au);
		ASSERT_GE(a, 0) << au;
		EXPECT_LT((fit.templates.offsets[std::size_t(a)] - t).cwiseAbs().maxCoeff(), 0.01) << au;
	}
	EXPECT_NE(std::find(fit.unused.begin(), fit.unused.end(), "AU4"), fit.unused.end());
	// Too few shapes for the AUs: a clear error.
	EXPECT_THROW(learnAuTemplates(s, {shapes[0], shapes[1]}, profiles), Error);
}

TEST(ActionUnits, theShippedIbug68TemplatesMoveDlibsPointsAsFacsSays) {
	// models/au-templates/ibug-68.tsv (corpus-tools/ibug68_au_templates.sh): faces made from video can
	// smile and frown by action units.
	const Scheme s = loadScheme("ibug-68");
	const auto t = findAuTemplates(s);
	ASSERT_TRUE(t.has_value());
	auto at = [&](const char* au, const char* point) { return t->offsets[std::size_t(t->find(au))].row(s.indexOf(point)); };
	EXPECT_LT(at("AU12", "OM0")(1), -0.05);  // corners up
	EXPECT_LT(at("AU12", "OM0")(0), -0.03);  // and out
	EXPECT_GT(at("AU12", "OM6")(0), 0.03);
	EXPECT_GT(at("AU15", "OM0")(1), 0.05);   // corners down
	EXPECT_LT(at("AU1", "RB4")(1), -0.1);    // inner brow up
	EXPECT_GT(at("AU4", "RB4")(1), 0.02);    // brows down
	EXPECT_GT(at("AU4", "RB4")(0), 0.02);    // and together
	EXPECT_GT(at("AU26", "JAW8")(1), 0.03);  // the chin drops
	// D69: anger's brows knit into a V — the inner ends lowered most, then the middles, the outer ends
	// least — and sadness lifts the inner ends most; the two brows mirror each other.
	auto emotion = [&](const char* e) {
		Points d = Points::Zero(s.pointCount(), 2);
		for (const auto& [au, v] : defaultAuProfiles().at(e))
			if (int a = t->find(au); a >= 0) d += v * t->offsets[std::size_t(a)];
		return d;
	};
	const Points anger = emotion("anger"), distress = emotion("distress");
	auto y = [&](const Points& d, const char* point) { return d(s.indexOf(point), 1); };
	EXPECT_GT(y(anger, "RB4"), y(anger, "RB2") + 0.02);
	EXPECT_GT(y(anger, "RB2"), y(anger, "RB0") + 0.05);
	EXPECT_GT(y(anger, "LB0"), y(anger, "LB2") + 0.02);
	EXPECT_LT(y(distress, "RB4"), y(distress, "RB3") - 0.05);
	for (const auto& [r, l] : {std::pair{"RB0", "LB4"}, {"RB1", "LB3"}, {"RB2", "LB2"}, {"RB3", "LB1"}, {"RB4", "LB0"}}) {
		EXPECT_NEAR(y(anger, r), y(anger, l), 0.002) << r;
		EXPECT_NEAR(anger(s.indexOf(r), 0), -anger(s.indexOf(l), 0), 0.002) << r;
	}
	// Lids and lips move apart as their contours do (D69): AU5 lifts the upper lids, not the lower; AU7
	// brings them together; AU25 and AU26 part the inner lips (the rest image's mouth is closed, so the
	// inner upper and lower lips start at the same place); AU10 lifts the upper lip off the lower.
	for (const char* upper : {"RE1", "RE2", "LE1", "LE2"}) {
		EXPECT_LT(at("AU5", upper)(1), -0.025) << upper;
		EXPECT_GT(at("AU7", upper)(1), 0.01) << upper;
	}
	for (const char* lower : {"RE4", "RE5", "LE4", "LE5"}) {
		EXPECT_GE(at("AU5", lower)(1), 0) << lower;
		EXPECT_LT(at("AU7", lower)(1), -0.008) << lower;
	}
	for (const char* au : {"AU25", "AU26"}) EXPECT_GT(at(au, "IM6")(1) - at(au, "IM2")(1), 0.05) << au;
	EXPECT_LT(at("AU10", "IM2")(1) - at("AU10", "IM6")(1), -0.02);
	EXPECT_FALSE(findAuTemplates(loadScheme("imm-73")).has_value());
}
