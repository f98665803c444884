// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead render: transcript (+ audio, emotion) → talking-head video.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "align/align.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/render_video.h"
#include "media/audio.h"
#include "phonetics/labels.h"
#include "phonetics/language.h"

namespace fs = std::filesystem;

namespace talkhead::cli {

namespace {

std::string emotionList() {
	std::string s;
	for (const auto& e : emotionLabels()) s += (s.empty() ? "" : ", ") + e.label;
	return s;
}

void checkWritableFolder(const std::string& path) {
	fs::path parent = fs::path(path).parent_path();
	if (parent.empty()) parent = ".";
	std::error_code ec;
	if (!fs::is_directory(parent, ec)) throw Error(path, 0, "cannot write: folder '" + parent.string() + "' does not exist");
	if (::access(parent.c_str(), W_OK) != 0) throw Error(path, 0, "cannot write: folder '" + parent.string() + "' is not writable");
}

}  // namespace

int runRender(const std::vector<std::string>& argv) {
	Args args("render", "talkhead render (--transcript T [--audio A] | --audio A --text \"…\") [--emotion LABEL] -o OUT.mp4 [options]",
	          {{"--transcript", "FILE", "timed transcript (TextGrid, .pho, HTK, GRID, speech marks, TSV, Rhubarb; - = stdin)"},
	           {"--text", "TEXT", "instead of --transcript: what --audio says, aligned to it (as 'talkhead align' does)"},
	           {"--text-file", "F", "the same, read from a file"},
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
	           {"--pauses", "STYLE", "pauses: natural (default: rest soon after speech, a breath before it) or thesis (one silence keypose at each pause midpoint)"},
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
	          "Renders a talking-head video (Costa 2015 §5): one keypose per phone at its midpoint (pauses: rest, then\n"
	          "a breath before speech; --pauses thesis for the thesis rule), its appearance\n"
	          "from the face model for (emotion, context-dependent viseme), feature points moving on zero-tangent\n"
	          "Hermite curves between keyposes, forward and backward piecewise-affine warps and a cross-dissolve;\n"
	          "H.264 + AAC MP4 muxed in process.");
	if (!args.parse(argv)) return 0;
	if (!args.positionals().empty()) throw UsageError("render: unexpected argument '" + args.positionals()[0] + "'");
	auto transcriptPath = args.get("--transcript");
	std::optional<std::string> text = args.get("--text");
	if (auto f = args.get("--text-file")) {
		if (text) throw UsageError("render: give --text or --text-file, not both");
		text = readTextFile(*f);
	}
	if (transcriptPath && text) throw UsageError("render: give --transcript or --text, not both");
	if (!transcriptPath && !text) throw UsageError("render: --transcript FILE (or --audio A with --text) is required");
	if (text && !args.get("--audio")) throw UsageError("render: --text needs --audio (the speech to align the text to)");
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
	const auto pauses = parsePauseStyle(args.get("--pauses", "natural"));
	if (!pauses) throw UsageError("render: --pauses takes natural or thesis");
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
	AudioClip audio;
	Transcript tr;
	if (text) {
		// Forced alignment of the text to the audio (align/align.h), as `talkhead align` does.
		audio = decodeAudio(*args.get("--audio"));
		AlignOptions ao;
		ao.languageTag = lang.tag();
		Alignment al;
		try {
			al = alignSpeech(audio, *text, ao);
		} catch (const Error& e) {
			throw Error(*args.get("--audio"), 0, e.what());
		}
		for (const std::string& w : al.warnings) std::fprintf(stderr, "talkhead: warning: %s: %s\n", args.get("--audio")->c_str(), w.c_str());
		if (!quiet) std::fprintf(stderr, "aligned: %s\n", alignmentSummary(al).c_str());
		tr = al.phones;
		transcriptPath = *args.get("--audio");
	} else {
		tr = readTranscript(*transcriptPath, ro);
	}
	std::vector<PhoneSegment> phones = phoneSegments(tr, lang, unknown);
	const std::int64_t frameNumer = kTicksPerSecond * vo.fpsDen;  // frame n at n · frameNumer / fpsNum ticks
	const Ticks frameTicks(frameNumer / vo.fpsNum);
	std::vector<Keypose> keys = keyposes(phones, frameTicks, *pauses);
	// Duration: the audio's, or the transcript's.
	Ticks duration = phones.back().end;
	if (auto a = args.get("--audio")) {
		if (audio.samples.empty()) audio = decodeAudio(*a);
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
