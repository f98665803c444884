// SPDX-License-Identifier: GPL-3.0-or-later
// The video pipeline: keyposes per batch, frames drawn in parallel (straight into YUV), a writer thread
// feeding the sinks in order, all-or-nothing outputs.
#include "render/render.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <thread>
#include <limits>
#include <cmath>

#include <sys/resource.h>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/json.h"
#include "base/parallel.h"
#include "base/progress.h"
#include "base/text.h"
#include "model/model_file.h"
#include "render/player.h"

namespace talkhead {

namespace {

using Clock = std::chrono::steady_clock;
// How much less the drawing threads weigh than the writer and encoder (nice +10: about 1/9 of a core's
// time when both want it). See the render loop.
constexpr int kDrawNice = 10;
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
		const std::string line = JsonObject().add("type", "progress").add("frame", (long long)done).add("frames", (long long)total).add("value", fraction, "%.3f").str();
		std::fprintf(out_, "%s\n", line.c_str());
		std::fflush(out_);
	}
	void finished(const RenderStats& s) override {
		std::fprintf(out_, "%s\n", JsonObject().add("type", "done").add("frames", (long long)s.frames).add("seconds", s.totalSeconds, "%.3f").str().c_str());
		std::fflush(out_);
	}

private:
	std::FILE* out_;
	int lastPercent_ = -1;
};

}  // namespace

std::unique_ptr<RenderProgress> makeTerminalProgress() { return std::make_unique<TerminalProgress>(); }
std::unique_ptr<RenderProgress> makeJsonProgress(std::FILE* out) { return std::make_unique<JsonProgress>(out); }

FaceModel loadRenderModel(const std::string& path, const ComponentLevels& levels) {
	std::string modelPath = path;
	if (modelPath.empty()) {
		auto d = findDefaultModel();
		if (!d) throw Error("no default face model found; give {{model}}, or let 'talkhead render', 'say' or 'inspect' make it once in " +
		                    (userCacheDir().empty() ? std::string("the user's cache") : userCacheDir()) + " (or build the target default_model)");
		modelPath = *d;
	}
	FaceModel model = loadModel(modelPath, ModelParts::Render, levels);
	for (const auto& r : model.regions)
		if (!r.hasAppearanceCache()) return loadModel(modelPath, ModelParts::All, levels);  // no appearance cache: the keyposes need the bases
	return model;
}

OutputFit fitOutput(const FaceModel& model, SynthOptions& so, Fit fit) {
	const int modelWidth = model.width, modelHeight = model.height;
	OutputFit f;
	if (so.width <= 0 && so.height <= 0 && (modelWidth % 2 || modelHeight % 2)) {
		so.width = std::max(2, modelWidth & ~1);
		so.height = std::max(2, modelHeight & ~1);
	}
	f.outWidth = so.width, f.outHeight = so.height;
	if (so.width > 0 && so.height > 0) {
		f.box = fitBox(modelWidth, modelHeight, so.width, so.height, fit, fit == Fit::Face ? faceArea(model) : FaceArea{});
		so.width = f.box.innerWidth, so.height = f.box.innerHeight;
	}
	f.place = f.box.innerWidth > 0 && (f.box.innerWidth != f.outWidth || f.box.innerHeight != f.outHeight);
	return f;
}

FaceArea faceArea(const FaceModel& model) {
	FaceArea a;
	if (model.meanShape.rows() == 0) return a;
	a.x0 = a.y0 = std::numeric_limits<double>::max();
	a.x1 = a.y1 = std::numeric_limits<double>::lowest();
	auto add = [&](const Points& p) {
		if (p.rows() == 0) return;
		a.x0 = std::min(a.x0, p.col(0).minCoeff()), a.x1 = std::max(a.x1, p.col(0).maxCoeff());
		a.y0 = std::min(a.y0, p.col(1).minCoeff()), a.y1 = std::max(a.y1, p.col(1).maxCoeff());
	};
	add(model.meanShape);
	for (const Points& p : model.alignedShapes) add(p);
	// A forehead where the scheme has brows and nothing well above them (dlib's 68 points), as FaceMatte.
	std::vector<int> brows;
	for (const BrowSpec& b : model.scheme.brows) brows.insert(brows.end(), b.points.begin(), b.points.end());
	if (!brows.empty()) {
		double browY = 0;
		for (int b : brows) browY += model.meanShape(b, 1) / double(brows.size());
		const double browToChin = model.meanShape.col(1).maxCoeff() - browY;
		if (browToChin > 0 && model.meanShape.col(1).minCoeff() > browY - 0.25 * browToChin) a.y0 = std::min(a.y0, browY - 0.5 * browToChin);
	}
	const double margin = 0.1 * std::max(a.x1 - a.x0, a.y1 - a.y0);
	a.x0 -= margin, a.y0 -= margin, a.x1 += margin, a.y1 += margin;
	return a;
}

FitBox fitBox(int mw, int mh, int w, int h, Fit fit, const FaceArea& face) {
	FitBox b{w, h, 0, 0};
	// The same aspect (within a pixel), stretch, or no model size: draw straight at the output size.
	if (fit == Fit::Stretch || mw <= 0 || mh <= 0 || std::abs(std::int64_t(w) * mh - std::int64_t(h) * mw) < std::max(mw, mh)) return b;
	if (fit == Fit::Face && face.empty()) fit = Fit::Crop;
	const double cover = std::max(double(w) / mw, double(h) / mh), inside = std::min(double(w) / mw, double(h) / mh);
	double s = fit == Fit::Crop ? cover : inside;
	if (fit == Fit::Face) {  // as large as the face's area still fits the output, between inside and cover
		const double faceW = std::min(face.x1, double(mw)) - std::max(face.x0, 0.0), faceH = std::min(face.y1, double(mh)) - std::max(face.y0, 0.0);
		s = std::clamp(std::min(double(w) / faceW, double(h) / faceH), inside, cover);
	}
	auto even = [](double v) { return std::max(2, int(std::lround(v / 2)) * 2); };
	b.innerWidth = even(mw * s), b.innerHeight = even(mh * s);
	if (fit == Fit::Crop) b.innerWidth = std::max(b.innerWidth, w), b.innerHeight = std::max(b.innerHeight, h);
	else if (fit == Fit::Pad) b.innerWidth = std::min(b.innerWidth, w), b.innerHeight = std::min(b.innerHeight, h);
	b.x = (w - b.innerWidth) / 2 / 2 * 2;
	b.y = (h - b.innerHeight) / 2 / 2 * 2;
	if (fit == Fit::Face) {
		// A side the frame overflows is cut around the face's centre (as far as the frame reaches); a side
		// it does not fill is padded evenly.
		auto place = [](int out, int inner, double centre) {
			if (inner <= out) return (out - inner) / 2 / 2 * 2;
			const double x = std::clamp(out / 2.0 - centre, double(out - inner), 0.0);
			return int(std::floor(x / 2)) * 2;
		};
		const double sx = double(b.innerWidth) / mw, sy = double(b.innerHeight) / mh;
		b.x = place(w, b.innerWidth, 0.5 * (face.x0 + face.x1) * sx);
		b.y = place(h, b.innerHeight, 0.5 * (face.y0 + face.y1) * sy);
	}
	return b;
}

namespace {

// Frames drawn together: their buffers, reused batch after batch.
struct Batch {
	std::vector<FrameSlot> slots;
	std::int64_t first = 0;
	std::size_t count = 0;
};

// Batches in flight: up to 4 within ~96 MiB of frames (2 at least: one drawn while one is written).
std::vector<Batch> makeBatches(const RenderStats& st, bool rgbFrames, bool place, std::size_t batch) {
	const double frameBytes = double(st.width) * st.height * (1.5 + (rgbFrames ? 3 : 0)) * (place ? 2 : 1);
	const std::size_t slots = std::clamp<std::size_t>(std::size_t(96.0 * 1024 * 1024 / (frameBytes * double(batch))), 2, 4);
	std::vector<Batch> batches(slots);
	for (auto& b : batches) b.slots.resize(batch);
	return batches;
}

// The queue between the drawing thread and the writing one: batches drawn (in order) and batches free.
// A failure while drawing is handed to the writer; stop() ends the drawing on every way out.
class BatchQueue {
public:
	explicit BatchQueue(std::vector<Batch>& batches) {
		for (auto& b : batches) spare_.push_back(&b);
	}
	// The drawer's side: a free batch (nullptr once stopped), a drawn one handed on, the end or a failure.
	Batch* takeSpare() {
		std::unique_lock<std::mutex> lock(m_);
		changed_.wait(lock, [&] { return stop_ || !spare_.empty(); });
		if (stop_) return nullptr;
		Batch* b = spare_.front();
		spare_.pop_front();
		return b;
	}
	void putDrawn(Batch* b) { push(drawn_, b); }
	void fail(std::exception_ptr e) {
		std::lock_guard<std::mutex> lock(m_);
		error_ = std::move(e);
		stop_ = true;
	}
	void drawingDone() {
		std::lock_guard<std::mutex> lock(m_);
		done_ = true;
		changed_.notify_all();
	}
	// The writer's side: the next drawn batch (nullptr when all are written; the drawer's error rethrown).
	Batch* takeDrawn() {
		std::unique_lock<std::mutex> lock(m_);
		changed_.wait(lock, [&] { return !drawn_.empty() || done_; });
		if (error_) std::rethrow_exception(error_);
		if (drawn_.empty()) return nullptr;
		Batch* b = drawn_.front();
		drawn_.pop_front();
		return b;
	}
	void putSpare(Batch* b) { push(spare_, b); }
	void stop() {
		{
			std::lock_guard<std::mutex> lock(m_);
			stop_ = true;
		}
		changed_.notify_all();
	}

private:
	void push(std::deque<Batch*>& q, Batch* b) {
		{
			std::lock_guard<std::mutex> lock(m_);
			q.push_back(b);
		}
		changed_.notify_all();
	}
	std::mutex m_;
	std::condition_variable changed_;
	std::deque<Batch*> drawn_, spare_;
	bool done_ = false, stop_ = false;
	std::exception_ptr error_;
};

// Draws one frame of a performance into a batch slot (any thread) with the frame player, then hands it to
// the any-thread sinks.
struct FramePainter {
	const Performance& perf;
	const FramePlayer& player;
	bool rgbFrames, alpha;
	const std::vector<FrameSink*>& anyThread;

	RenderedFrame frameOf(const Batch& bt, std::size_t k) const {
		RenderedFrame f;
		f.index = bt.first + std::int64_t(k);
		f.time = perf.frameTime(f.index);
		f.yuv = &bt.slots[k].yuv;
		f.rgb = rgbFrames ? &bt.slots[k].rgb : nullptr;
		f.points = &bt.slots[k].points;
		return f;
	}

	void draw(Batch& bt, std::size_t k, Synthesizer::Workspace& ws) const {
		player.draw(perf.frameTime(bt.first + std::int64_t(k)), perf.timeline.keys, ws, bt.slots[k], rgbFrames, alpha);
		const RenderedFrame f = frameOf(bt, k);
		for (FrameSink* s : anyThread) s->frame(f);
	}
};

// Frames are independent. Drawing threads draw batches of frames a few batches ahead while this
// thread feeds finished batches to the sinks in order. The drawing threads run at a lower priority
// (kDrawNice) than this thread and the encoder's threads, which the sinks started: the encoder is the
// bottleneck, so drawing takes the moments it leaves a core idle instead of slowing it down. The
// keyposes a batch needs are made just before it, and the first batch is one frame per thread, so a
// stream starts at once.
void drawInOrder(const Performance& perf, FramePlayer& player, const FramePainter& painter, std::vector<Batch>& batches,
                 std::vector<Synthesizer::Workspace>& workspaces, unsigned nThreads, const std::vector<FrameSink*>& ordered, RenderProgress& prog,
                 RenderStats& st, Clock::time_point t0) {
	const std::size_t batch = workspaces.size();
	const std::int64_t frames = perf.frameCount();
	BatchQueue queue(batches);
	std::thread drawer([&] {
		try {
			setpriority(PRIO_PROCESS, 0, kDrawNice);  // this thread only (Linux); best effort
			WorkerPool pool(nThreads);                // started here: same priority
			for (std::int64_t first = 0; first < frames;) {
				Batch* next = queue.takeSpare();
				if (!next) break;
				Batch& bt = *next;
				bt.first = first;
				bt.count = std::size_t(std::min<std::int64_t>(std::int64_t(first == 0 ? nThreads : batch), frames - first));
				first += std::int64_t(bt.count);
				const auto tPrep = Clock::now();
				player.prepare(perf.timeline.keys, perf.frameTime(bt.first), perf.frameTime(first - 1));
				st.keyposeSeconds += since(tPrep);
				const auto tDraw = Clock::now();
				pool.run(bt.count, [&](std::size_t k) { painter.draw(bt, k, workspaces[k]); });
				st.drawSeconds += since(tDraw);
				queue.putDrawn(&bt);
			}
		} catch (...) {
			queue.fail(std::current_exception());
		}
		queue.drawingDone();
	});
	struct StopDrawer {  // on every way out: no more batches, and the drawer joined before the buffers go
		BatchQueue& queue;
		std::thread& t;
		~StopDrawer() {
			queue.stop();
			if (t.joinable()) t.join();
		}
	} stopDrawer{queue, drawer};
	while (Batch* bt = queue.takeDrawn()) {
		const auto tWrite = Clock::now();
		for (std::size_t k = 0; k < bt->count; ++k) {
			const RenderedFrame f = painter.frameOf(*bt, k);
			for (FrameSink* s : ordered) s->frame(f);
		}
		st.writeSeconds += since(tWrite);
		if (bt->first == 0) st.firstFrameSeconds = since(t0);
		prog.frames(bt->first + std::int64_t(bt->count), frames);
		queue.putSpare(bt);
	}
	drawer.join();
}

}  // namespace

RenderStats renderPerformance(const FaceModel& model, const Performance& performance, const RenderOptions& options, const std::vector<FrameSink*>& sinks,
                              RenderProgress* progress) {
	const Face face(model);
	return renderPerformance(face, performance, options, sinks, progress);
}

RenderStats renderPerformance(const Face& face, const Performance& performance, const RenderOptions& options, const std::vector<FrameSink*>& sinks,
                              RenderProgress* progress) {
	const FaceModel& model = face.model();
	const auto t0 = Clock::now();
	RenderProgress none;
	RenderProgress& prog = progress ? *progress : none;
	const Performance& perf = performance;
	// D62: a predicted mouth shows the face's exemplar nearest it, chosen when the performance was planned.
	if (std::any_of(perf.timeline.keys.begin(), perf.timeline.keys.end(), [](const Keypose& k) { return k.mouthOpening && k.sample < 0; }))
		throw std::logic_error("renderPerformance: keyposes with a predicted mouth and no exemplar (plan them against the face: PerformanceSpec::face)");
	if (perf.timeline.keys.empty()) throw Error("nothing to render: the timeline has no keyposes");
	if (perf.rate.num < 1 || perf.rate.den < 1) throw Error("invalid frame rate " + perf.rate.str());
	const std::int64_t frames = perf.frameCount();
	RenderOptions ro = options;
	ro.synth.expression = perf.expression;
	if (perf.modulation.any(perf.timeline.events))
		ro.synth.modulator = std::make_shared<ShapeModulator>(perf.modulation, perf.expression.emotion(), perf.duration, perf.timeline.keys, perf.timeline.events);
	FramePlayer player(face, ro);
	const Synthesizer& synth = player.synthesizer();
	RenderStats st;
	st.frames = frames;
	st.width = player.width();
	st.height = player.height();
	st.keyposes = perf.timeline.keys.size();
	st.substitutions = synth.substitutionsFor(perf.timeline.keys);
	StreamInfo info;
	info.width = st.width, info.height = st.height, info.rate = perf.rate, info.frames = frames, info.range = synth.options().yuvRange;
	info.pointNames = model.scheme.pointNames;
	bool rgbFrames = false;
	std::vector<FrameSink*> ordered, anyThread;
	for (FrameSink* s : sinks) {
		rgbFrames = rgbFrames || s->needsRgb();
		info.alpha = info.alpha || s->needsAlpha();
		(s->anyThread() ? anyThread : ordered).push_back(s);
	}
	for (FrameSink* s : sinks) s->begin(info);
	prog.started(info, st.substitutions);

	const unsigned nThreads = resolveThreads(options.threads);
	const std::size_t batch = std::max<std::size_t>(8, 4 * nThreads);
	std::vector<Batch> batches = makeBatches(st, rgbFrames, player.places(), batch);
	std::vector<Synthesizer::Workspace> workspaces(batch);
	const FramePainter painter{perf, player, rgbFrames, info.alpha, anyThread};
	drawInOrder(perf, player, painter, batches, workspaces, nThreads, ordered, prog, st, t0);
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
