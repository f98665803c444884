// SPDX-License-Identifier: GPL-3.0-or-later
// Issue 31, route 2: action-unit appearance maps (expression ratio images) — learned back from images
// whose expression is a known luminance ratio, mapped onto another face by its anchors, identity at
// intensity 0, monotone in intensity, and a damaged file is one clear error.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "base/error.h"
#include "geometry/scheme.h"
#include "base/data_dirs.h"
#include "model/model_file.h"
#include "synth/au_appearance.h"
#include "synth/synthesizer.h"

using namespace talkhead;

namespace {

// A small face: eyes (corners and lids), brows (inner → outer), nose, mouth corners and lips, chin.
Scheme faceScheme() {
	return parseScheme("scheme small\nclass rigid 1\nclass soft 0.2\n"
	                   "point R1 rigid\npoint R2 rigid\npoint RU soft\npoint RL soft\npoint L1 rigid\npoint L2 rigid\npoint LU soft\npoint LL soft\n"
	                   "point RBi soft\npoint RBo soft\npoint LBi soft\npoint LBo soft\npoint N rigid\npoint MR soft\npoint ML soft\n"
	                   "point UL soft\npoint LLp soft\npoint C soft\n"
	                   "region face : RBo LBo ML C MR\nregion lips : MR UL ML LLp\n"
	                   "eye right corners R1 R2 upper RU lower RL\neye left corners L1 L2 upper LU lower LL\n"
	                   "brow right : RBi RBo\nbrow left : LBi LBo\n",
	                   "small.scheme");
}

// The face at a scale and offset (eye distance 80 px at scale 1).
Points face(double s = 1, double dx = 0, double dy = 0) {
	Points p(18, 2);
	p << 60, 100, 90, 100, 75, 94, 75, 106, 130, 100, 160, 100, 145, 94, 145, 106,  // eyes
	    95, 80, 55, 82, 125, 80, 165, 82,                                            // brows
	    110, 135, 85, 160, 135, 160, 110, 154, 110, 168, 110, 195;                   // nose, mouth, lips, chin
	p.col(0) = p.col(0).array() * s + dx;
	p.col(1) = p.col(1).array() * s + dy;
	return p;
}

// A grey image; the expressive one 25 % brighter in a disc between the brows (a glabella "furrow").
Image8 image(bool furrow) {
	Image8 img(220, 240, 3, 128);
	if (!furrow) return img;
	for (int y = 0; y < img.height; ++y)
		for (int x = 0; x < img.width; ++x)
			if (std::hypot(x - 110.0, y - 90.0) < 8)
				for (int c = 0; c < 3; ++c) img.at(x, y, c) = 160;
	return img;
}

AuAppearance learned() {
	std::vector<AppearanceSample> samples = {{"neutral", "sil", face()}, {"anger", "sil", face()}};
	const std::map<std::string, AuProfile> profiles = {{"anger", {{"AU4", 1.0}}}};
	return learnAuAppearance(faceScheme(), samples, [](std::size_t i) { return image(i == 1); }, profiles, 110);
}

// The grid value nearest to a point of the face's image.
float at(const AuAppearance& a, const Points& shape, double x, double y, int au = 0) {
	(void)shape;
	// The grid's anchors are the face's anchors under a similarity: solve for the point by the brows' and
	// eyes' corners (the first anchor and the chin give scale and offset).
	const Points fa = appearanceAnchors(faceScheme(), face());
	const double s = (a.anchors(8, 1) - a.anchors(0, 1)) / (fa(8, 1) - fa(0, 1));
	const double gx = a.anchors(0, 0) + (x - fa(0, 0)) * s, gy = a.anchors(0, 1) + (y - fa(0, 1)) * s;
	return a.logRatio[std::size_t(au)][std::size_t(std::lround(gy)) * std::size_t(a.width) + std::size_t(std::lround(gx))];
}

}  // namespace

TEST(AuAppearance, aKnownRatioIsLearnedBackWhereItIsAndNowhereElse) {
	const AuAppearance a = learned();
	ASSERT_EQ(a.names, std::vector<std::string>{"AU4"});
	const float expected = std::log((160.f + 8) / (128.f + 8));  // 0.21
	EXPECT_NEAR(at(a, face(), 110, 90), expected, 0.05);          // the glabella
	EXPECT_NEAR(at(a, face(), 110, 180), 0.0, 1e-3);              // the chin
	EXPECT_NEAR(at(a, face(), 80, 120), 0.0, 1e-3);               // a cheek
}

TEST(AuAppearance, mappedOntoAnotherFaceThroughItsAnchors) {
	const AuAppearance a = learned();
	// The same face 1.5 times larger and moved: the change lands between its brows.
	const Points big = face(1.5, 30, 10);
	const MappedAuAppearance m = mapAuAppearance(a, faceScheme(), big, 0, 0, 400, 400);
	auto value = [&](double x, double y) { return m.logRatio[0][std::size_t(std::lround(y)) * 400 + std::size_t(std::lround(x))]; };
	EXPECT_GT(value(110 * 1.5 + 30, 90 * 1.5 + 10), 0.12);
	EXPECT_NEAR(value(110 * 1.5 + 30, 180 * 1.5 + 10), 0.0, 1e-3);
	EXPECT_EQ(value(5, 5), 0.0f);  // outside the grid: no change
}

TEST(AuAppearance, intensityZeroIsIdentityAndTheChangeGrowsWithIntensity) {
	const AuAppearance a = learned();
	const MappedAuAppearance m = mapAuAppearance(a, faceScheme(), face(), 0, 0, 220, 240);
	EXPECT_TRUE(appearanceGain(m, {{"AU4", 0.0}}).empty());
	EXPECT_TRUE(appearanceGain(m, {{"AU12", 1.0}}).empty());  // an AU without a map
	double previous = 0;
	for (double w : {0.25, 0.5, 1.0}) {
		const std::vector<float> g = appearanceGain(m, {{"AU4", w}});
		ASSERT_EQ(g.size(), std::size_t(220 * 240));
		double change = 0;
		for (float v : g) change += std::abs(std::log(v));
		EXPECT_GT(change, previous) << w;
		previous = change;
	}
}

TEST(AuAppearance, savedAndLoadedExactlyAndDamageIsOneClearError) {
	const AuAppearance a = learned();
	const std::string path = (std::filesystem::temp_directory_path() / "talkhead-au-appearance-test.bin").string();
	saveAuAppearance(a, path);
	const AuAppearance b = loadAuAppearance(path);
	EXPECT_EQ(b.names, a.names);
	EXPECT_EQ(b.logRatio, a.logRatio);
	EXPECT_EQ(b.width, a.width);
	// Cut short.
	const auto size = std::filesystem::file_size(path);
	std::filesystem::resize_file(path, size - 10);
	try {
		loadAuAppearance(path);
		FAIL() << "a cut file loaded";
	} catch (const Error& e) {
		EXPECT_NE(std::string(e.what()).find("corrupt action-unit appearance file: cut short"), std::string::npos) << e.what();
		EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
	}
	// An AU given twice (a fuzz finding: reading that AU alone gave two maps).
	AuAppearance twice = a;
	twice.names.push_back(a.names.front());
	twice.logRatio.push_back(a.logRatio.front());
	saveAuAppearance(twice, path);
	try {
		loadAuAppearance(path);
		FAIL() << "a file naming an AU twice loaded";
	} catch (const Error& e) {
		EXPECT_NE(std::string(e.what()).find("corrupt action-unit appearance file: AU '" + a.names.front() + "' is given twice"), std::string::npos) << e.what();
	}
	std::ofstream(path) << "not this";
	try {
		loadAuAppearance(path);
		FAIL() << "text loaded";
	} catch (const Error& e) {
		EXPECT_NE(std::string(e.what()).find("not an action-unit appearance file"), std::string::npos) << e.what();
	}
	std::filesystem::remove(path);
}

// The check on the shipped maps: the default face, rendered from its neutral images by each
// prototype's action units, against its own render of the emotion from its corpus images (a silent
// keypose; no blinks, no head motion): the skin brings each closer, in the shape-normalised frame (the
// mean frame's face box) and in the rendered frame (the box of the face's points) (PSNR, dB).
TEST(AuAppearance, theDefaultFacesExpressionsFromItsNeutralImagesComeCloserToItsCorpusWithTheSkin) {
	const std::optional<std::string> path = findDefaultModel();
	if (!path || !installedAuAppearance({"AU4"})) GTEST_SKIP() << "no default model or models/au-appearance.bin built";
	const FaceModel model = loadModel(*path);
	const std::vector<PhoneSegment> phones = {{Ticks(0), std::chrono::duration_cast<Ticks>(std::chrono::seconds(1)), "", "", "sil", 0}};
	const auto keys = keyposes(phones, Ticks(kTicksPerSecond / 25));
	struct Face {
		std::vector<std::uint8_t> rgb;
		Image8 frame;
		Points points;
	};
	auto face = [&](const std::string& emotion, EmotionSource source, bool skin) {
		SynthOptions o;
		o.expression = Expression(Emotion::of(emotion));
		o.emotionSource = source;
		o.auAppearance = skin;
		Synthesizer s(model, o);
		s.prepare(keys);
		Synthesizer::Workspace ws;
		Face f;
		s.renderFrame(keys.front().time, keys, ws, f.frame, f.points);
		f.rgb = s.keypose("sil").rgb;
		return f;
	};
	auto psnr = [](const std::uint8_t* a, const std::uint8_t* b, std::size_t n) {
		double se = 0;
		for (std::size_t i = 0; i < n; ++i) se += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
		return 10 * std::log10(255.0 * 255.0 / std::max(se / double(n), 1e-12));
	};
	// The floors: today's figures less 0.5 dB (D61, D71: the 30 dB is reached by joy and hate; anger and
	// distress lack what a warp of the neutral shape cannot give, fear its parted lips). D84's sharp resampling
	// lowered the rendered figures by 0.1–1.0 dB (both renders are sharpened, their differences with them).
	const std::map<std::string, double> rendered = {{"joy", 31.7}, {"distress", 27.2}, {"hate", 29.1}, {"anger", 26.2}, {"fear", 22.6}};
	for (const auto& [emotion, floor] : rendered) {
		const Face corpus = face(emotion, EmotionSource::Corpus, false), shape = face(emotion, EmotionSource::ActionUnits, false),
		           skin = face(emotion, EmotionSource::ActionUnits, true);
		ASSERT_EQ(corpus.rgb.size(), skin.rgb.size());
		const double normalisedShape = psnr(corpus.rgb.data(), shape.rgb.data(), corpus.rgb.size());
		const double normalisedSkin = psnr(corpus.rgb.data(), skin.rgb.data(), corpus.rgb.size());
		// The rendered face box: the corpus face's points' box.
		const int x0 = int(corpus.points.col(0).minCoeff()), x1 = int(corpus.points.col(0).maxCoeff()) + 1;
		const int y0 = int(corpus.points.col(1).minCoeff()), y1 = int(corpus.points.col(1).maxCoeff()) + 1;
		auto box = [&](const Image8& im) {
			std::vector<std::uint8_t> v;
			for (int y = y0; y < y1; ++y) v.insert(v.end(), im.row(y) + 3 * x0, im.row(y) + 3 * x1);
			return v;
		};
		const auto c = box(corpus.frame), a = box(shape.frame), b = box(skin.frame);
		const double frameShape = psnr(c.data(), a.data(), c.size()), frameSkin = psnr(c.data(), b.data(), c.size());
		std::printf("%-9s shape-normalised %.1f -> %.1f dB, rendered %.1f -> %.1f dB\n", emotion.c_str(), normalisedShape, normalisedSkin, frameShape, frameSkin);
		EXPECT_GT(normalisedSkin, normalisedShape) << emotion;
		EXPECT_GT(frameSkin, frameShape) << emotion;
		EXPECT_GE(frameSkin, floor) << emotion;
	}
}

// D73: the shipped maps leave the base of the nose alone — the drawn nostrils rise with AU9 and AU10, and
// their registration darkened the skin just above the upper lip (a moustache's shadow on a real face) —
// while the units still change the skin around it.
TEST(AuAppearance, theShippedNoseWrinkleAndLipRaiseLeaveTheNostrilsBaseAlone) {
	const std::optional<std::string> path = findDefaultModel();
	const std::optional<AuAppearance> a = installedAuAppearance({"AU9", "AU10"});
	if (!path || !a) GTEST_SKIP() << "no default model or models/au-appearance.bin built";
	const FaceModel model = loadModel(*path);
	Scheme scheme = model.scheme;
	completeSchemeParts(scheme);
	const MappedAuAppearance m = mapAuAppearance(*a, scheme, model.meanShape, 0, 0, model.width, model.height);
	const Points& s = model.meanShape;
	auto centre = [&](const char* a, const char* b) -> Eigen::RowVector2d { return 0.5 * (s.row(scheme.indexOf(a)) + s.row(scheme.indexOf(b))); };
	const double iod = (centre("LEYE1", "LEYE3") - centre("REYE1", "REYE3")).norm();
	for (const char* au : {"AU9", "AU10"}) {
		const std::vector<float>& r = m.logRatio[std::size_t(m.find(au))];
		auto value = [&](double x, double y) { return r[std::size_t(std::lround(y)) * std::size_t(m.width) + std::size_t(std::lround(x))]; };
		float largest = 0;
		for (float v : r) largest = std::max(largest, std::abs(v));
		EXPECT_GT(largest, 0.05f) << au;
		for (const char* p : {"RN3", "N3", "LN3"})
			for (double down : {0.0, 0.04}) {
				const int i = scheme.indexOf(p);
				EXPECT_LT(std::abs(value(s(i, 0), s(i, 1) + down * iod)), 0.01f) << au << " at " << p << " + " << down;
			}
	}
}

TEST(AuAppearance, anotherFaceKeepsItsOwnSkinWithTheLinesDarkFoldsAndNoPaleBands) {
	// Issue 47, D85: a map of pale and dark bands (period 8 px on the learning face) on a face of other
	// proportions and with its own texture: the broad shading stays, the pale bands go, the dark ones
	// become narrowed folds, and the face's own fine detail is deepened where the bands were. The learning
	// face itself, and a face given no image, get the map as learned.
	AuAppearance a;
	a.width = 220, a.height = 240, a.names = {"AU9"};
	a.anchors = appearanceAnchors(faceScheme(), face());
	std::vector<float> bands(std::size_t(220 * 240), 0.f);
	for (int y = 100; y < 140; ++y)
		for (int x = 95; x < 125; ++x) bands[std::size_t(y) * 220 + std::size_t(x)] = 0.15f * float(std::sin(2 * 3.14159265358979 * y / 8.0));
	a.logRatio = {bands};
	Image8 skin(220, 240, 3, 128);  // the other face's own texture: a fine checker of ±6 levels
	for (int y = 0; y < 240; ++y)
		for (int x = 0; x < 220; ++x)
			for (int c = 0; c < 3; ++c) skin.at(x, y, c) = std::uint8_t(((x / 2 + y / 2) % 2) ? 134 : 122);
	const MappedAuAppearance same = mapAuAppearance(a, faceScheme(), face(), 0, 0, 220, 240, nullptr, &skin);
	EXPECT_FALSE(same.ownSkin);  // the learning face: as learned
	EXPECT_EQ(same.logRatio[0], mapAuAppearance(a, faceScheme(), face(), 0, 0, 220, 240).logRatio[0]);
	Points other = face();
	other(8, 1) -= 25, other(9, 1) -= 25;  // other proportions, which no affine map makes the learning face's: a
	other(17, 0) += 25;                    // right brow higher than the left, a chin to one side (12 % of the eye distance off)
	const MappedAuAppearance learnedOnOther = mapAuAppearance(a, faceScheme(), other, 0, 0, 220, 240);
	const MappedAuAppearance own = mapAuAppearance(a, faceScheme(), other, 0, 0, 220, 240, nullptr, &skin);
	ASSERT_TRUE(own.ownSkin);
	EXPECT_FALSE(learnedOnOther.ownSkin);
	// In the bands' box on the other face: learned, pale bands up to +0.15; own skin, no band paler than the
	// face's own detail deepened (checker ±0.05 in log luminance, ×(1 + 1.5) at most) and dark folds kept.
	double learnedMax = -1, ownMax = -1, ownMin = 1;
	for (int y = 110; y < 145; ++y)
		for (int x = 100; x < 120; ++x) {
			const std::size_t p = std::size_t(y) * 220 + std::size_t(x);
			learnedMax = std::max(learnedMax, double(learnedOnOther.logRatio[0][p]));
			ownMax = std::max(ownMax, double(own.logRatio[0][p]));
			ownMin = std::min(ownMin, double(own.logRatio[0][p]));
		}
	EXPECT_GT(learnedMax, 0.12);
	EXPECT_LT(ownMax, 0.09);
	EXPECT_LT(ownMin, -0.1);
	// Away from the bands the face's texture is left alone.
	EXPECT_EQ(own.logRatio[0][std::size_t(200) * 220 + 30], 0.f);
}
