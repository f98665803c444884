// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/error.h"
#include "base/frame_rate.h"
#include "geometry/scheme.h"
#include "synth_corpus.h"
#include "synth_face.h"
#include "render/render.h"
#include "test_support.h"

using namespace talkhead;
namespace fs = std::filesystem;

TEST(FrameRate, parsesIntegersDecimalsNtscAndFractions) {
	auto is = [](const char* text, int num, int den) {
		const auto r = FrameRate::parse(text);
		return r && r->num == num && r->den == den;
	};
	EXPECT_TRUE(is("30", 30, 1));
	EXPECT_TRUE(is("30.0", 30, 1));
	EXPECT_TRUE(is("25.000", 25, 1));
	EXPECT_TRUE(is("29.97", 30000, 1001));  // the NTSC spelling means 30000/1001 exactly
	EXPECT_TRUE(is("23.976", 24000, 1001));
	EXPECT_TRUE(is("59.94", 60000, 1001));
	EXPECT_TRUE(is("30000/1001", 30000, 1001));
	EXPECT_TRUE(is("2997/100", 2997, 100));  // a fraction is taken as written
	EXPECT_TRUE(is("12.5", 25, 2));
	EXPECT_TRUE(is("60/2", 30, 1));
	for (const char* bad : {"", "0", "241", "-30", "30fps", "1/0", "30/", "/2", "1/2", "29.97.1", "1e2", " 30", "30.1234567"})
		EXPECT_FALSE(FrameRate::parse(bad)) << bad;
}

TEST(FrameRate, ownsFrameTimesAndCounts) {
	const FrameRate ntsc{30000, 1001};
	EXPECT_EQ(ntsc.time(0), Ticks(0));
	EXPECT_EQ(ntsc.time(30000), Ticks(1001 * kTicksPerSecond));  // exact: 30000 frames last 1001 s
	EXPECT_EQ(ntsc.time(1).count(), kTicksPerSecond * 1001 / 30000);
	EXPECT_EQ(ntsc.frameCount(Ticks(1001 * kTicksPerSecond)), 30000);
	const FrameRate r25{25, 1};
	EXPECT_EQ(r25.frameCount(ticksFromSeconds(1.0)), 25);
	EXPECT_EQ(r25.frameCount(ticksFromSeconds(1.019)), 25);  // round(25.475) = 25
	EXPECT_EQ(r25.frameCount(ticksFromSeconds(1.021)), 26);  // round(25.525) = 26
	EXPECT_EQ(r25.frameCount(Ticks(0)), 1);                  // at least one frame
	EXPECT_EQ(r25.frameAt(ticksFromSeconds(0.079)), 1);
	EXPECT_EQ(r25.frameAt(r25.time(7)), 7);
	EXPECT_GT(r25.frameCount(Ticks(std::numeric_limits<std::int64_t>::max())), 0);  // no overflow
	EXPECT_EQ(ntsc.str(), "30000/1001");
	EXPECT_EQ(r25.str(), "25");
}

namespace {
// A tiny model built in memory from the synthetic corpus (neutral and joy, four visemes, 160×90).
const FaceModel& tinyModel() {
	static const FaceModel model = [] {
		SynthCorpusOptions o;
		o.width = 160, o.height = 90;
		o.emotions = {"neutral", "joy"};
		o.visemes = {"sil", "a", "p1", "u"};
		return test::synthModel(o);
	}();
	return model;
}

Performance threeSyllables() {
	std::vector<PhoneSegment> p;
	auto ms = [](long v) { return Ticks(v * (kTicksPerSecond / 1000)); };
	p = {{ms(0), ms(100), "", "_", "sil", 1}, {ms(100), ms(200), "p", "p", "p1", 2}, {ms(200), ms(400), "a", "a", "a", 3},
	     {ms(400), ms(500), "", "_", "sil", 4}};
	Performance perf;
	perf.rate = FrameRate{25, 1};
	perf.timeline.keys = keyposes(p, perf.rate.frameLength());
	perf.duration = ms(500);
	perf.expression = Expression(Emotion::of("joy"));
	return perf;
}
}  // namespace

TEST(Render, callbackSinkGetsEveryFrameInOrderWithItsTime) {
	const Performance perf = threeSyllables();
	std::vector<std::int64_t> seen;
	std::vector<Ticks> times;
	int width = 0;
	auto sink = makeCallbackSink([&](const StreamInfo& info, const RenderedFrame& f) {
		seen.push_back(f.index);
		times.push_back(f.time);
		width = info.width;
		ASSERT_NE(f.yuv, nullptr);
		ASSERT_NE(f.points, nullptr);
		EXPECT_EQ(f.points->rows(), std::int64_t(info.pointNames.size()));
		EXPECT_EQ(f.rgb, nullptr);  // no sink asked for RGB
	});
	const RenderStats st = renderPerformance(tinyModel(), perf, RenderOptions{}, {sink.get()});
	ASSERT_EQ(st.frames, 13);  // round(0.5 s × 25)
	ASSERT_EQ(seen.size(), 13u);
	for (std::size_t i = 0; i < seen.size(); ++i) {
		EXPECT_EQ(seen[i], std::int64_t(i));
		EXPECT_EQ(times[i], perf.rate.time(std::int64_t(i)));
	}
	EXPECT_EQ(width, 160);
	EXPECT_TRUE(st.substitutions.empty());
}

TEST(Render, sameInputsGiveIdenticalFramesAnyThreadCount) {
	const Performance perf = threeSyllables();
	auto collect = [&](unsigned threads) {
		std::vector<std::uint8_t> all;
		auto sink = makeCallbackSink([&](const StreamInfo&, const RenderedFrame& f) { all.insert(all.end(), f.yuv->y.begin(), f.yuv->y.end()); });
		RenderOptions o;
		o.threads = threads;
		renderPerformance(tinyModel(), perf, o, {sink.get()});
		return all;
	};
	EXPECT_EQ(collect(1), collect(2));
}

TEST(Render, monotoneTrajectoryKeepsTheKeyposesAndIsTheSameOnAnyThreadCount) {
	// Monotone tangents need the keyposes on either side of a frame's pair: with one thread the first batch
	// is a single frame, so the neighbours must be prepared with it (Synthesizer::margin).
	const Performance perf = threeSyllables();
	auto collect = [&](unsigned threads, Trajectory kind) {
		std::vector<std::uint8_t> all;
		std::vector<Points> pts;
		auto sink = makeCallbackSink([&](const StreamInfo&, const RenderedFrame& f) {
			all.insert(all.end(), f.yuv->y.begin(), f.yuv->y.end());
			pts.push_back(*f.points);
		});
		RenderOptions o;
		o.threads = threads;
		o.synth.trajectory = kind;
		renderPerformance(tinyModel(), perf, o, {sink.get()});
		return std::make_pair(all, pts);
	};
	const auto one = collect(1, Trajectory::Monotone), two = collect(2, Trajectory::Monotone), hermite = collect(2, Trajectory::Hermite);
	EXPECT_EQ(one.first, two.first);
	ASSERT_EQ(two.second.size(), hermite.second.size());
	// Same keyposes, so the same points where a frame falls on one (and before the first), different between.
	double most = 0;
	for (std::size_t i = 0; i < two.second.size(); ++i) {
		const Ticks tau = perf.rate.time(std::int64_t(i));
		const double d = (two.second[i] - hermite.second[i]).cwiseAbs().maxCoeff();
		const bool onKey = std::any_of(perf.timeline.keys.begin(), perf.timeline.keys.end(), [&](const Keypose& k) { return k.time == tau; }) || tau <= perf.timeline.keys.front().time;
		if (onKey) EXPECT_LT(d, 1e-9) << "frame " << i;
		most = std::max(most, d);
	}
	EXPECT_GT(most, 0.05);  // pixels
}

TEST(Render, theDefaultFitKeepsTheWholeFaceForEverySourceAspect) {
	// Issue 47: a 4:3, 1:1 or 9:16 face in a 16:9 frame (and the 16:9 face in a portrait one) keeps every
	// feature point inside the frame; the even crop cuts the 9:16 face through its forehead and chin.
	struct Case {
		int mw, mh, w, h;
	};
	for (const Case c : {Case{320, 240, 320, 180}, Case{240, 240, 320, 180}, Case{180, 320, 320, 180}, Case{320, 180, 180, 320}}) {
		SynthCorpusOptions o;
		o.width = c.mw, o.height = c.mh;
		o.emotions = {"neutral"};
		o.visemes = {"sil", "a", "p1"};
		const FaceModel model = test::synthModel(o);
		const FaceArea area = faceArea(model);
		ASSERT_FALSE(area.empty());
		auto extent = [&](Fit fit) {  // the points' box over every frame, in output pixels
			RenderOptions ro;
			ro.synth.width = c.w, ro.synth.height = c.h, ro.fit = fit;
			Eigen::RowVector2d lo(1e9, 1e9), hi(-1e9, -1e9);
			auto sink = makeCallbackSink([&](const StreamInfo& info, const RenderedFrame& f) {
				EXPECT_EQ(info.width, c.w);
				EXPECT_EQ(info.height, c.h);
				lo = lo.cwiseMin(f.points->colwise().minCoeff()), hi = hi.cwiseMax(f.points->colwise().maxCoeff());
			});
			renderPerformance(model, threeSyllables(), ro, {sink.get()});
			return std::make_pair(lo, hi);
		};
		const auto [lo, hi] = extent(Fit::Face);
		const std::string name = std::to_string(c.mw) + "x" + std::to_string(c.mh) + " in " + std::to_string(c.w) + "x" + std::to_string(c.h);
		EXPECT_GE(lo.minCoeff(), 0) << name;
		EXPECT_LE(hi(0), c.w) << name;
		EXPECT_LE(hi(1), c.h) << name;
		// As large as it can be: the face's area fills the output's width or its height (to within 2 pixels).
		const FitBox b = fitBox(c.mw, c.mh, c.w, c.h, Fit::Face, area);
		const double s = double(b.innerWidth) / c.mw;
		EXPECT_TRUE(std::min(area.x1, double(c.mw)) * s - std::max(area.x0, 0.0) * s >= c.w - 2 ||
		            std::min(area.y1, double(c.mh)) * s - std::max(area.y0, 0.0) * s >= c.h - 2 || b.innerWidth >= c.w && b.innerHeight >= c.h)
		    << name;
		if (c.mw == 180) {
			const auto [clo, chi] = extent(Fit::Crop);
			EXPECT_TRUE(clo(1) < 0 || chi(1) > c.h) << "the even crop keeps the 9:16 face whole: the test shows nothing";
		}
	}
}

TEST(Render, aPredictedMouthNotBoundToTheFaceIsRefused) {
	// D62, issue 46: a predicted mouth is bound to the face's exemplar when the performance is planned
	// against it (PerformanceSpec::face); the renderer does not choose exemplars.
	Performance perf = threeSyllables();
	perf.timeline.keys[1].mouthOpening = 0.5;
	auto sink = makeCallbackSink([](const StreamInfo&, const RenderedFrame&) {});
	EXPECT_THROW(renderPerformance(tinyModel(), perf, RenderOptions{}, {sink.get()}), std::logic_error);
	perf.timeline.keys[1].sample = 0;  // bound
	EXPECT_NO_THROW(renderPerformance(tinyModel(), perf, RenderOptions{}, {sink.get()}));
}

TEST(Render, aFailingSinkLeavesNoOutputBehind) {
	const Performance perf = threeSyllables();
	const std::string dir = test::tempDir("render-fail");
	const std::string mp4 = dir + "/out.mp4", tsv = dir + "/out.tsv";
	auto video = makeMp4Sink(mp4, Mp4Settings{}, nullptr);
	auto points = makeLandmarksSink(tsv);
	auto failing = makeCallbackSink([](const StreamInfo&, const RenderedFrame& f) {
		if (f.index == 5) throw Error("disk full (simulated)");
	});
	EXPECT_EQ(test::errorOf([&] { renderPerformance(tinyModel(), perf, RenderOptions{}, {video.get(), points.get(), failing.get()}); }),
	          "disk full (simulated)");
	video.reset(), points.reset();
	EXPECT_TRUE(fs::is_empty(dir)) << "a failed render left files in " << dir;
	// Without the failure, both appear.
	auto video2 = makeMp4Sink(mp4, Mp4Settings{}, nullptr);
	auto points2 = makeLandmarksSink(tsv);
	renderPerformance(tinyModel(), perf, RenderOptions{}, {video2.get(), points2.get()});
	EXPECT_TRUE(fs::is_regular_file(mp4));
	std::ifstream in(tsv);
	std::string line;
	int lines = 0;
	while (std::getline(in, line)) ++lines;
	EXPECT_EQ(lines, 14);  // header + 13 frames
}

TEST(Render, debugOverlayMarksThePointsAndWritesTheTimeline) {
	// Every feature point is drawn (luma 235 at its pixel) and text appears at the top left; without the
	// overlay neither is there. Blinks and head motion off, so both renders draw the same face.
	Performance perf = threeSyllables();
	perf.modulation.blinks = false;
	perf.modulation.headMotion = false;
	auto render = [&](bool overlay) {
		std::vector<YuvImage> frames;
		std::vector<Points> points;
		auto sink = makeCallbackSink([&](const StreamInfo&, const RenderedFrame& f) {
			frames.push_back(*f.yuv);
			points.push_back(*f.points);
		});
		RenderOptions o;
		o.debugOverlay = overlay;
		renderPerformance(tinyModel(), perf, o, {sink.get()});
		return std::make_pair(frames, points);
	};
	const auto [plain, pts] = render(false);
	const auto [marked, pts2] = render(true);
	ASSERT_EQ(plain.size(), marked.size());
	for (std::size_t f = 0; f < plain.size(); ++f) {
		EXPECT_EQ(pts[f], pts2[f]);
		const YuvImage& m = marked[f];
		for (Eigen::Index i = 0; i < pts[f].rows(); ++i) {
			const int x = int(std::lround(pts[f](i, 0))), y = int(std::lround(pts[f](i, 1)));
			if (x < 0 || y < 0 || x >= m.width || y >= m.height) continue;
			EXPECT_EQ(m.y[std::size_t(y) * std::size_t(m.width) + std::size_t(x)], 235) << "frame " << f << " point " << i;
		}
		int text = 0;  // changed pixels in the top-left band where the lines go
		for (int y = 0; y < 20; ++y)
			for (int x = 0; x < 80; ++x) text += m.y[std::size_t(y) * std::size_t(m.width) + std::size_t(x)] != plain[f].y[std::size_t(y) * std::size_t(m.width) + std::size_t(x)];
		EXPECT_GT(text, 50) << "frame " << f;
	}
}
