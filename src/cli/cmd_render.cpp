// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead render: transcript (+ audio, emotion) → talking-head video.
#include <unistd.h>

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
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/progress_bar.h"
#include "cli/render_video.h"
#include "media/audio.h"
#include "media/image_io.h"
#include "media/video_writer.h"
#include "model/model_file.h"
#include "phonetics/labels.h"
#include "phonetics/language.h"
#include "synth/synthesizer.h"

namespace fs = std::filesystem;

namespace talkhead::cli {

namespace {

std::string emotionList() {
	std::string s;
	for (const auto& e : emotionLabels()) s += (s.empty() ? "" : ", ") + e.label;
	return s;
}

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


void checkWritableFolder(const std::string& path) {
	fs::path parent = fs::path(path).parent_path();
	if (parent.empty()) parent = ".";
	std::error_code ec;
	if (!fs::is_directory(parent, ec)) throw Error(path, 0, "cannot write: folder '" + parent.string() + "' does not exist");
	if (::access(parent.c_str(), W_OK) != 0) throw Error(path, 0, "cannot write: folder '" + parent.string() + "' is not writable");
}

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

int runRender(const std::vector<std::string>& argv) {
	Args args("render", "talkhead render --transcript T [--audio A] [--emotion LABEL] -o OUT.mp4 [options]",
	          {{"--transcript", "FILE", "timed transcript (TextGrid, .pho, HTK, GRID, speech marks, TSV, Rhubarb; - = stdin)"},
	           {"--audio", "FILE", "speech audio (any format libav reads); the video lasts as long as it"},
	           {"--emotion", "LABEL", "one of the 23 emotion labels or an alias (default neutral)"},
	           {"--model", "M.thm", "face model (default: the embedded default face)"},
	           {"--lang", "LANG", "language of the transcript: pt-BR (default) or en-US"},
	           {"--fps", "N", "frame rate: 30 (default), 25, 24, 60 or a fraction like 30000/1001"},
	           {"--size", "WxH", "output size (default: the model's frame size)"},
	           {"--format", "FORMAT", "mp4 (default) or y4m (raw frames, e.g. -o - | ffplay -)"},
	           {"--frames", "DIR", "also write every frame as DIR/frame_NNNNNN.png"},
	           {"--landmarks-out", "F.tsv", "write every frame's feature points (frame, time, x y per point)"},
	           {"--no-audio", "", "no audio track even when --audio is given (its length still sets the duration)"},
	           {"--crf", "N", "H.264 quality, 0–51 (default 20)"},
	           {"--preset", "NAME", "x264 preset (default veryfast)"},
	           {"--trajectory", "KIND", "feature points between keyposes: hermite (default, thesis) or linear (MikeTalk-style)"},
	           {"--dissolve", "KIND", "cross-dissolve weight: linear (default, thesis) or hermite"},
	           {"--warp", "PATH", "direct (default: dissolve in the mean-shape frame, one warp) or keypose (the thesis's order: keyposes warped to their shapes, then forward and backward)"},
	           {"--transcript-format", "FORMAT", "transcript format if detection fails"},
	           {"--tier", "NAME", "TextGrid tier"},
	           {"--unknown", "POLICY", "unknown phones: error (default), nearest, silence"},
	           {"--threads", "N", "worker threads (default: all cores)"},
	           {"--json-progress", "", "machine-readable progress lines on stderr"},
	           {"--timing", "", "print the time of each stage (load, keyposes, warps, blend, encode) on stderr"},
	           {"--quiet", "", "no progress and no summary", "-q"},
	           {"--output", "OUT", "the video to write (- with --format y4m: standard output)", "-o"}},
	          "Renders a talking-head video (Costa 2015 §5): one keypose per phone at its midpoint, its appearance\n"
	          "from the face model for (emotion, context-dependent viseme), feature points moving on zero-tangent\n"
	          "Hermite curves between keyposes, forward and backward piecewise-affine warps and a cross-dissolve;\n"
	          "H.264 + AAC MP4 muxed in process.");
	if (!args.parse(argv)) return 0;
	if (!args.positionals().empty()) throw UsageError("render: unexpected argument '" + args.positionals()[0] + "'");
	auto transcriptPath = args.get("--transcript");
	if (!transcriptPath) throw UsageError("render: --transcript FILE is required");
	auto output = args.get("--output");
	if (!output) throw UsageError("render: -o OUT is required");
	const std::string format = args.get("--format", "mp4");
	if (format != "mp4" && format != "y4m") throw UsageError("render: --format must be mp4 or y4m");
	if (*output == "-" && format != "y4m") throw UsageError("render: -o - needs --format y4m");
	const auto emotion = canonicalEmotion(args.get("--emotion", "neutral"));
	if (!emotion) throw Error("unknown emotion '" + args.get("--emotion", "") + "' (known: " + emotionList() + "; aliases such as sadness, disgust)");
	VideoOptions vo;
	{
		const std::string fps = args.get("--fps", "30");
		auto slash = fps.find('/');
		long long num, den = 1;
		bool ok = slash == std::string::npos ? parseInt(fps, num) : (parseInt(fps.substr(0, slash), num) && parseInt(fps.substr(slash + 1), den));
		if (!ok || num < 1 || den < 1 || num > 240 * den || num < den) throw UsageError("render: --fps must be 1–240, e.g. 30 or 30000/1001");
		vo.fpsNum = int(num);
		vo.fpsDen = int(den);
	}
	vo.crf = int(args.number("--crf", 20, 0, 51));
	vo.preset = args.get("--preset", "veryfast");
	SynthOptions so;
	so.emotion = *emotion;
	if (auto s = args.get("--size")) parseSize("render: --size", *s, so.width, so.height);
	const std::string traj = args.get("--trajectory", "hermite"), diss = args.get("--dissolve", "linear");
	if ((traj != "hermite" && traj != "linear") || (diss != "hermite" && diss != "linear"))
		throw UsageError("render: --trajectory and --dissolve take hermite or linear");
	so.trajectory = traj == "hermite" ? Trajectory::Hermite : Trajectory::Linear;
	so.dissolve = diss == "hermite" ? Trajectory::Hermite : Trajectory::Linear;
	const std::string warpPath = args.get("--warp", "direct");
	if (warpPath != "direct" && warpPath != "keypose") throw UsageError("render: --warp takes direct or keypose");
	so.warpPath = warpPath == "direct" ? WarpPath::Direct : WarpPath::Keypose;
	const std::string policy = args.get("--unknown", "error");
	UnknownPhone unknown = policy == "nearest" ? UnknownPhone::Nearest : policy == "silence" ? UnknownPhone::Silence : UnknownPhone::Error;
	if (policy != "error" && policy != "nearest" && policy != "silence") throw UsageError("render: --unknown must be error, nearest or silence");
	const unsigned threads = unsigned(args.number("--threads", 0, 0, 256));
	const bool quiet = args.has("--quiet"), jsonProgress = args.has("--json-progress");
	if (*output != "-") checkWritableFolder(*output);
	if (auto f = args.get("--landmarks-out")) checkWritableFolder(*f);

	const auto t0 = std::chrono::steady_clock::now();
	// Timeline.
	const Language& lang = Language::get(args.get("--lang", "pt-BR"));
	ReadOptions ro;
	ro.format = args.get("--transcript-format", "");
	ro.tier = args.get("--tier", "");
	Transcript tr = readTranscript(*transcriptPath, ro);
	std::vector<PhoneSegment> phones = phoneSegments(tr, lang, unknown);
	const std::int64_t frameNumer = kTicksPerSecond * vo.fpsDen;  // frame n at n · frameNumer / fpsNum ticks
	const Ticks frameTicks(frameNumer / vo.fpsNum);
	std::vector<Keypose> keys = keyposes(phones, frameTicks);
	// Duration: the audio's, or the transcript's.
	AudioClip audio;
	Ticks duration = phones.back().end;
	if (auto a = args.get("--audio")) {
		audio = decodeAudio(*a);
		const Ticks audioDur = audio.duration();
		const Ticks tolerance(kTicksPerSecond / 10);
		if (duration > audioDur + tolerance) {
			char buf[200];
			std::snprintf(buf, sizeof buf, "the transcript (%.3f s) is longer than the audio (%.3f s) by %.3f s", toSeconds(duration), toSeconds(audioDur),
			              toSeconds(duration - audioDur));
			throw Error(*transcriptPath, 0, buf);
		}
		duration = audioDur;
	}
	const std::int64_t frames = frameCount(duration, vo.fpsNum, vo.fpsDen);  // round(duration × fps)
	RenderJob job;
	job.keys = keys;
	job.frames = frames;
	job.duration = duration;
	job.video = vo;
	job.synth = so;
	job.output = *output;
	job.format = format;
	job.modelPath = args.get("--model", "");
	job.framesDir = args.get("--frames");
	job.landmarksOut = args.get("--landmarks-out");
	job.audio = audio.samples.empty() ? nullptr : &audio;
	job.noAudio = args.has("--no-audio");
	job.quiet = quiet;
	job.jsonProgress = jsonProgress;
	job.timing = args.has("--timing");
	job.threads = threads;
	job.started = t0;
	renderVideo(job);
	return 0;
}

}  // namespace talkhead::cli
