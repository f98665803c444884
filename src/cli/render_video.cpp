// SPDX-License-Identifier: GPL-3.0-or-later
// The video pipeline shared by `render` and `say`: model, keyposes per batch, frames drawn in parallel
// (straight into YUV), a writer thread encoding in order, outputs through temporary names.
#include "cli/render_video.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "base/atomic_file.h"
#include "base/data_dirs.h"
#include "base/error.h"
#include "base/parallel.h"
#include "cli/progress_bar.h"
#include "media/image_io.h"
#include "model/model_file.h"

namespace fs = std::filesystem;

namespace talkhead::cli {

namespace {
// Removes a temporary output unless released (a failure leaves no file behind).
struct TempFile {
	std::string path;
	bool keep = false;
	~TempFile() {
		if (!keep && !path.empty()) {
			std::error_code ec;
			fs::remove_all(path, ec);
		}
	}
};

}  // namespace

std::int64_t frameCount(Ticks duration, int fpsNum, int fpsDen) {
	const std::int64_t numer = kTicksPerSecond * fpsDen;
	return std::max<std::int64_t>(1, (duration.count() * fpsNum + numer / 2) / numer);
}

namespace {
// The render itself; `temporary` gets the video's temporary name once there is one.
void renderVideoTo(const RenderJob& job, std::string& temporary) {
	const std::vector<Keypose>& keys = job.keys;
	VideoOptions vo = job.video;
	const SynthOptions& so = job.synth;
	const std::int64_t frames = job.frames, frameNumer = kTicksPerSecond * vo.fpsDen;
	const Ticks duration = job.duration;
	const bool quiet = job.quiet, jsonProgress = job.jsonProgress;
	const unsigned threads = job.threads;
	const std::string format = job.format;
	const auto t0 = job.started;
	// Model and synthesizer.
	std::string modelPath = job.modelPath;
	if (modelPath.empty()) {
		auto d = findDefaultModel();
		if (!d) throw Error("no default face model found; build it with scripts/demo (target default_model) or give --model");
		modelPath = *d;
	}
	using Clock = std::chrono::steady_clock;
	auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
	const auto tLoad = Clock::now();
	FaceModel model = loadModel(modelPath, ModelParts::Render);
	for (const auto& r : model.regions)
		if (!r.hasAppearanceCache()) {  // no appearance cache: the keyposes need the bases
			model = loadModel(modelPath);
			break;
		}
	const double loadSeconds = since(tLoad);
	SynthOptions synthOptions = so;
	synthOptions.yuvRange = YuvRange::Limited;  // what H.264 and y4m readers assume
	// 4:2:0 video needs even sizes: a model with an odd width or height renders one pixel smaller (the
	// warps resample to the output size anyway).
	if (synthOptions.width <= 0 && synthOptions.height <= 0 && (model.width % 2 || model.height % 2)) {
		synthOptions.width = std::max(2, model.width & ~1);
		synthOptions.height = std::max(2, model.height & ~1);
	}
	Synthesizer synth(model, synthOptions);
	vo.width = synth.width();
	vo.height = synth.height();
	double keyposeSeconds = 0, drawSeconds = 0, encodeSeconds = 0, firstFrameSeconds = 0;
	const auto subs = synth.substitutionsFor(keys);
	if (!subs.empty() && !quiet) {
		std::string s;
		for (const auto& x : subs) s += (s.empty() ? "" : "; ") + x;
		std::fprintf(stderr, "talkhead: the model lacks some (emotion, viseme) entries; substituted: %s\n", s.c_str());
	}
	// Outputs (temporary names, renamed when complete).
	TempFile tmpVideo, tmpLandmarks;
	std::unique_ptr<Mp4Writer> mp4;
	std::unique_ptr<Y4mWriter> y4m;
	std::FILE* y4mFile = nullptr;
	const bool withAudio = job.audio && !job.audio->samples.empty() && !job.noAudio;
	if (format == "mp4") {
		tmpVideo.path = temporaryNameFor(job.output);
		temporary = tmpVideo.path;
		mp4 = std::make_unique<Mp4Writer>(tmpVideo.path, vo, withAudio ? job.audio : nullptr);
	} else if (job.output == "-") {
		y4mFile = stdout;
		y4m = std::make_unique<Y4mWriter>(stdout, vo);
	} else {
		tmpVideo.path = temporaryNameFor(job.output);
		temporary = tmpVideo.path;
		y4mFile = std::fopen(tmpVideo.path.c_str(), "wb");
		if (!y4mFile) throw Error(job.output, 0, "cannot write");
		y4m = std::make_unique<Y4mWriter>(y4mFile, vo);
	}
	std::ofstream landmarks;
	if (auto f = job.landmarksOut) {
		tmpLandmarks.path = temporaryNameFor(*f);
		landmarks.open(tmpLandmarks.path);
		landmarks << "frame\ttime";
		for (const auto& n : model.scheme.pointNames) landmarks << '\t' << n << "_x\t" << n << "_y";
		landmarks << '\n';
	}
	std::string framesDir;
	if (auto d = job.framesDir) {
		framesDir = *d;
		std::error_code ec;
		fs::create_directories(framesDir, ec);
		if (ec) throw Error(framesDir, 0, "cannot create folder: " + ec.message());
	}

	// Frames are independent: workers draw a batch (straight into YUV unless PNG frames are wanted) while a
	// writer thread encodes the previous batch in order (double buffering). The keyposes a batch needs are
	// made just before it, and the first batch is small, so a stream starts after a frame or two.
	ProgressBar bar(quiet || jsonProgress);
	const unsigned nThreads = resolveThreads(threads);
	const std::size_t batch = std::max<std::size_t>(8, 4 * nThreads);
	const bool rgbFrames = !framesDir.empty();
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
	int lastPercent = -1;
	std::exception_ptr writeError;
	auto writeBatch = [&](Batch& bt) {
		try {
			const auto tEncode = Clock::now();
			for (std::size_t k = 0; k < bt.count; ++k) {
				const std::int64_t n = bt.first + std::int64_t(k);
				if (mp4) mp4->write(bt.yuv[k]);
				if (y4m) y4m->write(bt.yuv[k]);
				if (landmarks.is_open()) {
					char buf[64];
					std::snprintf(buf, sizeof buf, "%lld\t%.6f", (long long)n, double(n) * vo.fpsDen / vo.fpsNum);
					landmarks << buf;
					for (Eigen::Index i = 0; i < bt.pts[k].rows(); ++i) {
						std::snprintf(buf, sizeof buf, "\t%.3f\t%.3f", bt.pts[k](i, 0), bt.pts[k](i, 1));
						landmarks << buf;
					}
					landmarks << '\n';
				}
			}
			encodeSeconds += since(tEncode);
			if (bt.first == 0) firstFrameSeconds = since(t0);
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
	int cur = 0;
	auto frameTime = [&](std::int64_t n) { return Ticks(n * frameNumer / vo.fpsNum); };
	for (std::int64_t first = 0; first < frames;) {
		Batch& bt = batches[cur];
		bt.first = first;
		bt.count = std::size_t(std::min<std::int64_t>(std::int64_t(first == 0 ? nThreads : batch), frames - first));
		first += std::int64_t(bt.count);
		const auto tPrep = Clock::now();
		synth.prepare(Synthesizer::keyposesBetween(keys, frameTime(bt.first), frameTime(first - 1)));
		keyposeSeconds += since(tPrep);
		const auto tDraw = Clock::now();
		parallelFor(bt.count, nThreads, [&](std::size_t k) {
			const Ticks tau = frameTime(bt.first + std::int64_t(k));
			if (rgbFrames) {
				synth.renderFrame(tau, keys, workspaces[k], bt.rgb[k], bt.pts[k]);
				rgbToYuv420(bt.rgb[k], bt.yuv[k], synthOptions.yuvRange);
				char name[64];  // PNG compression is the slow part: done here, by the workers
				std::snprintf(name, sizeof name, "frame_%06lld.png", (long long)(bt.first + std::int64_t(k)));
				writeImage((fs::path(framesDir) / name).string(), bt.rgb[k], 1);
			} else {
				synth.renderFrameYuv(tau, keys, workspaces[k], bt.yuv[k], bt.pts[k]);
			}
		});
		drawSeconds += since(tDraw);
		if (writer.joinable()) writer.join();
		if (writeError) std::rethrow_exception(writeError);
		writer = std::thread(writeBatch, std::ref(bt));
		cur ^= 1;
		const double fraction = double(first) / double(frames);
		bar.report(fraction, "rendering");
		const int percent = int(fraction * 100);
		if (jsonProgress && percent != lastPercent) {
			std::fprintf(stderr, "{\"type\": \"progress\", \"frame\": %lld, \"frames\": %lld, \"value\": %.3f}\n", (long long)first,
			             (long long)frames, fraction);
			std::fflush(stderr);
			lastPercent = percent;
		}
	}
	if (writer.joinable()) writer.join();
	if (writeError) std::rethrow_exception(writeError);
	const auto tFinish = Clock::now();
	if (mp4) mp4->finish();
	mp4.reset();
	encodeSeconds += since(tFinish);
	y4m.reset();
	if (y4mFile && y4mFile != stdout && std::fclose(y4mFile) != 0) throw Error(job.output, 0, "cannot write");
	if (landmarks.is_open()) {
		landmarks.close();
		if (!landmarks) throw Error(*job.landmarksOut, 0, "cannot write");
		fs::rename(tmpLandmarks.path, *job.landmarksOut);
		tmpLandmarks.keep = true;
	}
	if (!tmpVideo.path.empty()) {
		std::error_code ec;
		fs::rename(tmpVideo.path, job.output, ec);
		if (ec) throw Error(job.output, 0, "cannot write: " + ec.message());
		tmpVideo.keep = true;
	}
	bar.finish();
	if (job.timing) {
		double warp = 0;
		for (const auto& w : workspaces) warp += w.warpSeconds;
		std::fprintf(stderr,
		             "timing: %smodel load %.3f s; keyposes %.3f s (%zu); frames drawn %.3f s wall (warp+dissolve %.3f s thread time); "
		             "encode+write %.3f s; %lld frames; first frame out after %.3f s\n",
		             job.timingPrefix.c_str(), loadSeconds, keyposeSeconds, keys.size(), drawSeconds, warp, encodeSeconds, (long long)frames,
		             firstFrameSeconds);
	}
	const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	if (jsonProgress) std::fprintf(stderr, "{\"type\": \"done\", \"frames\": %lld, \"seconds\": %.3f}\n", (long long)frames, secs);
	else if (!quiet)
		std::fprintf(stderr, "rendered %s: %lld frames %dx%d at %d/%d fps (%.3f s of %s), %zu keyposes, emotion %s; %.1f s (%.1f frames/s, %.1fx real time)\n",
		             job.output.c_str(), (long long)frames, vo.width, vo.height, vo.fpsNum, vo.fpsDen, toSeconds(duration),
		             withAudio ? "audio" : "transcript", keys.size(), so.emotion.c_str(), secs, double(frames) / secs, toSeconds(duration) / secs);
}

}  // namespace

void renderVideo(const RenderJob& job) {
	std::string temporary;
	try {
		renderVideoTo(job, temporary);
	} catch (const Error& e) {  // errors name the output, not its temporary (which is gone)
		const std::string m = e.what();
		if (temporary.empty() || m.rfind(temporary + ": ", 0) != 0) throw;
		throw Error(job.output + ": " + m.substr(temporary.size() + 2));
	}
}

}  // namespace talkhead::cli
