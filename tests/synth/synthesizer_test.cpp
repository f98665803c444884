// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"

#include <opencv2/imgproc.hpp>

#include "geometry/scheme.h"
#include "image/region_mask.h"
#include "synth/au_appearance.h"
#include "synth/face_rig.h"
#include "synth/synthesizer.h"
#include "synth_corpus.h"
#include "warp/piecewise_affine.h"

using namespace talkhead;

namespace {

// A small model built in memory from the synthetic corpus: 3 emotions × 6 visemes at 320×180.
struct SmallFace {
	std::vector<SynthItem> items;
	std::vector<SynthFace> faces;
	FaceModel model;
};

const SmallFace& smallFace() {
	static const SmallFace f = [] {
		SmallFace s;
		SynthCorpusOptions o;
		o.width = 320;
		o.height = 180;
		o.emotions = {"neutral", "joy", "anger"};
		o.visemes = {"sil", "a", "u", "p1", "f1", "i1"};
		s.items = synthCorpusItems(o);
		FaceRenderer r(o.width, o.height);
		std::vector<Points> shapes;
		std::vector<SampleInfo> samples;
		for (const auto& it : s.items) {
			s.faces.push_back(r.render(it.articulation, it.actionUnits, it.pose));
			shapes.push_back(s.faces.back().points);
			samples.push_back(SampleInfo{it.fileName, it.emotion, it.viseme, it.word, it.context});
		}
		NullProgress quiet;
		s.model = buildFaceModel(loadScheme("ch-unicamp-56"), shapes, samples, o.width, o.height,
		                         [&](std::size_t i) { return s.faces[i].image; }, BuildOptions{}, quiet);
		return s;
	}();
	return f;
}

Ticks ms(long v) { return Ticks(v * (kTicksPerSecond / 1000)); }

}  // namespace

TEST(Trajectory, hermiteMidpointsAndZeroSpeedAtKeyposes) {
	Points s(2, 2), t(2, 2);
	s << 0, 0, 10, 20;
	t << 30, -10, 10, 60;
	EXPECT_LT((Synthesizer::trajectory(s, t, 0.5, Trajectory::Hermite) - (s + t) / 2).cwiseAbs().maxCoeff(), 1e-12);
	EXPECT_LT((Synthesizer::trajectory(s, t, 0.5, Trajectory::Linear) - (s + t) / 2).cwiseAbs().maxCoeff(), 1e-12);
	EXPECT_EQ(Synthesizer::trajectory(s, t, 0, Trajectory::Hermite), s);
	EXPECT_EQ(Synthesizer::trajectory(s, t, 1, Trajectory::Hermite), t);
	// Speed (finite differences): ≈ 0 at both keyposes with Hermite, constant with linear.
	const double h = 1e-4;
	auto speed = [&](double u, Trajectory k) {
		return (Synthesizer::trajectory(s, t, std::min(1.0, u + h), k) - Synthesizer::trajectory(s, t, std::max(0.0, u - h), k)).norm() /
		       (std::min(1.0, u + h) - std::max(0.0, u - h));
	};
	const double full = (t - s).norm();
	EXPECT_LT(speed(0, Trajectory::Hermite), 1e-3 * full);
	EXPECT_LT(speed(1, Trajectory::Hermite), 1e-3 * full);
	EXPECT_NEAR(speed(0.5, Trajectory::Hermite), 1.5 * full, 1e-3 * full);  // peak speed 1.5× the linear one
	for (double u : {0.0, 0.25, 0.5, 0.75, 1.0}) EXPECT_NEAR(speed(u, Trajectory::Linear), full, 1e-6 * full);
}

TEST(Trajectory, monotoneStopsWhereTheMotionTurnsAndCarriesItThroughElsewhere) {
	// One point, x only (y constant): keyposes x = 0, 1, 3, 2 at t = 0, 1, 2, 4 s.
	auto pt = [](double x) { Points p(1, 2); p << x, 5; return p; };
	const Points a = pt(0), b = pt(1), c = pt(3), d = pt(2);
	auto at = [&](int seg, double u) {  // segment 0: a→b, 1: b→c, 2: c→d
		const std::array<const Points*, 5> all = {nullptr, &a, &b, &c, &d};
		const std::array<double, 4> times = {0, 1, 2, 4};
		auto k = [&](int j) { return j >= 0 && j < 4 ? times[std::size_t(j)] : 0.0; };
		const std::array<const Points*, 4> p = {all[std::size_t(seg)], all[std::size_t(seg) + 1], all[std::size_t(seg) + 2],
		                                        seg + 3 < 5 ? all[std::size_t(seg) + 3] : nullptr};
		return Synthesizer::monotoneTrajectory(p, {k(seg - 1), k(seg), k(seg + 1), k(seg + 2)}, u)(0, 0);
	};
	// Through the keyposes, y untouched.
	EXPECT_DOUBLE_EQ(at(0, 0), 0);
	EXPECT_DOUBLE_EQ(at(0, 1), 1);
	EXPECT_DOUBLE_EQ(at(1, 1), 3);
	EXPECT_DOUBLE_EQ(at(2, 1), 2);
	const std::array<const Points*, 4> p = {&a, &b, &c, &d};
	EXPECT_DOUBLE_EQ(Synthesizer::monotoneTrajectory(p, {0, 1, 2, 4}, 0.3)(0, 1), 5);
	// Velocity (x per second; segment durations 1, 1, 2 s), by finite differences.
	const double e = 1e-6;
	auto v = [&](int seg, double u) {
		const double h = seg == 2 ? 2 : 1;
		return (at(seg, std::min(1.0, u + e)) - at(seg, std::max(0.0, u - e))) / ((std::min(1.0, u + e) - std::max(0.0, u - e)) * h);
	};
	// b is passed on the way up (chords 1 and 2 per s): Fritsch–Carlson's tangent 4/3, the same on both sides (C¹).
	EXPECT_NEAR(v(0, 1), 4.0 / 3, 1e-4);
	EXPECT_NEAR(v(1, 0), 4.0 / 3, 1e-4);
	// c is a turning point: a stop, as the thesis's curve; so are the ends (the face holds there).
	EXPECT_NEAR(v(1, 1), 0, 1e-4);
	EXPECT_NEAR(v(2, 0), 0, 1e-4);
	EXPECT_NEAR(v(0, 0), 0, 1e-4);
	EXPECT_NEAR(v(2, 1), 0, 1e-4);
	// No overshoot: each segment stays between its keyposes and moves one way.
	for (int seg = 0; seg < 3; ++seg) {
		const double lo = std::min(at(seg, 0), at(seg, 1)), hi = std::max(at(seg, 0), at(seg, 1));
		double last = at(seg, 0);
		for (double u = 0.01; u <= 1.0; u += 0.01) {
			const double x = at(seg, u);
			EXPECT_GE(x, lo - 1e-12);
			EXPECT_LE(x, hi + 1e-12);
			EXPECT_GE((x - last) * (at(seg, 1) - at(seg, 0)), -1e-12);
			last = x;
		}
	}
	// Keyposes on a straight line at even times: the spline is the line itself.
	const Points q0 = pt(0), q1 = pt(1), q2 = pt(2), q3 = pt(3);
	EXPECT_NEAR(Synthesizer::monotoneTrajectory({&q0, &q1, &q2, &q3}, {0, 1, 2, 3}, 0.25)(0, 0), 1.25, 1e-12);
	// No neighbours: the thesis's zero-tangent curve.
	EXPECT_LT((Synthesizer::monotoneTrajectory({nullptr, &a, &c, nullptr}, {0, 0, 1, 0}, 0.3) - Synthesizer::trajectory(a, c, 0.3, Trajectory::Hermite))
	              .cwiseAbs()
	              .maxCoeff(),
	          1e-12);
}

TEST(Synthesizer, framesAtKeyposeTimesMatchTheCorpusImages) {
	const SmallFace& f = smallFace();
	for (const WarpPath path : {WarpPath::Direct, WarpPath::Keypose})
	for (const std::string emotion : {"joy", "anger"}) {
		SynthOptions o;
		o.expression = Expression(Emotion::parse(emotion));
		o.warpPath = path;
		Synthesizer synth(f.model, o);
		// A timeline through every viseme of the model: 200 ms phones, keyposes at their midpoints.
		std::vector<PhoneSegment> phones;
		const std::vector<Cdv> order = {"sil", "a", "p1", "u", "f1", "i1", "sil"};
		for (std::size_t i = 0; i < order.size(); ++i) phones.push_back({ms(200 * long(i)), ms(200 * long(i) + 200), "", "", order[i], 0});
		auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
		ASSERT_EQ(keys.size(), order.size());
		synth.prepare(keys);
		EXPECT_TRUE(synth.substitutions().empty());
		Synthesizer::Workspace ws;
		for (const auto& k : keys) {
			Image8 frame;
			Points pts;
			synth.renderFrame(k.time, keys, ws, frame, pts);
			const long sample = f.model.findSample(emotion, k.cdv.label());
			ASSERT_GE(sample, 0);
			// The corpus image, its head jitter removed (warped to its aligned shape, where the keypose is drawn).
			const SynthFace& face = f.faces[std::size_t(sample)];
			const Points& aligned = f.model.alignedShapes[std::size_t(sample)];
			EXPECT_LT((pts - aligned).cwiseAbs().maxCoeff(), 1e-9) << "points at the keypose are its shape";
			PiecewiseAffineWarp w(f.model.frameMesh, withFrameBorder(aligned, 320, 180), 320, 180);
			w.setSource(withFrameBorder(face.points, 320, 180));
			Image8 truth(320, 180, 3);
			w.apply(face.image, truth);
			// The model's face region, drawn on the keypose's shape (its fully opaque part).
			const RegionSpec& spec = f.model.scheme.regions[0];
			const Points boundary = regionBoundary(spec, aligned);
			const std::vector<float> alpha = softRegionMask(boundary, spec.grow, spec.feather * std::sqrt(regionArea(boundary, spec.grow)), 320, 180);
			std::vector<std::uint8_t> mask(alpha.size());
			for (std::size_t i = 0; i < alpha.size(); ++i) mask[i] = alpha[i] > 0.99f;
			EXPECT_GE(psnr(toFloat(frame), toFloat(truth), mask), 30.0) << emotion << " " << k.cdv << (path == WarpPath::Direct ? " direct" : " keypose");
		}
		// Halfway between two keyposes the points are the midpoints of their shapes.
		Image8 frame;
		Points pts;
		const Ticks mid((keys[1].time.count() + keys[2].time.count()) / 2);
		synth.renderFrame(mid, keys, ws, frame, pts);
		const auto& a = f.model.alignedShapes[std::size_t(f.model.findSample(emotion, "a"))];
		const auto& p1 = f.model.alignedShapes[std::size_t(f.model.findSample(emotion, "p1"))];
		EXPECT_LT((pts - (a + p1) / 2).cwiseAbs().maxCoeff(), 1e-9);
	}
}

TEST(Synthesizer, missingEntriesFallBackAndSaySo) {
	const SmallFace& f = smallFace();
	SynthOptions o;
	o.expression = Expression(Emotion::of("fear"));  // not in the small model
	o.emotionSource = EmotionSource::Corpus;  // the corpus alone (the default, Auto, takes action units)
	Synthesizer synth(f.model, o);
	synth.keypose("a");
	synth.keypose("p2");  // not in the model at all: neutral p2 missing → the group's p1
	auto subs = synth.substitutions();
	ASSERT_EQ(subs.size(), 2u);
	EXPECT_EQ(subs[0], "fear a -> neutral a");
	EXPECT_EQ(subs[1], "fear p2 -> neutral p1");
}

TEST(Synthesizer, anEmotionTheModelLacksComesFromActionUnits) {
	// D48: fear is not in the small model. Auto takes it from the AU templates (the neutral sample, its
	// shape moved: brows up, lids wide); ActionUnits does that even for joy, which the model has.
	const SmallFace& f = smallFace();
	const int reb1 = f.model.scheme.indexOf("REB1"), rm2 = f.model.scheme.indexOf("RM2"), cum = f.model.scheme.indexOf("CUM");
	SynthOptions n;
	Synthesizer neutral(f.model, n);
	const Points rest = neutral.keypose("sil").shape;
	SynthOptions o;
	o.expression = Expression(Emotion::of("fear"));
	o.emotionSource = EmotionSource::Auto;
	o.auAppearance = false;
	Synthesizer fear(f.model, o);
	const KeyposeImage& k = fear.keypose("sil");
	EXPECT_EQ(k.usedEmotion, "fear (action units)");
	EXPECT_LT(k.shape(reb1, 1), rest(reb1, 1) - 2);            // AU1: the inner brow rises
	// The neutral appearance, reshaped; fear's units part the lips (AU25, AU26), which a warp of the shut
	// silence cannot show: the mouth's skin comes from the neutral sample whose mouth is nearest the
	// reshaped one (D71), and everything above the mouth stays the silence's own.
	ASSERT_GE(k.mouthSample, 0);
	const SampleInfo& mouth = f.model.samples[std::size_t(k.mouthSample)];
	EXPECT_EQ(mouth.emotion, "neutral");
	EXPECT_NE(mouth.cdv, "sil");
	const KeyposeImage& rested = neutral.keypose("sil");
	ASSERT_EQ(k.y.size(), rested.y.size());
	EXPECT_NE(k.y, rested.y);
	const std::size_t upper = k.y.size() / 2;  // the face box's upper half: brows, eyes, nose
	EXPECT_TRUE(std::equal(k.y.begin(), k.y.begin() + long(upper), rested.y.begin()));
	EXPECT_EQ(neutral.keypose("sil").mouthSample, -1);
	ASSERT_EQ(fear.substitutions().size(), 1u);
	EXPECT_EQ(fear.substitutions()[0], "fear from the neutral images by its action units (the model has no fear images)");
	if (installedAuAppearance({"AU1"})) {  // issue 31: with the appearance maps the skin changes too, the shape not
		o.auAppearance = true;
		Synthesizer skin(f.model, o);
		EXPECT_EQ(skin.keypose("sil").shape, k.shape);
		EXPECT_NE(skin.keypose("sil").y, k.y);
		o.auAppearance = false;
	}
	o.expression = Expression(Emotion::of("joy"));  // in the model: Auto uses the corpus
	Synthesizer joyCorpus(f.model, o);
	EXPECT_EQ(joyCorpus.keypose("sil").usedEmotion, "joy");
	o.emotionSource = EmotionSource::ActionUnits;
	Synthesizer joyAu(f.model, o);
	const Points smile = joyAu.keypose("sil").shape;
	EXPECT_LT(smile(rm2, 1) - smile(cum, 1), rest(rm2, 1) - rest(cum, 1) - 1);  // the corners rise against the lip
	EXPECT_TRUE(joyAu.substitutions().empty());  // asked for: not a substitution
	// A bilabial's closure overrides the units that part the lips (AU10, AU16, AU25, AU26): joy's /p/ stays
	// shut, its /a/ opens wider than neutral's.
	const int cium = f.model.scheme.indexOf("CIUM"), cilm = f.model.scheme.indexOf("CILM");
	auto gap = [&](const Points& p) { return p(cilm, 1) - p(cium, 1); };
	EXPECT_LE(gap(joyAu.keypose("p1").shape), gap(neutral.keypose("p1").shape) + 0.25);
	EXPECT_EQ(joyAu.keypose("p1").mouthSample, -1);
	EXPECT_GT(gap(joyAu.keypose("a").shape), gap(neutral.keypose("a").shape) + 1);
	// Intensity scales the action units.
	o.expression = Expression(o.expression.emotion(), 0.5);
	Synthesizer half(f.model, o);
	const Points mid = half.keypose("sil").shape;
	EXPECT_NEAR(mid(rm2, 1), 0.5 * (rest(rm2, 1) + smile(rm2, 1)), 1e-6);
}

TEST(Synthesizer, anEmotionWithoutASmileTakesAwayTheSmileAFacesOwnMouthBrings) {
	// D72: a face that grins as it opens its mouth (its /a/'s corners 3 px higher than the drawn face's).
	// Anger and hate (no AU12) bring its corners down to its shut mouths' level; joy keeps the grin.
	const FaceModel& plain = smallFace().model;
	FaceModel grinning = plain;
	const int rm2 = plain.scheme.indexOf("RM2"), lm2 = plain.scheme.indexOf("LM2");
	const long a = plain.findSample("neutral", "a");
	ASSERT_GE(a, 0);
	grinning.alignedShapes[std::size_t(a)](rm2, 1) -= 3, grinning.alignedShapes[std::size_t(a)](lm2, 1) -= 3;
	auto corners = [&](const FaceModel& m, const char* emotion) {
		SynthOptions o;
		o.expression = Expression(Emotion::of(emotion));
		o.emotionSource = EmotionSource::ActionUnits;
		o.auAppearance = false;
		Synthesizer s(m, o);
		const Points p = s.keypose("a").shape;
		return 0.5 * (p(rm2, 1) + p(lm2, 1));
	};
	for (const char* e : {"anger", "hate"}) {
		EXPECT_GE(corners(grinning, e), corners(plain, e) - 0.5) << e;  // the grin taken away (y grows down)
		EXPECT_GT(corners(grinning, e), corners(grinning, "joy") + 2) << e;
	}
	EXPECT_NEAR(corners(grinning, "joy"), corners(plain, "joy") - 3, 0.25);  // a smile keeps it
	// Intensity 0: nothing taken away (the neutral keypose).
	SynthOptions zero;
	zero.expression = Expression(Emotion::of("anger"), 0);
	zero.emotionSource = EmotionSource::ActionUnits;
	zero.auAppearance = false;
	Synthesizer none(grinning, zero), neutral(grinning, SynthOptions{});
	EXPECT_EQ(none.keypose("a").shape, neutral.keypose("a").shape);
}

namespace {
// Two seconds of silence and one action unit on the image's right half (the subject's left), rising at
// 0.5 s, held to 1.2 s, gone at 1.4 s; no blinks or head motion.
struct OneAuEvent {
	std::vector<Keypose> keys;
	ModulatorOptions mo;
	TimedEvents events;
	explicit OneAuEvent(const char* au) {
		keys = keyposes({{ms(0), ms(2000), "", "", "sil", 0}}, Ticks(kTicksPerSecond / 30));
		mo.blinks = false;
		mo.headMotion = false;
		AuEvent e;
		e.au = au;
		e.time = ms(500), e.onset = ms(200), e.apex = ms(500), e.offset = ms(200);
		e.side = 1;
		events.actionUnits = {e};
	}
};
}  // namespace

TEST(Synthesizer, actionUnitEventsMoveThePointsOnTheirSide) {
	const SmallFace& f = smallFace();
	const OneAuEvent ev("AU12");
	const auto& keys = ev.keys;
	const auto& mo = ev.mo;
	SynthOptions o;
	o.modulator = std::make_shared<ShapeModulator>(mo, Emotion::of("neutral"), ms(2000), keys, ev.events);
	Synthesizer synth(f.model, o);
	synth.prepare(keys);
	Synthesizer::Workspace ws;
	Image8 frame;
	Points before, apex, after;
	synth.renderFrame(ms(400), keys, ws, frame, before);
	synth.renderFrame(ms(900), keys, ws, frame, apex);
	synth.renderFrame(ms(1500), keys, ws, frame, after);
	const int rm2 = f.model.scheme.indexOf("RM2"), lm2 = f.model.scheme.indexOf("LM2");
	EXPECT_LT(apex(lm2, 1), before(lm2, 1) - 1);           // the image-right corner rises
	EXPECT_DOUBLE_EQ(apex(rm2, 1), before(rm2, 1));          // the other does not move
	EXPECT_LT((after - before).cwiseAbs().maxCoeff(), 1e-9);  // and it is over
	// A scheme without templates cannot take AU events: a clear error.
	FaceModel other = f.model;
	other.scheme.name = "no-such-scheme";
	EXPECT_THROW(Synthesizer(other, o), Error);
}

TEST(Synthesizer, actionUnitEventsChangeTheSkinOnTheirSideOnlyWhileTheyAct) {
	// Issue 31: a timed AU4 (brow lowerer) darkens the glabella's furrows through the installed maps, on
	// the side asked for, and only while it acts; the points move exactly as without the skin.
	if (!installedAuAppearance({"AU4"})) GTEST_SKIP() << "no models/au-appearance.bin built";
	const SmallFace& f = smallFace();
	const OneAuEvent ev("AU4");
	const auto& keys = ev.keys;
	const auto& mo = ev.mo;
	auto render = [&](bool skin, Ticks at, Points& points) {
		SynthOptions o;
		o.auAppearance = skin;
		o.modulator = std::make_shared<ShapeModulator>(mo, Emotion::of("neutral"), ms(2000), keys, ev.events);
		Synthesizer synth(f.model, o);
		synth.prepare(keys);
		Synthesizer::Workspace ws;
		Image8 frame;
		synth.renderFrame(at, keys, ws, frame, points);
		return frame;
	};
	Points p0, p1;
	EXPECT_EQ(render(true, ms(400), p0).data, render(false, ms(400), p1).data);  // before: nothing
	EXPECT_EQ(render(true, ms(1500), p0).data, render(false, ms(1500), p1).data);  // after: nothing
	const Image8 on = render(true, ms(900), p0), off = render(false, ms(900), p1);
	EXPECT_EQ(p0, p1);
	const double mid = 0.5 * (p0(f.model.scheme.indexOf("REB1"), 0) + p0(f.model.scheme.indexOf("LEB1"), 0));
	double leftChange = 0, rightChange = 0, darker = 0, brighter = 0;
	for (int y = 0; y < on.height; ++y)
		for (int x = 0; x < on.width; ++x)
			for (int c = 0; c < 3; ++c) {
				const int d = int(on.at(x, y, c)) - int(off.at(x, y, c));
				(x < mid ? leftChange : rightChange) += std::abs(d);
				(d < 0 ? darker : brighter) += std::abs(d);
			}
	EXPECT_GT(rightChange, 1000);
	EXPECT_LT(leftChange, 0.25 * rightChange);  // the midline's band takes half
	EXPECT_GT(darker, brighter);                // furrows are shadows
}

TEST(Synthesizer, sameInputsGiveTheSameFrames) {
	const SmallFace& f = smallFace();
	SynthOptions o;
	o.expression = Expression(Emotion::of("joy"));
	o.width = 640;
	o.height = 360;  // scaled output
	std::vector<PhoneSegment> phones = {{ms(0), ms(150), "", "", "a", 0}, {ms(150), ms(300), "", "", "u", 0}};
	auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	Image8 a, b;
	Points pa, pb;
	for (Image8* img : {&a, &b}) {
		Synthesizer s(f.model, o);
		s.prepare(keys);
		Synthesizer::Workspace ws;
		s.renderFrame(ms(110), keys, ws, *img, img == &a ? pa : pb);
	}
	EXPECT_EQ(a.width, 640);
	EXPECT_EQ(a.data, b.data);
	EXPECT_EQ(pa, pb);
}

namespace {
double planePsnr(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
	double se = 0;
	for (std::size_t i = 0; i < a.size(); ++i) se += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
	return psnrFromMse(se / double(a.size()));
}
}  // namespace

TEST(Synthesizer, yuvFramesAndBothWarpOrdersDrawTheSameFrame) {
	// renderFrameYuv (drawn in YUV 4:2:0) against the RGB frame converted; the direct warp against the
	// thesis's keypose order; mid-transition frames at a scaled output size.
	const SmallFace& f = smallFace();
	std::vector<PhoneSegment> phones = {{ms(0), ms(150), "", "", "a", 0}, {ms(150), ms(300), "", "", "p1", 0}, {ms(300), ms(450), "", "", "u", 0}};
	auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	SynthOptions o;
	o.expression = Expression(Emotion::of("joy"));
	o.width = 480;
	o.height = 270;
	Synthesizer direct(f.model, o);
	o.warpPath = WarpPath::Keypose;
	Synthesizer keypose(f.model, o);
	direct.prepare(keys);
	keypose.prepare(keys);
	Synthesizer::Workspace w1, w2, w3;
	for (long t : {0L, 110L, 160L, 260L, 400L}) {
		Image8 rgb, rgbKeypose;
		YuvImage yuv, converted;
		Points p1, p2, p3;
		direct.renderFrame(ms(t), keys, w1, rgb, p1);
		direct.renderFrameYuv(ms(t), keys, w2, yuv, p2);
		keypose.renderFrame(ms(t), keys, w3, rgbKeypose, p3);
		EXPECT_EQ(p1, p2);
		EXPECT_LT((p1 - p3).cwiseAbs().maxCoeff(), 1e-9);
		rgbToYuv420(rgb, converted);
		ASSERT_EQ(yuv.width, 480);
		EXPECT_GE(planePsnr(yuv.y, converted.y), 45.0) << t;
		EXPECT_GE(planePsnr(yuv.u, converted.u), 40.0) << t;
		EXPECT_GE(planePsnr(yuv.v, converted.v), 40.0) << t;
		EXPECT_GE(psnr(toFloat(rgb), toFloat(rgbKeypose)), 38.0) << t;
	}
}

TEST(Synthesizer, keyposesAreMadeOnlyForTheFramesThatNeedThem) {
	std::vector<Keypose> keys;
	for (long t : {100L, 300L, 500L, 700L}) keys.push_back(Keypose{ms(t), "a", 0, 0});
	auto times = [](const std::vector<Keypose>& k) {
		std::vector<long> v;
		for (const auto& x : k) v.push_back(long(x.time.count() / (kTicksPerSecond / 1000)));
		return v;
	};
	EXPECT_EQ(times(Synthesizer::keyposesBetween(keys, ms(350), ms(450))), (std::vector<long>{300, 500}));
	EXPECT_EQ(times(Synthesizer::keyposesBetween(keys, ms(0), ms(50))), (std::vector<long>{100}));      // hold before the first
	EXPECT_EQ(times(Synthesizer::keyposesBetween(keys, ms(800), ms(900))), (std::vector<long>{700}));   // and after the last
	EXPECT_EQ(times(Synthesizer::keyposesBetween(keys, ms(300), ms(520))), (std::vector<long>{300, 500, 700}));
	EXPECT_EQ(times(Synthesizer::keyposesBetween(keys, ms(350), ms(450), 1)), (std::vector<long>{100, 300, 500, 700}));  // Monotone looks one further
	// Substitutions are known before any keypose is made, and agree with the ones prepare() reports.
	const SmallFace& f = smallFace();
	SynthOptions o;
	o.expression = Expression(Emotion::of("fear"));
	Synthesizer synth(f.model, o);
	std::vector<Keypose> k2 = {Keypose{ms(100), "a", 0, 0}, Keypose{ms(300), "p2", 0, 0}};
	const auto planned = synth.substitutionsFor(k2);
	synth.prepare(k2);
	EXPECT_EQ(planned, synth.substitutions());
}

TEST(Synthesizer, monotoneFramesPreparedOneAtATimeMatchThoseOfAFullPrepare) {
	// As a live stream prepares them (render/live.cpp): only the keyposes each frame needs, margin() included.
	const SmallFace& f = smallFace();
	SynthOptions o;
	o.trajectory = Trajectory::Monotone;
	std::vector<PhoneSegment> phones = {{ms(0), ms(150), "", "", "sil", 0}, {ms(150), ms(300), "", "", "p1", 0}, {ms(300), ms(450), "", "", "a", 0},
	                                    {ms(450), ms(600), "", "", "u", 0}, {ms(600), ms(750), "", "", "sil", 0}};
	const auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	Synthesizer whole(f.model, o), piecewise(f.model, o);
	whole.prepare(keys);
	Synthesizer::Workspace ws;
	Image8 a, b;
	Points pa, pb;
	for (long t = 0; t <= 750; t += 33) {
		piecewise.prepare(Synthesizer::keyposesBetween(keys, ms(t), ms(t), piecewise.margin()));
		whole.renderFrame(ms(t), keys, ws, a, pa);
		piecewise.renderFrame(ms(t), keys, ws, b, pb);
		EXPECT_EQ(a.data, b.data) << t << " ms";
		EXPECT_EQ(pa, pb) << t << " ms";
	}
}

TEST(Synthesizer, theBackgroundBeyondTheAnchorsNeverMovesAndReusedBuffersDrawTheSameFrames) {
	// D41: pixels that change from frame to frame all lie within the anchors (at most 2 margins outside the
	// hull of every training shape); a buffer that holds an earlier frame, redrawn with outHoldsFrame, gets
	// the same bytes as a fresh one (RGB and YUV).
	const SmallFace& f = smallFace();
	SynthOptions o;
	o.expression = Expression(Emotion::of("joy"));
	Synthesizer synth(f.model, o);
	std::vector<PhoneSegment> phones = {{ms(0), ms(150), "", "", "a", 0}, {ms(150), ms(300), "", "", "p1", 0}, {ms(300), ms(450), "", "", "u", 0},
	                                    {ms(450), ms(600), "", "", "i1", 0}};
	auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	synth.prepare(keys);
	std::vector<cv::Point2f> all, hull;
	for (const auto& s : f.model.alignedShapes)
		for (Eigen::Index i = 0; i < s.rows(); ++i) all.emplace_back(float(s(i, 0)), float(s(i, 1)));
	cv::convexHull(all, hull);
	const Eigen::RowVector2d extent = f.model.meanShape.colwise().maxCoeff() - f.model.meanShape.colwise().minCoeff();
	const double limit = 2 * 0.15 * extent.maxCoeff() + 2;
	Synthesizer::Workspace w1, w2;
	Image8 first, reused;
	YuvImage reusedYuv;
	int changed = 0;
	for (long t = 0; t <= 600; t += 33) {
		Image8 fresh;
		YuvImage freshYuv;
		Points p1, p2;
		synth.renderFrame(ms(t), keys, w1, fresh, p1);
		synth.renderFrame(ms(t), keys, w2, reused, p2, t > 0);
		ASSERT_EQ(fresh.data, reused.data) << t;
		synth.renderFrameYuv(ms(t), keys, w1, freshYuv, p1);
		synth.renderFrameYuv(ms(t), keys, w2, reusedYuv, p2, t > 0);
		ASSERT_EQ(freshYuv.y, reusedYuv.y) << t;
		ASSERT_EQ(freshYuv.u, reusedYuv.u) << t;
		ASSERT_EQ(freshYuv.v, reusedYuv.v) << t;
		if (t == 0) {
			first = fresh;
			continue;
		}
		for (int y = 0; y < fresh.height; ++y)
			for (int x = 0; x < fresh.width; ++x)
				if (std::memcmp(fresh.row(y) + 3 * x, first.row(y) + 3 * x, 3) != 0) {
					++changed;
					EXPECT_GE(cv::pointPolygonTest(hull, cv::Point2f(float(x), float(y)), true), -limit) << x << "," << y << " at " << t << " ms";
				}
	}
	EXPECT_GT(changed, 1000);  // the face does move
}

namespace {
std::vector<Keypose> speechKeys(long ms0, long ms1) {
	std::vector<PhoneSegment> phones;
	const std::vector<Cdv> order = {"a", "p1", "u", "f1", "i1"};
	long t = ms0;
	for (std::size_t i = 0; t < ms1; ++i, t += 150) phones.push_back({ms(t), ms(t + 150), "", "", order[i % order.size()], 0});
	return keyposes(phones, Ticks(kTicksPerSecond / 30));
}
}  // namespace

TEST(ShapeModulator, blinksCloseTheEyesAndOpenThemAgainSeeded) {
	// D42: during a blink the lid distance (upper-lid to lower-lid point of the landmark output) falls to
	// ≤ 10 % of the open eye's and is back after it; the same seed gives the same blinks; blinks off gives
	// none and the same points as no modulator.
	const SmallFace& f = smallFace();
	const auto keys = speechKeys(0, 6000);
	ModulatorOptions mo;
	mo.headMotion = false;
	mo.seed = 7;
	auto mod = std::make_shared<ShapeModulator>(mo, Emotion::of("joy"), ms(6000), keys);
	ASSERT_GE(mod->blinks().size(), 1u);
	EXPECT_EQ(ShapeModulator(mo, Emotion::of("joy"), ms(6000), keys).blinks().size(), mod->blinks().size());
	EXPECT_EQ(ShapeModulator(mo, Emotion::of("joy"), ms(6000), keys).blinks()[0].start, mod->blinks()[0].start);
	mo.seed = 8;
	EXPECT_NE(ShapeModulator(mo, Emotion::of("joy"), ms(6000), keys).blinks()[0].start, mod->blinks()[0].start);
	SynthOptions o;
	o.expression = Expression(Emotion::of("joy"));
	Synthesizer plain(f.model, o);
	o.modulator = mod;
	Synthesizer blinking(f.model, o);
	plain.prepare(keys);
	blinking.prepare(keys);
	const int up = f.model.scheme.indexOf("REYE2"), down = f.model.scheme.indexOf("REYE4");
	Synthesizer::Workspace w1, w2;
	YuvImage frame;
	Points p0, p1;
	auto opening = [&](const Points& p) { return p(down, 1) - p(up, 1); };
	for (const BlinkEvent& b : mod->blinks()) {
		EXPECT_GE(toSeconds(b.end() - b.start), 0.1);
		EXPECT_LE(toSeconds(b.end() - b.start), 0.3);
		EXPECT_LT(b.closing, b.opening);
		const Ticks shut = b.start + b.closing + b.closed / 2, after = b.end() + ms(1);
		plain.renderFrameYuv(shut, keys, w1, frame, p0);
		blinking.renderFrameYuv(shut, keys, w2, frame, p1);
		EXPECT_LE(opening(p1), 0.1 * opening(p0)) << toSeconds(shut);
		plain.renderFrameYuv(after, keys, w1, frame, p0);
		blinking.renderFrameYuv(after, keys, w2, frame, p1);
		EXPECT_LT((p1 - p0).cwiseAbs().maxCoeff(), 1e-9) << "open again after the blink";
	}
	mo.blinks = false;
	EXPECT_TRUE(ShapeModulator(mo, Emotion::of("joy"), ms(6000), keys).blinks().empty());
}

TEST(ShapeModulator, anEmotionsBlinksAndHeadScaleWithItsIntensityFromNeutrals) {
	// Issue 31: intensity 0 is neutral in everything (blinks and head motion too, so a render at 0 is
	// byte-identical to neutral's); 1 the emotion's; half-way half-way; beyond, further.
	const auto keys = speechKeys(0, 60000);
	ModulatorOptions mo;
	mo.seed = 3;
	const ShapeModulator neutral(mo, Emotion::of("neutral"), ms(60000), keys);
	mo.intensity = 0;
	const ShapeModulator fear0(mo, Emotion::of("fear"), ms(60000), keys);
	ASSERT_EQ(fear0.blinks().size(), neutral.blinks().size());
	for (std::size_t i = 0; i < neutral.blinks().size(); ++i) EXPECT_EQ(fear0.blinks()[i].start, neutral.blinks()[i].start);
	EXPECT_EQ(fear0.maxAngle(), neutral.maxAngle());
	mo.intensity = 1;
	const ShapeModulator fear(mo, Emotion::of("fear"), ms(60000), keys);
	mo.intensity = 0.5;
	const ShapeModulator half(mo, Emotion::of("fear"), ms(60000), keys);
	EXPECT_NEAR(fear.maxAngle(), 0.6 * neutral.maxAngle(), 1e-12);  // fear's head is subdued (0.6)
	EXPECT_NEAR(half.maxAngle(), 0.8 * neutral.maxAngle(), 1e-12);
	EXPECT_LT(fear.blinks().size(), half.blinks().size());  // fear blinks 10 a minute, neutral 17
	EXPECT_LT(half.blinks().size(), neutral.blinks().size());
}

TEST(ShapeModulator, headMotionHasTheAmplitudeAskedForAndKeepsTheFaceInTheFrame) {
	const SmallFace& f = smallFace();
	const auto keys = speechKeys(0, 30000);
	for (double amplitude : {1.0, 2.0}) {
		ModulatorOptions mo;
		mo.blinks = false;
		mo.headAmplitude = amplitude;
		auto mod = std::make_shared<ShapeModulator>(mo, Emotion::of("neutral"), ms(30000), keys);
		EXPECT_NEAR(mod->maxAngle(), amplitude * 1.5 * M_PI / 180, 1e-12);
		double peak = 0;
		for (long t = 0; t < 30000; t += 20) peak = std::max(peak, std::abs(mod->head(ms(t)).angle));
		EXPECT_LE(peak, mod->maxAngle() + 1e-12);
		EXPECT_GE(peak, 0.6 * mod->maxAngle()) << "the motion reaches its amplitude";
		// Smooth: no jump between frames larger than 1/10 of the amplitude.
		for (long t = 0; t < 30000; t += 33)
			EXPECT_LT(std::abs(mod->head(ms(t + 33)).angle - mod->head(ms(t)).angle), 0.1 * mod->maxAngle());
		SynthOptions o;
		o.expression = Expression(Emotion::of("joy"));
		o.modulator = mod;
		Synthesizer synth(f.model, o);
		synth.prepare(keys);
		Synthesizer::Workspace ws;
		YuvImage frame;
		Points p;
		for (long t = 0; t < 30000; t += 500) {
			synth.renderFrameYuv(ms(t), keys, ws, frame, p);
			EXPECT_GE(p.col(0).minCoeff(), 0);
			EXPECT_GE(p.col(1).minCoeff(), 0);
			EXPECT_LE(p.col(0).maxCoeff(), 319);
			EXPECT_LE(p.col(1).maxCoeff(), 179);
		}
	}
	ModulatorOptions still;
	still.blinks = false;
	still.headMotion = false;
	EXPECT_EQ(ShapeModulator(still, Emotion::of("joy"), ms(3000), keys).head(ms(1000)).angle, 0);
}

TEST(Synthesizer, intensityGoesFromTheNeutralKeyposesToTheEmotionAndBeyond) {
	// D43: intensity 0 draws the neutral keyposes (the same frames as --emotion neutral); the mouth corners
	// rise steadily with joy's intensity and the brows come down with anger's.
	const SmallFace& f = smallFace();
	std::vector<PhoneSegment> phones = {{ms(0), ms(150), "", "", "a", 0}, {ms(150), ms(300), "", "", "p1", 0}};
	const auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	auto frame = [&](const std::string& emotion, double intensity, long t) {
		SynthOptions o;
		o.expression = Expression(Emotion::parse(emotion), intensity);
		Synthesizer s(f.model, o);
		s.prepare(keys);
		Synthesizer::Workspace ws;
		YuvImage out;
		Points p;
		s.renderFrameYuv(ms(t), keys, ws, out, p);
		return std::make_pair(out.y, p);
	};
	for (long t : {0L, 110L, 250L}) {
		EXPECT_EQ(frame("joy", 0, t).first, frame("neutral", 1, t).first) << t;
		EXPECT_EQ(frame("anger", 0, t).second, frame("neutral", 1, t).second) << t;
	}
	const int corner = f.model.scheme.indexOf("RM2"), brow = f.model.scheme.indexOf("REB2"), eye = f.model.scheme.indexOf("REYE1");
	double lastCorner = 1e9, lastBrow = -1e9;
	for (double i : {0.0, 0.5, 1.0, 1.5}) {
		const Points joy = frame("joy", i, 0).second, anger = frame("anger", i, 0).second;
		const double cornerHeight = joy(corner, 1), browGap = anger(eye, 1) - anger(brow, 1);  // y grows downwards
		EXPECT_LT(cornerHeight, lastCorner - 0.05) << "joy " << i;
		EXPECT_GT(-browGap, lastBrow + 0.05) << "anger " << i;
		lastCorner = cornerHeight, lastBrow = -browGap;
	}
}

TEST(Synthesizer, keyposesTakeTheirOwnEmotionWhenATrackSetsIt) {
	// Issue 13 §2: keyposes before an emotion change come from the first emotion, after it from the second.
	const SmallFace& f = smallFace();
	std::vector<PhoneSegment> phones = {{ms(0), ms(200), "", "", "a", 0}, {ms(200), ms(400), "", "", "u", 0}, {ms(400), ms(600), "", "", "a", 0},
	                                    {ms(600), ms(800), "", "", "u", 0}};
	auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	ASSERT_EQ(keys.size(), 4u);
	keys[2].emotion = keys[3].emotion = Emotion::of("anger");
	keys[2].intensity = keys[3].intensity = 1;
	SynthOptions o;
	o.expression = Expression(Emotion::of("joy"));
	Synthesizer synth(f.model, o);
	synth.prepare(keys);
	Synthesizer::Workspace ws;
	YuvImage frame;
	Points p;
	for (std::size_t i = 0; i < keys.size(); ++i) {
		synth.renderFrameYuv(keys[i].time, keys, ws, frame, p);
		const long sample = f.model.findSample(i < 2 ? "joy" : "anger", keys[i].cdv.label());
		ASSERT_GE(sample, 0);
		EXPECT_LT((p - f.model.alignedShapes[std::size_t(sample)]).cwiseAbs().maxCoeff(), 1e-9) << i;
	}
}

TEST(ShapeModulator, browsRiseForARaiseAndComeDownAndTogetherForAFrown) {
	// D46: at the apex of a raise every brow point is 10 % of the eye distance higher; a frown lowers the
	// inner ends by 6 % and draws them toward the midline; before and after, the brows are at rest.
	const SmallFace& f = smallFace();
	const auto keys = speechKeys(0, 3000);
	ModulatorOptions mo;
	mo.blinks = mo.headMotion = false;
	TimedEvents events;
	events.brows = {BrowEvent{ms(500), ms(800), 1, 0}, BrowEvent{ms(2000), ms(800), 0, 1}};
	SynthOptions o;
	o.expression = Expression(Emotion::of("joy"));
	Synthesizer plain(f.model, o);
	o.modulator = std::make_shared<ShapeModulator>(mo, Emotion::of("joy"), ms(3000), keys, events);
	Synthesizer moved(f.model, o);
	plain.prepare(keys);
	moved.prepare(keys);
	Synthesizer::Workspace w1, w2;
	YuvImage frame;
	auto at = [&](Synthesizer& s, Synthesizer::Workspace& w, long t) {
		Points p;
		s.renderFrameYuv(ms(t), keys, w, frame, p);
		return p;
	};
	const Points& m = f.model.meanShape;
	const double eyes = ((m.row(f.model.scheme.indexOf("REYE1")) + m.row(f.model.scheme.indexOf("REYE3"))) / 2 -
	                     (m.row(f.model.scheme.indexOf("LEYE1")) + m.row(f.model.scheme.indexOf("LEYE3"))) / 2).norm();
	const int inner = f.model.scheme.indexOf("REB1"), outer = f.model.scheme.indexOf("REB3"), innerLeft = f.model.scheme.indexOf("LEB1");
	const Points rest = at(plain, w1, 900), raised = at(moved, w2, 900);  // the raise's plateau
	EXPECT_NEAR(rest(inner, 1) - raised(inner, 1), 0.10 * eyes, 1e-6);
	EXPECT_NEAR(rest(outer, 1) - raised(outer, 1), 0.10 * eyes, 1e-6);
	const Points rest2 = at(plain, w1, 2400), frowned = at(moved, w2, 2400);
	EXPECT_NEAR(frowned(inner, 1) - rest2(inner, 1), 0.06 * eyes, 1e-6);
	EXPECT_NEAR(frowned(outer, 1) - rest2(outer, 1), 0.03 * eyes, 1e-6);
	const double gapRest = std::abs(rest2(innerLeft, 0) - rest2(inner, 0)), gapFrown = std::abs(frowned(innerLeft, 0) - frowned(inner, 0));
	EXPECT_NEAR(gapRest - gapFrown, 0.10 * eyes, 1e-6);  // each inner end 5 % closer to the midline
	EXPECT_LT((at(moved, w2, 1500) - at(plain, w1, 1500)).cwiseAbs().maxCoeff(), 1e-9);  // between the two: at rest
}

TEST(ShapeModulator, speechBrowsRiseOnEachPhrasesLongestVowel) {
	// D49. Phones (start, end in ms, phone, CDV): a short phrase, a 300-ms pause, a long phrase.
	auto seg = [](long a, long b, const char* phone, const char* cdv) { return PhoneSegment{ms(a), ms(b), phone, phone, Cdv::of(cdv), 0}; };
	std::vector<PhoneSegment> phones = {seg(0, 100, "p", "p1"), seg(100, 180, "a", "a"), seg(180, 260, "t", "t1"), seg(260, 420, "u", "u"),
	                                    seg(420, 1500, "_", "sil")};  // the longest vowel: [u]; then a pause
	const std::vector<PhoneSegment> second = {
	    seg(0, 80, "s", "s1"),       seg(80, 280, "e", "e"),      seg(280, 380, "l", "l1"), seg(380, 460, "i", "i1"),
	    seg(460, 580, "m", "p1"),    seg(580, 680, "o", "o"),     seg(680, 780, "k", "k1"), seg(780, 1280, "k", "k1"),
	    seg(1280, 1380, "i", "i1"),  seg(1380, 1580, "a", "a"),   seg(1580, 1880, "t", "t1"), seg(1880, 2020, "ɔ", "ɔ"),
	    seg(2020, 2180, "s", "s1"),  seg(2180, 2480, "a", "a"),   seg(2480, 2580, "_", "sil")};
	for (PhoneSegment p : second) p.start += ms(1500), p.end += ms(1500), phones.push_back(p);
	const auto brows = speechBrows(phones);
	// The first phrase: its 160-ms [u]; the second (2.48 s) its longest vowel (the 300-ms [a] at 3.68 s)
	// and, in its first half, the 200-ms [e] at 1.58 s.
	ASSERT_EQ(brows.size(), 3u);
	EXPECT_EQ(brows[0].time, ms(260 - 80));
	EXPECT_EQ(brows[0].duration, ms(160 + 350));
	EXPECT_EQ(brows[1].time, ms(1580 - 80));
	EXPECT_EQ(brows[2].time, ms(3680 - 80));
	EXPECT_DOUBLE_EQ(brows[0].raise, 0.5);
	EXPECT_DOUBLE_EQ(speechBrows(phones, 2)[0].raise, 1.0);
	EXPECT_TRUE(speechBrows(phones, 0).empty());
	// Never two within 1.2 s: a second phrase right after the first gives way.
	std::vector<PhoneSegment> close = {seg(0, 100, "a", "a"), seg(100, 300, "e", "e"), seg(300, 500, "_", "sil"),
	                                   seg(500, 600, "o", "o"), seg(600, 800, "u", "u")};
	EXPECT_EQ(speechBrows(close).size(), 1u);
}

namespace {
// A small synthetic corpus (neutral sil and a) with a closed-eyes image last (D50).
struct EyesShutCorpus {
	SynthCorpusOptions o;
	std::vector<SynthItem> items;
	std::vector<SynthFace> faces;
	std::vector<Points> shapes;
	std::vector<SampleInfo> samples;
};
EyesShutCorpus eyesShutCorpus() {
	EyesShutCorpus c;
	c.o.width = 320;
	c.o.height = 180;
	c.o.emotions = {"neutral"};
	c.o.visemes = {"sil", "a"};
	c.items = synthCorpusItems(c.o);
	c.items.push_back(closedEyesItem(c.o));
	FaceRenderer r(c.o.width, c.o.height);
	for (const auto& it : c.items) {
		c.faces.push_back(r.render(it.articulation, it.actionUnits, it.pose));
		c.shapes.push_back(c.faces.back().points);
		c.samples.push_back(SampleInfo{it.fileName, it.emotion, it.viseme, it.word, it.context});
	}
	return c;
}
// Two seconds at rest, and a modulator with one blink at 1 s and nothing else; returns when the lids are shut.
std::vector<Keypose> restingKeys() { return keyposes({{ms(0), ms(2000), "", "", "sil", 0}}, Ticks(kTicksPerSecond / 30)); }
Ticks oneBlink(SynthOptions& o, const std::vector<Keypose>& keys) {
	ModulatorOptions mo;
	mo.blinks = false;
	mo.headMotion = false;
	TimedEvents events;
	events.blinks = {ms(1000)};
	o.modulator = std::make_shared<ShapeModulator>(mo, Emotion::of("neutral"), ms(2000), keys, events);
	return o.modulator->blinks().at(0).start + o.modulator->blinks().at(0).closing + ms(10);
}
}  // namespace

TEST(Synthesizer, blinksTakeTheShutLidFromTheCorpusClosedEyeImage) {
	// D50: a model whose corpus has a closed-eyes image draws the shut lid's skin from it.
	const EyesShutCorpus c = eyesShutCorpus();
	const std::vector<SynthItem>& items = c.items;
	const std::vector<SynthFace>& faces = c.faces;
	const std::vector<Points>& shapes = c.shapes;
	const std::vector<SampleInfo>& samples = c.samples;
	const SynthCorpusOptions& o = c.o;
	const int reye2 = loadScheme("ch-unicamp-56").indexOf("REYE2"), reye4 = loadScheme("ch-unicamp-56").indexOf("REYE4");
	EXPECT_LT(std::abs(shapes.back()(reye2, 1) - shapes.back()(reye4, 1)), 0.5);  // the image's lids meet
	NullProgress quiet;
	BuildOptions with;
	with.closedEyes = long(items.size() - 1);
	auto source = [&](std::size_t i) { return faces[i].image; };
	const FaceModel a = buildFaceModel(loadScheme("ch-unicamp-56"), shapes, samples, o.width, o.height, source, with, quiet);
	const FaceModel b = buildFaceModel(loadScheme("ch-unicamp-56"), shapes, samples, o.width, o.height, source, BuildOptions{}, quiet);
	EXPECT_EQ(a.closedEyesIndex, long(items.size() - 1));
	EXPECT_EQ(b.closedEyesIndex, -1);
	const std::vector<Keypose> keys = restingKeys();
	SynthOptions so;
	const Ticks shut = oneBlink(so, keys);
	Synthesizer sa(a, so), sb(b, so);
	sa.prepare(keys), sb.prepare(keys);
	Synthesizer::Workspace wa, wb;
	Image8 fa, fb, oa, ob;
	Points pa, pb;
	sa.renderFrame(ms(400), keys, wa, oa, pa);
	sb.renderFrame(ms(400), keys, wb, ob, pb);
	EXPECT_EQ(oa.data, ob.data);  // eyes open: the same frame
	sa.renderFrame(shut, keys, wa, fa, pa);
	sb.renderFrame(shut, keys, wb, fb, pb);
	// The shut eye against the closed-eyes image warped to the frame's points, over the eyes' box.
	PiecewiseAffineWarp w(a.frameMesh, withFrameBorder(pa, 320, 180), 320, 180);
	w.setSource(withFrameBorder(faces.back().points, 320, 180));
	Image8 truth(320, 180, 3);
	w.apply(faces.back().image, truth);
	const Scheme sc = loadScheme("ch-unicamp-56");
	std::vector<std::uint8_t> mask(320 * 180, 0);
	double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
	for (const char* n : {"REYE1", "REYE3", "LEYE1", "LEYE3", "REB2", "LEB2"}) {
		const int i = sc.indexOf(n);
		x0 = std::min(x0, pa(i, 0)), x1 = std::max(x1, pa(i, 0)), y0 = std::min(y0, pa(i, 1)), y1 = std::max(y1, pa(i, 1));
	}
	for (int y = int(y0); y <= int(y1 + 3); ++y)
		for (int x = int(x0); x <= int(x1); ++x) mask[std::size_t(y) * 320 + std::size_t(x)] = 1;
	EXPECT_NE(fa.data, fb.data);
	const double corpusLid = psnr(toFloat(fa), toFloat(truth), mask), drawnLid = psnr(toFloat(fb), toFloat(truth), mask);
	EXPECT_GT(corpusLid, drawnLid + 1.0) << corpusLid << " dB vs " << drawnLid << " dB";
	std::fprintf(stderr, "shut eye against the closed-eyes image: %.1f dB (corpus lid), %.1f dB (drawn lid)\n", corpusLid, drawnLid);
}

TEST(Face, itsPartsAreMadeOnceAndSharedBySynthesizersThatDrawTheSameFrames) {
	// Issue 46: the model's parts (the closed-eye composite, the AU templates) belong to a Face made once;
	// synthesizers drawing it share them and draw what a synthesizer of the model alone draws.
	const EyesShutCorpus c = eyesShutCorpus();
	NullProgress quiet;
	BuildOptions with;
	with.closedEyes = long(c.items.size() - 1);
	const FaceModel model = buildFaceModel(loadScheme("ch-unicamp-56"), c.shapes, c.samples, c.o.width, c.o.height, [&](std::size_t i) { return c.faces[i].image; }, with, quiet);
	const Face face(model);
	const Image8& closed = face.closedEyes();
	ASSERT_EQ(closed.width, model.width);
	EXPECT_EQ(&face.closedEyes(), &closed);  // made once
	EXPECT_TRUE(Face(smallFace().model).closedEyes().empty());  // no closed-eyes sample: none
	const AuTemplates* templates = face.auTemplates();
	ASSERT_NE(templates, nullptr);  // models/au-templates/ch-unicamp-56.tsv
	EXPECT_EQ(face.auTemplates(), templates);
	EXPECT_EQ(face.coarticulation(), nullptr);
	const std::vector<Keypose> keys = restingKeys();
	SynthOptions so;
	so.expression = Expression(Emotion::of("joy"));  // not in the model: its action units (the templates)
	const Ticks shut = oneBlink(so, keys);
	Synthesizer a(face, so), b(face, so), alone(model, so);
	for (Synthesizer* s : {&a, &b, &alone}) s->prepare(keys);
	Synthesizer::Workspace wa, wb, wc;
	Image8 fa, fb, fc;
	Points pa, pb, pc;
	a.renderFrame(shut, keys, wa, fa, pa);
	b.renderFrame(shut, keys, wb, fb, pb);
	alone.renderFrame(shut, keys, wc, fc, pc);
	EXPECT_EQ(fa.data, fb.data);
	EXPECT_EQ(fa.data, fc.data);
}

TEST(Synthesizer, theThesisWarpOrderDrawsTheShutLidsToo) {
	// --warp keypose never builds the mean frame the lids are drawn in: blink frames go back to it and
	// forward again, and agree with the direct order's.
	const SmallFace& f = smallFace();
	const std::vector<Keypose> keys = restingKeys();
	SynthOptions o;
	const Ticks shut = oneBlink(o, keys);
	Image8 direct, thesis, open;
	Points p;
	{
		Synthesizer s(f.model, o);
		s.prepare(keys);
		Synthesizer::Workspace ws;
		s.renderFrame(shut, keys, ws, direct, p);
	}
	o.warpPath = WarpPath::Keypose;
	Synthesizer s(f.model, o);
	s.prepare(keys);
	Synthesizer::Workspace ws;
	s.renderFrame(shut, keys, ws, thesis, p);
	s.renderFrame(ms(400), keys, ws, open, p);
	const Scheme sc = loadScheme("ch-unicamp-56");
	std::vector<std::uint8_t> eyes(320 * 180, 0);
	const int r1 = sc.indexOf("REYE1"), l1 = sc.indexOf("LEYE1"), r2 = sc.indexOf("REYE2");
	for (int y = int(p(r2, 1)) - 6; y <= int(p(r2, 1)) + 6; ++y)
		for (int x = int(p(r1, 0)); x <= int(p(l1, 0)); ++x) eyes[std::size_t(y) * 320 + std::size_t(x)] = 1;
	EXPECT_GT(psnr(toFloat(thesis), toFloat(direct), eyes), 30.0);
	EXPECT_LT(psnr(toFloat(thesis), toFloat(open), eyes), 25.0);  // and the eyes are not open
}

TEST(Synthesizer, aCdvAnEmotionsTakeLacksComesFromTheNeutralMouthMovedByItsActionUnits) {
	// Issue 47: joy recorded without /a/ (a short take). Auto draws joy's /a/ from the neutral /a/ with joy's
	// action units — not neutral's /a/ as it is (no joy left) nor joy's shut silence — and says so; joy's own
	// CDVs stay its own, and the corpus alone (EmotionSource::Corpus) keeps the old fallback.
	FaceModel model = smallFace().model;
	const long joyA = model.findSample("joy", "a");
	ASSERT_GE(joyA, 0);
	model.samples[std::size_t(joyA)].emotion = "-";  // unlabelled: joy has no /a/ now
	SynthOptions o;
	o.expression = Expression(Emotion::of("joy"));
	o.emotionSource = EmotionSource::Auto;
	o.auAppearance = false;
	Synthesizer joy(model, o);
	const KeyposeImage& a = joy.keypose("a");
	EXPECT_EQ(a.usedEmotion, "joy (action units)");
	EXPECT_EQ(joy.keypose("u").usedEmotion, "joy");  // its own
	ASSERT_EQ(joy.substitutions().size(), 1u);
	EXPECT_EQ(joy.substitutions()[0], "joy a -> neutral a with joy's action units (the model's joy has no a nor its group)");
	SynthOptions n;
	Synthesizer neutral(model, n);
	const int rm2 = model.scheme.indexOf("RM2"), cum = model.scheme.indexOf("CUM"), cium = model.scheme.indexOf("CIUM"), cilm = model.scheme.indexOf("CILM");
	const Points& na = neutral.keypose("a").shape;
	EXPECT_LT(a.shape(rm2, 1) - a.shape(cum, 1), na(rm2, 1) - na(cum, 1) - 1);  // joy's corners rise against the lip
	EXPECT_GT(a.shape(cilm, 1) - a.shape(cium, 1), 1.0);                          // and the mouth is open
	o.emotionSource = EmotionSource::Corpus;
	Synthesizer corpus(model, o);
	EXPECT_EQ(corpus.keypose("a").usedEmotion, "neutral");
}

TEST(Synthesizer, aCdvNoTakeHasShowsTheNearestMouthTheEmotionHasNotItsShutRest) {
	// Issue 47: /ɪ/ is in no take of the small model (neither joy nor neutral nor a group of its own). It
	// showed joy's shut silence; now the joy mouth nearest its articulatory target (phonetics/cdv-mouth-
	// targets.tsv): /i1/. A bilabial's nearest is still the shut mouth.
	const SmallFace& f = smallFace();
	SynthOptions o;
	o.expression = Expression(Emotion::of("joy"));
	Synthesizer joy(f.model, o);
	const KeyposeImage& k = joy.keypose("ɪ");
	EXPECT_EQ(k.usedEmotion, "joy");
	EXPECT_EQ(k.usedCdv, "i1");
	EXPECT_EQ(joy.substitutions(), (std::vector<std::string>{"joy ɪ -> joy i1"}));
	EXPECT_LT(Cdv("p2").mouthDistance(Cdv("p1")), Cdv("p2").mouthDistance(Cdv("a")));
	EXPECT_EQ(Cdv("a").mouthDistance(Cdv("u")), Cdv("u").mouthDistance(Cdv("a")));
	EXPECT_EQ(Cdv("a").mouthDistance(Cdv("a")), 0.0);
	EXPECT_GT(Cdv("a").mouthDistance(Cdv()), Cdv("p1").mouthDistance(Cdv()));  // the open vowel is far from the rest
}

namespace {
// Variance of the 4-neighbour Laplacian of the green channel in [x0, x1) × [y0, y1).
double laplacianVariance(const Image8& im, int x0, int y0, int x1, int y1) {
	double s = 0, s2 = 0;
	long n = 0;
	for (int y = y0; y < y1; ++y)
		for (int x = x0; x < x1; ++x) {
			const double l = double(im.at(x - 1, y, 1)) + im.at(x + 1, y, 1) + im.at(x, y - 1, 1) + im.at(x, y + 1, 1) - 4.0 * im.at(x, y, 1);
			s += l, s2 += l * l, ++n;
		}
	return s2 / double(n) - (s / double(n)) * (s / double(n));
}

Image8 keyposeFrame(const FaceModel& model, Resampling r, int width, int height, Points& pts) {
	SynthOptions o;
	o.resampling = r;
	o.dissolveDetail = false;  // the prefilter alone (D84); the dissolve's detail has its own test (D88)
	o.width = width, o.height = height;
	Synthesizer synth(model, o);
	std::vector<PhoneSegment> phones;
	const std::vector<Cdv> order = {"sil", "a", "u", "sil"};
	for (std::size_t i = 0; i < order.size(); ++i) phones.push_back({ms(200 * long(i)), ms(200 * long(i) + 200), "", "", order[i], 0});
	const auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	synth.prepare(keys);
	Synthesizer::Workspace ws;
	Image8 frame;
	synth.renderFrame(Ticks((keys[1].time.count() + keys[2].time.count()) / 2), keys, ws, frame, pts);  // between a and u
	return frame;
}
}  // namespace

TEST(Synthesizer, sharpResamplingRestoresTheMovingMouthsDetailAndLeavesWhatNeverMovesAlone) {
	// Issue 47, D84: the images the frame warp samples are prefiltered where it resamples them. At the
	// model's size the static background is copied, not resampled: byte for byte what linear draws; the
	// mouth, which moves, has more fine detail than bilinear leaves it. Enlarged, the whole frame is
	// resampled and sharpened.
	const SmallFace& f = smallFace();
	Points pts, unused;
	const Image8 sharp = keyposeFrame(f.model, Resampling::Sharp, 0, 0, pts), linear = keyposeFrame(f.model, Resampling::Linear, 0, 0, unused);
	const Scheme& sc = f.model.scheme;
	double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
	for (int i = 0; i < sc.pointCount(); ++i)
		if (const std::string& n = sc.pointNames[std::size_t(i)]; n == "CUM" || n == "CLM" || n.rfind("RM", 0) == 0 || n.rfind("LM", 0) == 0 || n.rfind("CI", 0) == 0)
			x0 = std::min(x0, pts(i, 0)), x1 = std::max(x1, pts(i, 0)), y0 = std::min(y0, pts(i, 1)), y1 = std::max(y1, pts(i, 1));
	ASSERT_LT(x0, x1) << "the scheme names its mouth points";
	const double gain = laplacianVariance(sharp, int(x0) - 2, int(y0) - 2, int(x1) + 3, int(y1) + 3) /
	                    laplacianVariance(linear, int(x0) - 2, int(y0) - 2, int(x1) + 3, int(y1) + 3);
	EXPECT_GT(gain, 1.1);
	EXPECT_LT(gain, 2.0);
	for (int y = 0; y < 180; ++y)  // the frame's border strip: the static background
		for (int x : {0, 1, 2, 317, 318, 319})
			for (int c = 0; c < 3; ++c) ASSERT_EQ(sharp.at(x, y, c), linear.at(x, y, c)) << x << "," << y;
	// Samples that all share one shape: nothing moves, nothing is prefiltered.
	std::vector<Points> shapes(f.faces.size(), f.faces[0].points);
	std::vector<SampleInfo> samples;
	for (const auto& it : f.items) samples.push_back(SampleInfo{it.fileName, it.emotion, it.viseme, it.word, it.context});
	NullProgress quiet;
	const FaceModel still = buildFaceModel(loadScheme("ch-unicamp-56"), shapes, samples, 320, 180, [&](std::size_t i) { return f.faces[i].image; }, BuildOptions{}, quiet);
	const Image8 stillFrame = keyposeFrame(still, Resampling::Sharp, 0, 0, unused);
	EXPECT_EQ(stillFrame.data, keyposeFrame(still, Resampling::Linear, 0, 0, unused).data);
	{  // and on a keypose, over the face region's opaque part, the exemplar itself byte for byte
		std::vector<PhoneSegment> phones;
		for (const Cdv& c : {Cdv("sil"), Cdv("a"), Cdv("sil")}) phones.push_back({ms(200 * long(phones.size())), ms(200 * long(phones.size()) + 200), "", "", c, 0});
		const auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
		Synthesizer synth(still, SynthOptions{});
		synth.prepare(keys);
		Synthesizer::Workspace ws;
		Image8 frame;
		synth.renderFrame(keys[1].time, keys, ws, frame, unused);
		const Image8& exemplar = f.faces[std::size_t(still.findSample("neutral", "a"))].image;
		const RegionSpec& spec = still.scheme.regions[0];
		const Points boundary = regionBoundary(spec, still.meanShape);
		const std::vector<float> alpha = softRegionMask(boundary, spec.grow, spec.feather * std::sqrt(regionArea(boundary, spec.grow)), 320, 180);
		long compared = 0;
		for (std::size_t i = 0; i < frame.data.size(); ++i)
			if (alpha[i / 3] >= 0.999f) {
				ASSERT_EQ(frame.data[i], exemplar.data[i]) << i;
				++compared;
			}
		EXPECT_GT(compared, 3000);
	}
	// Enlarged twice: the background is resampled too, and sharpened.
	const Image8 big = keyposeFrame(f.model, Resampling::Sharp, 640, 360, unused), bigLinear = keyposeFrame(f.model, Resampling::Linear, 640, 360, unused);
	EXPECT_NE(big.data, bigLinear.data);
	EXPECT_GT(laplacianVariance(big, 2 * int(x0), 2 * int(y0), 2 * int(x1), 2 * int(y1)),
	          1.1 * laplacianVariance(bigLinear, 2 * int(x0), 2 * int(y0), 2 * int(x1), 2 * int(y1)));
}

TEST(Synthesizer, aDissolveKeepsTheTwoKeyposesFineDetailAndLeavesTheKeyposesThemselvesAlone) {
	// Issue 47, D88: between two keyposes whose textures differ, the blend's lost fine detail is put back
	// (warp/dissolve_detail.h); on a keypose there is nothing to blend, so the frame is byte for byte the
	// plain one. Drawn at the model's own size (the detail is restored where the warp prefilters).
	const SmallFace& f = smallFace();
	std::vector<PhoneSegment> phones;
	for (const Cdv& c : {Cdv("sil"), Cdv("a"), Cdv("sil")}) phones.push_back({ms(200 * long(phones.size())), ms(200 * long(phones.size()) + 200), "", "", c, 0});
	const auto keys = keyposes(phones, Ticks(kTicksPerSecond / 30));
	SynthOptions plainOptions;
	plainOptions.dissolveDetail = false;
	Synthesizer kept(f.model, SynthOptions{}), plain(f.model, plainOptions);
	kept.prepare(keys), plain.prepare(keys);
	Synthesizer::Workspace wk, wp;
	Image8 a, b;
	Points pts, unused;
	for (const Keypose& k : keys) {
		kept.renderFrame(k.time, keys, wk, a, pts), plain.renderFrame(k.time, keys, wp, b, unused);
		ASSERT_EQ(a.data, b.data) << "on the keypose at " << toSeconds(k.time);
	}
	const Ticks mid = keys[0].time + (keys[1].time - keys[0].time) / 2;
	kept.renderFrame(mid, keys, wk, a, pts), plain.renderFrame(mid, keys, wp, b, unused);
	EXPECT_NE(a.data, b.data);
	double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
	for (Eigen::Index i = 0; i < pts.rows(); ++i)
		x0 = std::min(x0, pts(i, 0)), x1 = std::max(x1, pts(i, 0)), y0 = std::min(y0, pts(i, 1)), y1 = std::max(y1, pts(i, 1));
	EXPECT_GT(laplacianVariance(a, int(x0), int(y0), int(x1), int(y1)), 1.03 * laplacianVariance(b, int(x0), int(y0), int(x1), int(y1)));  // 1.054
}

TEST(Synthesizer, aFaceWithItsOwnShutEyesLowersALidOverTheEyeInsteadOfDrawingOne) {
	// Issue 47, D86: half shut, the part of the eye the lid leaves open is the open eye's own, at its own
	// size (the frame's warp squeezes the band between the lids; the band is drawn from the rows that stay
	// visible); the face without a closed-eyes image draws its lid over the slit (D42), which differs.
	const EyesShutCorpus c = eyesShutCorpus();
	NullProgress quiet;
	BuildOptions with;
	with.closedEyes = long(c.items.size() - 1);
	auto source = [&](std::size_t i) { return c.faces[i].image; };
	const FaceModel own = buildFaceModel(loadScheme("ch-unicamp-56"), c.shapes, c.samples, c.o.width, c.o.height, source, with, quiet);
	const FaceModel drawn = buildFaceModel(loadScheme("ch-unicamp-56"), c.shapes, c.samples, c.o.width, c.o.height, source, BuildOptions{}, quiet);
	const std::vector<Keypose> keys = restingKeys();
	SynthOptions so;
	so.width = 1280, so.height = 720;  // four times the model: a slit some pixels high
	oneBlink(so, keys);
	Ticks half{};  // a frame about half shut
	for (Ticks t = ms(900); t < ms(1200); t += ms(2))
		if (std::abs(so.modulator->eyeClosure(t) - 0.5) < 0.03) half = t;
	ASSERT_GT(half.count(), 0);
	Synthesizer so_(own, so), sd(drawn, so);
	so_.prepare(keys), sd.prepare(keys);
	Synthesizer::Workspace w1, w2, w3;
	Image8 open, halfOwn, halfDrawn;
	Points po, ph, pd;
	so_.renderFrame(ms(400), keys, w1, open, po);
	so_.renderFrame(half, keys, w2, halfOwn, ph);
	sd.renderFrame(half, keys, w3, halfDrawn, pd);
	// The visible slit of the right eye: between its lowered upper lid and its lower lid, inset a pixel.
	const Scheme sc = loadScheme("ch-unicamp-56");
	const EyeSpec& eye = sc.eyes.front();
	const auto up = lidLine(ph, eye, true), lo = lidLine(ph, eye, false);
	const double xa = std::min(ph(eye.corner0, 0), ph(eye.corner1, 0)), xb = std::max(ph(eye.corner0, 0), ph(eye.corner1, 0));
	double seOwn = 0, seDrawn = 0;
	long n = 0;
	for (int x = int(xa + 0.3 * (xb - xa)); x <= int(xb - 0.3 * (xb - xa)); ++x) {
		const double yu = polylineY(up, x), yl = polylineY(lo, x);
		for (int y = int(std::ceil(yu)) + 1; y <= int(std::floor(yl)) - 1; ++y)
			for (int k = 0; k < 3; ++k) {
				const double d1 = double(halfOwn.at(x, y, k)) - open.at(x, y, k), d2 = double(halfDrawn.at(x, y, k)) - open.at(x, y, k);
				seOwn += d1 * d1, seDrawn += d2 * d2, ++n;
			}
	}
	ASSERT_GT(n, 30);
	const double rmsOwn = std::sqrt(seOwn / double(n)), rmsDrawn = std::sqrt(seDrawn / double(n));
	EXPECT_LT(rmsOwn, 12) << "the open eye, where the lid leaves it open";
	EXPECT_GT(rmsDrawn, 2 * rmsOwn) << "the drawn lid covers it";
}
