// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <set>

#include "base/data_dirs.h"
#include "geometry/scheme.h"
#include "phonetics/labels.h"
#include "synth/action_units.h"
#include "synth_corpus.h"

using namespace talkhead;

namespace {
const FaceRenderer& renderer() {
	static const FaceRenderer r(640, 360);
	return r;
}
int idx(const char* name) {
	static const Scheme s = loadScheme("ch-unicamp-56");
	return s.indexOf(name);
}
const SynthItem& item(const std::vector<SynthItem>& items, const std::string& emotion, const std::string& viseme) {
	for (const auto& it : items)
		if (it.emotion == emotion && it.viseme == viseme) return it;
	throw std::runtime_error("no item " + emotion + " " + viseme);
}
// Points without head jitter, so differences are articulation only.
Points still(const SynthItem& it) { return renderer().points(it.articulation, it.actionUnits, HeadPose{}); }
double eyeCorners(const Points& p) { return (p.row(idx("REYE1")) - p.row(idx("LEYE1"))).norm(); }
const std::vector<int>& mouthPoints() {
	static const std::vector<int> m = [] {
		std::vector<int> v;
		for (const char* n : {"RM1", "RM2", "RM3", "RM4", "RM5", "LM1", "LM2", "LM3", "LM4", "LM5", "CUM", "CLM", "VMR", "VML", "CIUM", "CILM", "CJAW"})
			v.push_back(idx(n));
		return v;
	}();
	return m;
}
}  // namespace

TEST(SynthCorpus, labelsAreTheCanonicalLists) {
	EXPECT_EQ(emotionLabels().size(), 23u);
	EXPECT_EQ(visemeLabels().size(), 34u);
	auto items = synthCorpusItems({});
	EXPECT_EQ(items.size(), 782u);
	std::set<std::string> files;
	for (const auto& it : items) files.insert(it.fileName);
	EXPECT_EQ(files.size(), 782u) << "file names must be unique";
	EXPECT_EQ(canonicalEmotion("Sadness"), std::optional<std::string>("distress"));
	EXPECT_EQ(canonicalEmotion("disgust"), std::optional<std::string>("hate"));
	EXPECT_EQ(canonicalViseme("<p1>"), std::optional<std::string>("p1"));
	EXPECT_EQ(canonicalViseme("sh1"), std::optional<std::string>("ʃ1"));
	EXPECT_EQ(canonicalViseme("E"), std::optional<std::string>("ɛ"));
	EXPECT_EQ(canonicalViseme("e"), std::optional<std::string>("e"));
}

TEST(SynthFace, sameInputsGiveTheSameBytes) {
	auto items = synthCorpusItems({});
	const SynthItem& it = item(items, "joy", "a");
	SynthFace a = renderer().render(it.articulation, it.actionUnits, it.pose);
	SynthFace b = renderer().render(it.articulation, it.actionUnits, it.pose);
	EXPECT_EQ(a.image.data, b.image.data);
	EXPECT_EQ(a.points, b.points);
	EXPECT_EQ(a.points, renderer().points(it.articulation, it.actionUnits, it.pose));
}

TEST(SynthCorpus, seedChangesTheJitterOnly) {
	SynthCorpusOptions o1, o2;
	o2.seed = 2;
	auto a = synthCorpusItems(o1), b = synthCorpusItems(o2), a2 = synthCorpusItems(o1);
	ASSERT_EQ(a.size(), b.size());
	int posesDiffer = 0;
	for (std::size_t i = 0; i < a.size(); ++i) {
		EXPECT_EQ(a[i].fileName, b[i].fileName);
		EXPECT_EQ(a[i].context, b[i].context);
		EXPECT_EQ(a[i].pose.angleDeg, a2[i].pose.angleDeg);  // same seed: same jitter
		posesDiffer += a[i].pose.angleDeg != b[i].pose.angleDeg;
		// Jitter bounds: ≤ 2°, ± 2 % scale.
		EXPECT_LE(std::abs(a[i].pose.angleDeg), 2.0);
		EXPECT_LE(std::abs(a[i].pose.scale - 1), 0.02);
		if (i % 97 == 0) {
			// The two versions of an image differ by a similarity transform of the head only.
			Points pa = renderer().points(a[i].articulation, a[i].actionUnits, a[i].pose);
			Points pb = renderer().points(b[i].articulation, b[i].actionUnits, b[i].pose);
			Similarity s = alignSimilarity(pa, pb, Eigen::VectorXd::Ones(56));
			EXPECT_LT((s.apply(pa) - pb).cwiseAbs().maxCoeff(), 1e-6);
			EXPECT_GT((pa - pb).cwiseAbs().maxCoeff(), 0.1);
		}
	}
	EXPECT_GT(posesDiffer, 770);
}

TEST(SynthCorpus, pointsLieInsideTheImage) {
	for (const auto& it : synthCorpusItems({})) {
		Points p = renderer().points(it.articulation, it.actionUnits, it.pose);
		EXPECT_GE(p.col(0).minCoeff(), 0) << it.fileName;
		EXPECT_GE(p.col(1).minCoeff(), 0) << it.fileName;
		EXPECT_LT(p.col(0).maxCoeff(), 640) << it.fileName;
		EXPECT_LT(p.col(1).maxCoeff(), 360) << it.fileName;
	}
}

TEST(SynthCorpus, visemesTheThesisSeparatesHaveDifferentMouths) {
	auto items = synthCorpusItems({});
	const std::vector<std::vector<std::string>> groups = {{"p1", "p2"}, {"f1", "f2"}, {"t1", "t2"}, {"s1", "s2"}, {"l1", "l2", "l3", "l4"},
	                                                      {"ʃ1", "ʃ2"}, {"ʎ1", "ʎ2", "ʎ3"}, {"r1", "r2"}, {"k1", "k2", "k3"}, {"i1", "i2"}};
	// Threshold: 2 % of the eye-corner distance (≈ 2.3 px at 640×360, 7 px at 1920×1080) for the mouth
	// point that moves most.
	const double threshold = 0.02;
	for (const std::string emotion : {"neutral", "joy", "anger"})
		for (const auto& g : groups)
			for (std::size_t i = 0; i < g.size(); ++i)
				for (std::size_t j = i + 1; j < g.size(); ++j) {
					Points a = still(item(items, emotion, g[i])), b = still(item(items, emotion, g[j]));
					double most = 0;
					for (int k : mouthPoints()) most = std::max(most, (a.row(k) - b.row(k)).norm());
					EXPECT_GT(most / eyeCorners(a), threshold) << emotion << ": " << g[i] << " vs " << g[j];
				}
}

TEST(SynthCorpus, bilabialsCloseTheLipsAndOpenVowelsOpenTheJaw) {
	auto items = synthCorpusItems({});
	for (const auto& e : emotionLabels()) {
		for (const char* v : {"p1", "p2"}) {
			Points p = still(item(items, e.label, v));
			EXPECT_LT((p.row(idx("CIUM")) - p.row(idx("CILM"))).norm(), 0.01) << e.label << " " << v;
			EXPECT_LT((p.row(idx("RM4")) - p.row(idx("RM5"))).norm(), 0.01) << e.label << " " << v;
		}
		// <a> has the largest jaw opening of all visemes (chin lowest, lips furthest apart).
		Points a = still(item(items, e.label, "a"));
		for (const auto& v : visemeLabels()) {
			if (v.label == "a") continue;
			Points p = still(item(items, e.label, v.label));
			EXPECT_GT(a(idx("CJAW"), 1), p(idx("CJAW"), 1)) << e.label << ": a vs " << v.label;
			EXPECT_GT(a(idx("CILM"), 1) - a(idx("CIUM"), 1), p(idx("CILM"), 1) - p(idx("CIUM"), 1)) << e.label << ": a vs " << v.label;
		}
	}
}

TEST(SynthCorpus, expressionsMoveBrowsAndMouthAsTheirActionUnitsSay) {
	auto items = synthCorpusItems({});
	Points neutral = still(item(items, "neutral", "e")), joy = still(item(items, "joy", "e")), anger = still(item(items, "anger", "e")),
	       fear = still(item(items, "fear", "e"));
	auto width = [](const Points& p) { return p(idx("LM2"), 0) - p(idx("RM2"), 0); };
	EXPECT_GT(width(joy), 1.1 * width(neutral));                            // a smile widens the mouth
	EXPECT_LT(joy(idx("RM2"), 1), neutral(idx("RM2"), 1));                  // and lifts its corners
	EXPECT_GT(anger(idx("REB1"), 1), neutral(idx("REB1"), 1) + 3);          // AU4 lowers the inner brow
	EXPECT_LT(fear(idx("REB1"), 1), neutral(idx("REB1"), 1) - 3);           // AU1 raises it
	EXPECT_LT(fear(idx("REYE2"), 1), neutral(idx("REYE2"), 1) - 1);         // AU5 raises the upper lid
	// The prototypes at apex (expression-aus.tsv): sadness 1+4+15+17, anger 4+5+7+23+24, fear 1+2+4+5+20,
	// disgust 9+10+15+17.
	Points distress = still(item(items, "distress", "e")), hate = still(item(items, "hate", "e"));
	const double eye = eyeCorners(neutral);
	auto y = [](const Points& p, const char* n) { return p(idx(n), 1); };
	EXPECT_GT(y(distress, "RM2") - y(distress, "CLM"), y(neutral, "RM2") - y(neutral, "CLM") + 0.05 * eye);  // corners down
	// The oblique brow of sadness: the inner end rises above the middle of the brow.
	EXPECT_LT(y(distress, "REB1"), y(distress, "REB2"));
	EXPECT_GT(y(neutral, "REB1"), y(neutral, "REB2"));
	// Anger draws the brows together; fear's brows are raised and flattened (less arch than neutral's).
	auto gap = [](const Points& p) { return p(idx("LEB1"), 0) - p(idx("REB1"), 0); };
	EXPECT_LT(gap(anger), gap(neutral) - 0.05 * eye);
	auto arch = [&](const Points& p) { return (y(p, "REB1") + y(p, "REB3")) / 2 - y(p, "REB2"); };
	EXPECT_LT(arch(fear), 0.6 * arch(neutral));
	EXPECT_GT(width(fear), 1.15 * width(neutral));  // AU20 stretches the lips sideways
	EXPECT_LT(y(anger, "CIUM") - y(anger, "CUM"), 0.7 * (y(neutral, "CIUM") - y(neutral, "CUM")));  // lips pressed thin
	// Disgust: AU9 lifts the nose base, AU10 the upper lip.
	EXPECT_LT(y(hate, "N3"), y(neutral, "N3") - 0.02 * eye);
	EXPECT_LT(y(hate, "CUM"), y(neutral, "CUM") - 0.03 * eye);
}

TEST(SynthFace, expressionsDrawTheWrinklesAndFoldsAWarpCannotMake) {
	auto items = synthCorpusItems({});
	auto face = [&](const char* e) {
		const SynthItem& it = item(items, e, "sil");
		return renderer().render(it.articulation, it.actionUnits, HeadPose{});
	};
	const SynthFace neutral = face("neutral");
	const Points& p = neutral.points;
	const double f = eyeCorners(p) / 1.76;  // face units: the outer eye corners are 1.76 apart
	// Mean brightness of a box (half-size h face units) centred at point `name` + (dx, dy) face units.
	auto mean = [&](const SynthFace& s, const char* name, double dx, double dy, double h) {
		const double cx = p(idx(name), 0) + dx * f, cy = p(idx(name), 1) + dy * f;
		double sum = 0;
		int n = 0;
		for (int yy = int(cy - h * f); yy <= int(cy + h * f); ++yy)
			for (int xx = int(cx - h * f); xx <= int(cx + h * f); ++xx, ++n)
				for (int c = 0; c < 3; ++c) sum += s.image.data[(std::size_t(yy) * 640 + std::size_t(xx)) * 3 + std::size_t(c)];
		return sum / (3.0 * n);
	};
	struct Cue {
		const char* emotion;
		const char* what;
		const char* point;
		double dx, dy, h;
	} cues[] = {
	    {"anger", "AU4 glabella furrows", "N1", 0, -0.25, 0.12},
	    {"distress", "AU1 forehead lines", "N1", 0, -0.85, 0.25},
	    {"hate", "AU9 wrinkles across the nose root", "N1", 0, 0.06, 0.07},
	    {"joy", "AU6 crow's feet", "REYE1", -0.12, 0.02, 0.06},
	    {"distress", "AU15 furrow below the corner", "RM2", 0.0, 0.16, 0.06},
	    {"distress", "AU17 mentolabial furrow", "CLM", 0.0, 0.12, 0.06},
	};
	for (const Cue& c : cues) {
		const double before = mean(neutral, c.point, c.dx, c.dy, c.h), after = mean(face(c.emotion), c.point, c.dx, c.dy, c.h);
		EXPECT_LT(after, before - 2.0) << c.emotion << ": " << c.what;
	}
}

TEST(SynthCorpus, everyTwoExpressionsDifferInSomeActionUnit) {
	const auto table = loadActionUnits(*findDataFile("corpus-tools/data/expression-aus.tsv"));
	auto values = [](const ActionUnits& u) {
		return std::vector<double>{u.au1,  u.au2,  u.au4,  u.au5,  u.au6,  u.au7,  u.au9,  u.au10, u.au12,
		                           u.au15, u.au16, u.au17, u.au20, u.au23, u.au24, u.au25, u.au43, u.au26};
	};
	for (auto a = table.begin(); a != table.end(); ++a)
		for (auto b = std::next(a); b != table.end(); ++b) {
			const auto va = values(a->second), vb = values(b->second);
			double most = 0;
			for (std::size_t i = 0; i < va.size(); ++i) most = std::max(most, std::abs(va[i] - vb[i]));
			EXPECT_GE(most, 0.2 - 1e-9) << a->first << " vs " << b->first;
		}
}

TEST(SynthCorpus, theShippedActionUnitTemplatesAreTheOnesTheDefaultCorpusTeaches) {
	// models/au-templates/ch-unicamp-56.tsv was written by 'talkhead corpus au-templates' from the default
	// corpus; learning again from the generator's exact points must give the same numbers (4 decimals).
	const Scheme scheme = loadScheme("ch-unicamp-56");
	std::vector<LabelledShape> shapes;
	for (const auto& it : synthCorpusItems({})) shapes.push_back({it.emotion, it.viseme, renderer().points(it.articulation, it.actionUnits, it.pose)});
	const AuFit fit = learnAuTemplates(scheme, shapes, defaultAuProfiles());
	EXPECT_LT(fit.rmsResidual, 0.25 * fit.rmsData);  // the additive AU model explains the corpus's expressions
	const auto shipped = findAuTemplates(scheme);
	ASSERT_TRUE(shipped.has_value());
	ASSERT_EQ(shipped->names, fit.templates.names);
	for (std::size_t a = 0; a < fit.templates.names.size(); ++a)
		EXPECT_LT((shipped->offsets[a] - fit.templates.offsets[a]).cwiseAbs().maxCoeff(), 5e-4) << fit.templates.names[a];
	// And they say what FACS says: AU12 lifts and widens the mouth corners, AU1 lifts the inner brow, AU26
	// drops the chin, AU15 lowers the corners.
	auto at = [&](const char* au, const char* point) { return shipped->offsets[std::size_t(shipped->find(au))].row(idx(point)); };
	EXPECT_LT(at("AU12", "RM2")(1), -0.05);
	EXPECT_LT(at("AU12", "RM2")(0), -0.03);
	EXPECT_GT(at("AU12", "LM2")(0), 0.03);
	EXPECT_LT(at("AU1", "REB1")(1), -0.1);
	EXPECT_GT(at("AU26", "CJAW")(1), 0.03);
	EXPECT_GT(at("AU15", "RM2")(1), 0.05);
}
