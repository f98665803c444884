// SPDX-License-Identifier: GPL-3.0-or-later
// The video pipeline: keyposes per batch, frames drawn in parallel (straight into YUV), a writer thread
// feeding the sinks in order, all-or-nothing outputs.
#include "render/render.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/parallel.h"
#include "base/progress.h"
#include "model/model_file.h"

namespace talkhead {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

class TerminalProgress final : public RenderProgress {
public:
	void frames(std::int64_t done, std::int64_t total) override { bar_.report(double(done) / double(std::max<std::int64_t>(1, total)), "rendering"); }
	void finished(const RenderStats&) override { bar_.finish(); }

private:
	ProgressBar bar_;
};

class JsonProgress final : public RenderProgress {
public:
	explicit JsonProgress(std::FILE* out) : out_(out) {}
	void frames(std::int64_t done, std::int64_t total) override {
		const double fraction = double(done) / double(std::max<std::int64_t>(1, total));
		const int percent = int(fraction * 100);
		if (percent == lastPercent_) return;
		lastPercent_ = percent;
		std::fprintf(out_, "{\"type\": \"progress\", \"frame\": %lld, \"frames\": %lld, \"value\": %.3f}\n", (long long)done, (long long)total, fraction);
		std::fflush(out_);
	}
	void finished(const RenderStats& s) override {
		std::fprintf(out_, "{\"type\": \"done\", \"frames\": %lld, \"seconds\": %.3f}\n", (long long)s.frames, s.totalSeconds);
		std::fflush(out_);
	}

private:
	std::FILE* out_;
	int lastPercent_ = -1;
};

}  // namespace

std::unique_ptr<RenderProgress> makeTerminalProgress() { return std::make_unique<TerminalProgress>(); }
std::unique_ptr<RenderProgress> makeJsonProgress(std::FILE* out) { return std::make_unique<JsonProgress>(out); }

FaceModel loadRenderModel(const std::string& path) {
	std::string modelPath = path;
	if (modelPath.empty()) {
		auto d = findDefaultModel();
		if (!d) throw Error("no default face model found; build it with scripts/demo (target default_model) or give --model");
		modelPath = *d;
	}
	FaceModel model = loadModel(modelPath, ModelParts::Render);
	for (const auto& r : model.regions)
		if (!r.hasAppearanceCache()) return loadModel(modelPath);  // no appearance cache: the keyposes need the bases
	return model;
}

RenderStats renderPerformance(const FaceModel& model, const Performance& perf, const RenderOptions& options, const std::vector<FrameSink*>& sinks,
                              RenderProgress* progress) {
	const auto t0 = Clock::now();
	RenderProgress none;
	RenderProgress& prog = progress ? *progress : none;
	if (perf.keys.empty()) throw Error("nothing to render: the timeline has no keyposes");
	if (perf.rate.num < 1 || perf.rate.den < 1) throw Error("invalid frame rate " + perf.rate.str());
	const std::vector<Keypose>& keys = perf.keys;
	const std::int64_t frames = perf.frameCount();
	SynthOptions so = options.synth;
	so.emotion = perf.emotion;
	so.yuvRange = YuvRange::Limited;  // what H.264 and y4m readers assume
	// 4:2:0 video needs even sizes: a model with an odd width or height renders one pixel smaller (the
	// warps resample to the output size anyway).
	if (so.width <= 0 && so.height <= 0 && (model.width % 2 || model.height % 2)) {
		so.width = std::max(2, model.width & ~1);
		so.height = std::max(2, model.height & ~1);
	}
	Synthesizer synth(model, so);
	RenderStats st;
	st.frames = frames;
	st.width = synth.width();
	st.height = synth.height();
	st.keyposes = keys.size();
	st.substitutions = synth.substitutionsFor(keys);
	StreamInfo info;
	info.width = st.width, info.height = st.height, info.rate = perf.rate, info.frames = frames, info.range = so.yuvRange;
	info.pointNames = model.scheme.pointNames;
	for (FrameSink* s : sinks) s->begin(info);
	prog.started(info, st.substitutions);
	bool rgbFrames = false;
	std::vector<FrameSink*> ordered, anyThread;
	for (FrameSink* s : sinks) {
		rgbFrames = rgbFrames || s->needsRgb();
		(s->anyThread() ? anyThread : ordered).push_back(s);
	}

	// Frames are independent: workers draw a batch while a writer thread feeds the previous batch to the
	// sinks in order (double buffering). The keyposes a batch needs are made just before it, and the first
	// batch is one frame per thread, so a stream starts at once.
	const unsigned nThreads = resolveThreads(options.threads);
	const std::size_t batch = std::max<std::size_t>(8, 4 * nThreads);
	struct Batch {
		std::vector<Image8> rgb;
		std::vector<YuvImage> yuv;
		std::vector<Points> pts;
		std::int64_t first = 0;
		std::size_t count = 0;
	};
	Batch batches[2];
	for (auto& b : batches) b.rgb.resize(batch), b.yuv.resize(batch), b.pts.resize(batch);
	std::vector<Synthesizer::Workspace> workspaces(batch);
	std::exception_ptr writeError;
	auto frameOf = [&](const Batch& bt, std::size_t k) {
		RenderedFrame f;
		f.index = bt.first + std::int64_t(k);
		f.time = perf.frameTime(f.index);
		f.yuv = &bt.yuv[k];
		f.rgb = rgbFrames ? &bt.rgb[k] : nullptr;
		f.points = &bt.pts[k];
		return f;
	};
	auto writeBatch = [&](Batch& bt) {
		try {
			const auto tWrite = Clock::now();
			for (std::size_t k = 0; k < bt.count; ++k) {
				const RenderedFrame f = frameOf(bt, k);
				for (FrameSink* s : ordered) s->frame(f);
			}
			st.writeSeconds += since(tWrite);
			if (bt.first == 0) st.firstFrameSeconds = since(t0);
		} catch (...) {
			writeError = std::current_exception();
		}
	};
	std::thread writer;
	struct JoinOnExit {  // an error while the writer runs must not destroy a joinable thread
		std::thread& t;
		~JoinOnExit() {
			if (t.joinable()) t.join();
		}
	} joinWriter{writer};
	std::exception_ptr drawError;
	std::mutex drawErrorMutex;
	int cur = 0;
	for (std::int64_t first = 0; first < frames;) {
		Batch& bt = batches[cur];
		bt.first = first;
		bt.count = std::size_t(std::min<std::int64_t>(std::int64_t(first == 0 ? nThreads : batch), frames - first));
		first += std::int64_t(bt.count);
		const auto tPrep = Clock::now();
		synth.prepare(Synthesizer::keyposesBetween(keys, perf.frameTime(bt.first), perf.frameTime(first - 1)));
		st.keyposeSeconds += since(tPrep);
		const auto tDraw = Clock::now();
		parallelFor(bt.count, nThreads, [&](std::size_t k) {
			const Ticks tau = perf.frameTime(bt.first + std::int64_t(k));
			if (rgbFrames) {
				synth.renderFrame(tau, keys, workspaces[k], bt.rgb[k], bt.pts[k]);
				rgbToYuv420(bt.rgb[k], bt.yuv[k], so.yuvRange);
			} else {
				synth.renderFrameYuv(tau, keys, workspaces[k], bt.yuv[k], bt.pts[k]);
			}
			if (anyThread.empty()) return;
			try {
				const RenderedFrame f = frameOf(bt, k);
				for (FrameSink* s : anyThread) s->frame(f);
			} catch (...) {
				std::lock_guard<std::mutex> lock(drawErrorMutex);
				if (!drawError) drawError = std::current_exception();
			}
		});
		st.drawSeconds += since(tDraw);
		if (drawError) std::rethrow_exception(drawError);
		if (writer.joinable()) writer.join();
		if (writeError) std::rethrow_exception(writeError);
		writer = std::thread(writeBatch, std::ref(bt));
		cur ^= 1;
		prog.frames(first, frames);
	}
	if (writer.joinable()) writer.join();
	if (writeError) std::rethrow_exception(writeError);
	const auto tFinish = Clock::now();
	for (FrameSink* s : sinks) s->finish();
	st.writeSeconds += since(tFinish);
	for (FrameSink* s : sinks) s->commit();
	for (const auto& w : workspaces) st.warpSeconds += w.warpSeconds;
	st.totalSeconds = since(t0);
	prog.finished(st);
	return st;
}

}  // namespace talkhead
