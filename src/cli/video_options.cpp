// SPDX-License-Identifier: GPL-3.0-or-later
// The options `render` and `say` share, checked in one order before any work, and the call into the
// render library (src/render) with its sinks and progress.
#include "cli/video_options.h"

#include "cli/run.h"
#include "model/faces.h"

#include <tuple>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "phonetics/emotion.h"
#include "phonetics/labels.h"
#include "phonetics/timing_formats.h"
#include "phonetics/transcript.h"

namespace fs = std::filesystem;

namespace talkhead::cli {

namespace {

// The summary and the substitution warning on stderr around the library's progress (bar or JSON lines).
class CliProgress final : public RenderProgress {
public:
	CliProgress(const VideoCommand& cmd) : cmd_(cmd) {
		if (cmd.jsonProgress) inner_ = makeJsonProgress(stderr);
		else if (!cmd.quiet) inner_ = makeTerminalProgress();
	}
	void started(const StreamInfo& info, const std::vector<std::string>& subs) override {
		if (!subs.empty() && !cmd_.quiet) {
			std::string s;
			for (const auto& x : subs) s += (s.empty() ? "" : "; ") + x;
			std::fprintf(stderr, "talkhead: the model lacks some (emotion, viseme) entries; substituted: %s\n", s.c_str());
		}
		if (inner_) inner_->started(info, subs);
	}
	void frames(std::int64_t done, std::int64_t total) override {
		if (inner_) inner_->frames(done, total);
	}
	void finished(const RenderStats& st) override {
		if (inner_) inner_->finished(st);
	}

private:
	const VideoCommand& cmd_;
	std::unique_ptr<RenderProgress> inner_;
};

}  // namespace

OptionSpec genericVisemesOption() {
	return {"--generic-visemes", "", "a --lang without a viseme table maps its IPA phones through a generic table (phonetics/generic; approximate, with a warning)"};
}

std::string languageOptionHelp(const std::string& what) {
	std::string known;
	for (const auto& a : Language::available()) known += (known.empty() ? "" : ", ") + a;
	return what + ": pt-BR (default) or another language with a viseme table (" + known + "; others with --generic-visemes)";
}

std::string defaultLanguageFor(const std::string& transcriptPath, const std::string& format) {
	// A GRID .align is English by definition (the GRID corpus): en-US unless --lang says otherwise.
	if (format == "grid" || endsWith(toLower(transcriptPath), ".align")) return "en-US";
	if (format.empty() && !transcriptPath.empty() && transcriptPath != "-") {
		std::error_code ec;
		if (fs::is_regular_file(transcriptPath, ec) && fs::file_size(transcriptPath, ec) < (64u << 20)) {
			try {
				const std::string text = readTextFile(transcriptPath);
				if (detectTranscriptFormat(text) == std::optional<std::string>("grid")) return "en-US";
				// A file that names its language (Whisper's "language": "fr", aeneas's fragments): that one.
				if (auto tag = timingFileLanguage(text)) return *tag;
			} catch (const std::exception&) {  // unreadable: the reader says so later
			}
		}
	}
	return "pt-BR";
}

const Language& languageOption(const Args& args, const std::string& defaultTag) {
	const std::string tag = args.get("--lang", defaultTag);
	if (!args.has("--generic-visemes")) return Language::get(tag);
	const std::string lower = toLower(tag), primary = lower.substr(0, lower.find('-'));
	for (const auto& a : Language::available())
		if (toLower(a) == lower || toLower(a) == primary) return Language::get(tag);
	const Language& lang = Language::generic(tag);
	std::fprintf(stderr, "talkhead: warning: no viseme table for language '%s': its IPA phones are mapped through the generic table (approximate)\n",
	             tag.c_str());
	return lang;
}

const Language& transcriptLanguage(const Args& args, const std::string& path, const std::string& format) {
	const std::string tag = defaultLanguageFor(path, format);
	if (args.has("--lang") || tag == "pt-BR") return languageOption(args, tag);
	try {
		return languageOption(args, tag);
	} catch (const Error& e) {
		throw Error(path, 0, "the file states its language as '" + tag + "': " + e.what() + "; or {{lang}} to read it as another language");
	}
}

void noteWordLanguage(const Args& args, const Transcript& tr, const Language& lang, const std::string& path) {
	if (tr.level != LabelLevel::Word || args.has("--lang") || tr.format == "grid" || tr.format == "gentle") return;
	try {
		if (path != "-" && timingFileLanguage(readTextFile(path))) return;
	} catch (const std::exception&) {
	}
	std::fprintf(stderr, "talkhead: warning: %s: its words are read as %s (the default; the file names no language): --lang for another\n", shownLine(path).c_str(),
	             lang.tag().c_str());
}

TranscriptOptions parseTranscriptOptions(const Args& args, const std::string& command, const std::string& formatOption) {
	TranscriptOptions t;
	ReadOptions& ro = t.read;
	ro.format = args.get(formatOption, "");
	if (const auto& f = transcriptFormats(); !ro.format.empty() && std::find(f.begin(), f.end(), ro.format) == f.end())
		throw UsageError(command + ": unknown " + formatOption + " '" + ro.format + "' (" + joined(f) + ")");
	ro.tier = args.get("--tier", "");
	if (args.has("--speaker")) {
		if (args.has("--tier")) throw UsageError(command + ": --tier and --speaker name the same choice: give one");
		ro.tier = args.get("--speaker", "");
	}
	ro.timingText = args.get("--timing-text", "");
	if (const std::string level = args.get("--level", "auto"); level == "words") ro.level = LabelLevel::Word;
	else if (level == "phones") ro.level = LabelLevel::Phone;
	else if (level != "auto") throw UsageError(command + ": --level takes auto, phones or words");
	ro.utterance = args.get("--utterance", "");
	ro.sampleRate = int(args.number("--sample-rate", 16000, 1000, 192000));
	const std::string policy = args.get("--unknown", "error");
	if (policy == "nearest") t.unknown = UnknownPhone::Nearest;
	else if (policy == "silence") t.unknown = UnknownPhone::Silence;
	else if (policy != "error") throw UsageError(command + ": --unknown must be error, nearest or silence");
	const auto notation = parseNotation(args.get("--notation", "auto"));
	if (!notation) throw UsageError(command + ": --notation takes auto, ipa, arpabet, sampa, xsampa, espeak, praat or br1");
	t.notation = *notation;
	return t;
}

void reportSpeech(const VideoCommand& cmd, const TimedSpeech& speech) {
	if (!cmd.quiet)
		for (const std::string& n : speech.notes) std::fprintf(stderr, "%s\n", shownLine(n).c_str());
	if (cmd.verbose && !speech.read.verdict.empty())
		std::fprintf(stderr, "talkhead: %s: %s\n", shownLine(speech.name).c_str(), shownLine(speech.read.verdict).c_str());
	for (const std::string& w : speech.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", shownLine(w).c_str());
}

void reportMarks(const VideoCommand& cmd, const std::vector<Utterance::Mark>& marks) {
	for (const auto& m : marks) {
		if (cmd.jsonProgress) std::fprintf(stderr, "%s\n", JsonObject().add("type", "mark").add("name", m.name).add("time", toSeconds(m.time), "%.3f").str().c_str());
		else if (!cmd.quiet) std::fprintf(stderr, "talkhead: mark %s at %.3f s\n", jsonQuote(m.name).c_str(), toSeconds(m.time));
	}
}

PerformanceSpec performanceSpec(const VideoCommand& cmd, const VideoFace& face) {
	PerformanceSpec spec;
	spec.face = face.model.get();
	spec.rate = cmd.rate;
	spec.coarticulation = face.face->coarticulation();
	spec.pauses = cmd.pauses;
	spec.expression = cmd.expression;
	spec.modulation = cmd.modulation;
	spec.speechBrows = cmd.speechBrows;
	return spec;
}

void checkWritableFolder(const std::string& path) {
	fs::path parent = fs::path(path).parent_path();
	if (parent.empty()) parent = ".";
	std::error_code ec;
	if (!fs::is_directory(parent, ec)) throw Error(path, 0, "cannot write: folder '" + parent.string() + "' does not exist");
	if (::access(parent.c_str(), W_OK) != 0) throw Error(path, 0, "cannot write: folder '" + parent.string() + "' is not writable");
}

std::vector<OptionSpec> drawingOptionSpecs() {
	return {{"--trajectory", "KIND", "feature points between keyposes: hermite (default, thesis: zero tangents, a stop at each keypose), linear (MikeTalk-style) or monotone (a C¹ Hermite spline: stops only where the motion turns)"},
	        {"--dissolve", "KIND", "cross-dissolve weight: linear (default, thesis) or hermite"},
	        {"--warp", "PATH", "direct (default: dissolve in the mean-shape frame, one warp) or keypose (the thesis's order: keyposes warped to their shapes, then forward and backward)"},
	        {"--resampling", "KIND", "the direct warp's one resampling: sharp (default: the images it samples are prefiltered so that its bilinear kernel keeps the face's fine detail) or linear (plain bilinear: the frames of earlier versions)"},
	        {"--dissolve-detail", "on|off", "with sharp resampling, a cross-dissolve between two keyposes keeps the fine detail's energy where their textures differ (on, default) or is the plain blend (off)"},
	        {"--emotion-source", "SRC", "auto (default: the model's images of the emotion where it has them, else au), corpus (only the model's images; neutral where it has none) or au (the neutral images changed by the emotion's action units: shape and skin)"},
	        {"--au-appearance", "on|learned|off", "with action units, change the skin too (furrows, wrinkles; models/au-appearance.bin): on (default; a face other than the default one keeps its own skin, deepened where the lines form), learned (the lines as learned on the default face, on any face) or off (the shape alone)"}};
}

OptionSpec faceOption() {
	return {"--face", "NAME", "a face that ships with talkhead, by name ('talkhead faces' lists them): a real person's, built from the clips on first use, or synthetic (the default face)"};
}

std::vector<OptionSpec> videoOptionSpecs() {
	std::vector<OptionSpec> specs = {genericVisemesOption(),
	        {"--emotion", "LABEL[:I]", "one of the 23 emotion labels or an alias (default neutral); :I sets its intensity, 0 (neutral) to 1 (the corpus, default), up to 1.5"},
	        faceOption(),
	        {"--model", "M.thm", "face model file (default: the embedded default face)"},
	        {"--fps", "RATE", "frame rate: 30 (default), 25, 29.97 (= 30000/1001), 30.0, 12.5 or a fraction like 30000/1001"},
	        {"--size", "WxH", "output size (default: the model's frame size)"},
	        {"--fit", "MODE", "when --size has another aspect than the model: face (default: fill as far as the whole face still fits, cut around it, pad the rest), crop (fill, cut the overflow evenly), pad (fit inside, extend the edges) or stretch"},
	        {"--format", "FORMAT", "mp4 (H.264 + AAC; the default), webm (VP9 + Vorbis; the default for -o F.webm), y4m (raw frames, e.g. -o - | ffplay -; the default for -o F.y4m) or none (no video: only --frames, --landmarks-out, …)"},
	        {"--background", "KIND", "opaque (default: the model's frame) or transparent (the face on a feathered matte, as alpha: --format webm, VP9 with alpha, and/or --frames, RGBA PNG)"},
	        {"--feather", "PX", "with --background transparent: the matte's soft edge, σ in output pixels (default: 2 % of the face's width)"},
	        {"--frames", "DIR", "also write every frame as DIR/frame_NNNNNN.png"},
	        {"--landmarks-out", "F.tsv", "write every frame's feature points: the landmarks TSV (frame, time, status 'drawn', confidence, x y per point)"},
	        {"--no-audio", "", "no audio track (the audio's length still sets the duration)"},
	        {"--crf", "N", "quality: H.264 0–51 (default 20), VP9 0–63 (default 32); lower is better and larger"},
	        {"--preset", "NAME", "x264 preset (default veryfast)"},
	        {"--pauses", "STYLE", "pauses: natural (rest soon after speech, a breath before it; the default with --coarticulation off), still (rest soon after speech and held; before the next words a slow in-breath where the pause allows; the default) or thesis (one silence keypose at each pause midpoint)"},
	        {"--coarticulation", "on|off|F.tsv", "the mouth from its phone context (D62, D90): each phone's keypose shows the face's exemplar nearest the opening a model learned from real speakers predicts; bilabials close. on (default): the model that ships (95 GRID clips, 6 speakers); off: the thesis's path (one target per phone); or a model of your own ('talkhead corpus coarticulation')"},
	        {"--controls", "F", "timed events (JSON, or a TextGrid with --control-tier): emotion changes, blinks, nods, shakes, turns, brows, action units (README: Timed controls)"},
	        {"--control-tier", "NAME", "with a TextGrid --controls: the tier whose labels are the events"},
	        {"--blinks", "on|off", "blink (default on: ~17 a minute at rest, fewer in fear, more in distress, placed in pauses)"},
	        {"--head-motion", "on|off|X", "small smooth head motion (default on; X scales its amplitude, 0–3)"},
	        {"--lead-in", "MS", "still face and silence before the speech (default 0; for experiment software that drifts at a clip's start)"},
	        {"--tail", "MS", "still face and silence after it (default 0)"},
	        {"--av-offset", "MS", "audio later than the video by MS (negative: earlier), for asynchrony designs (default 0)"},
	        {"--audio-out", "F.wav", "also write the sound track exactly as muxed (lead-in, offset and tail applied), also with --no-audio or --format y4m"},
	        {"--timeline-out", "F.json", "write the stimulus's timeline: frames, speech onset and offset, every phone and keypose (seconds of the video)"},
	        {"--speech-brows", "on|off|X", "raise the brows on each phrase's most prominent (longest) vowel (default off; X scales the raise, 0–3)"},
	        {"--components", "R=N,...", "components kept per model region, e.g. face=20,cheeks_lips=90%,lips=all (default: all; the thesis's Appendix C reductions, appearance only)"},
	        {"--seed", "N", "seed for blinks and head motion (default 1): the same seed gives the same video"},
	        {"--debug-overlay", "", "draw the feature points, the keyposes around each frame and the lids and head on every frame"},
	        {"--threads", "N", "worker threads (default: all cores)"},
	        {"--json-progress", "", "machine-readable progress lines on stderr"},
	        {"--timing", "", "print the time of each stage (load, keyposes, warps, blend, encode) on stderr"},
	        {"--quiet", "", "no progress and no summary", "-q"},
	        {"--verbose", "", "also say what the timing's plausibility gate checked (units, rates, duration)", "-v"},
	        {"--output", "OUT", "the video to write (- with --format y4m: standard output)", "-o"}};
	for (auto& d : drawingOptionSpecs()) specs.push_back(d);
	return specs;
}

FrameRate parseFps(const Args& args, const std::string& command) {
	const auto rate = FrameRate::parse(args.get("--fps", "30"));
	if (!rate) throw UsageError(command + ": --fps must be 1–240, e.g. 30, 29.97, 12.5 or 30000/1001");
	return *rate;
}

Fit parseFit(const Args& args, const std::string& command) {
	const std::string fit = args.get("--fit", "face");
	if (fit != "face" && fit != "crop" && fit != "pad" && fit != "stretch") throw UsageError(command + ": --fit takes face, crop, pad or stretch");
	return fit == "face" ? Fit::Face : fit == "crop" ? Fit::Crop : fit == "pad" ? Fit::Pad : Fit::Stretch;
}

Expression parseEmotionOption(const Args& args, const std::string& command) {
	// --emotion LABEL[:INTENSITY]: 0 = neutral, 1 = the corpus (default), up to 1.5 (extrapolated, with a warning).
	try {
		const Expression e = Expression::parse(args.get("--emotion", Emotion::neutralLabel()));
		if (e.extrapolated())
			std::fprintf(stderr, "talkhead: warning: intensity %g is beyond the corpus's emotion: shapes and appearances are extrapolated\n", e.intensity());
		return e;
	} catch (const FieldError& e) {
		if (e.field() == "emotion") throw Error(e.what());  // as an unknown label in a file: exit 1
		throw UsageError(command + ": --emotion LABEL:INTENSITY: " + e.what());
	}
}

ModulatorOptions parseModulation(const Args& args, const std::string& command) {
	ModulatorOptions m;
	const std::string blinks = args.get("--blinks", "on"), head = args.get("--head-motion", "on");
	if (blinks != "on" && blinks != "off") throw UsageError(command + ": --blinks takes on or off");
	m.blinks = blinks == "on";
	double amplitude = 1;
	if (head == "off") amplitude = 0;
	else if (head != "on" && (!parseDouble(head, amplitude) || !(amplitude >= 0 && amplitude <= 3)))
		throw UsageError(command + ": --head-motion takes on, off or an amplitude from 0 to 3");
	m.headMotion = amplitude > 0;
	m.headAmplitude = amplitude;
	m.seed = std::uint64_t(args.number("--seed", 1, 0, 9007199254740991.0));
	return m;
}

double parseSpeechBrows(const Args& args, const std::string& command, const std::string& fallback) {
	const std::string brows = args.get("--speech-brows", fallback);
	double amount = brows == "on" ? 1.0 : 0.0;
	if (brows != "on" && brows != "off" && (!parseDouble(brows, amount) || !(amount >= 0 && amount <= 3)))
		throw UsageError(command + ": --speech-brows takes on, off or an amount from 0 to 3");
	return amount;
}

std::optional<VideoFormat> parseVideoFormat(const Args& args, const std::string& command, const std::string& output, bool allowNone) {
	const std::string named = args.get("--format", "");
	if (named == "none" && allowNone) return std::nullopt;
	if (const OutputFormat* f = findOutputFormat(named); !named.empty() && (!f || f->stream))
		throw UsageError(command + ": --format must be " + (allowNone ? outputFormatNames() + " or none" : outputFormatNames()));
	try {
		return videoFormatFor(output, named);
	} catch (const FieldError& e) {
		throw UsageError(command + ": " + cliField(e.field()) + " " + e.what());
	}
}

bool parseTransparent(const Args& args, const std::string& command, std::optional<VideoFormat> format, const std::string& alternatives) {
	const std::string background = args.get("--background", "opaque");
	if (background != "opaque" && background != "transparent") throw UsageError(command + ": --background takes opaque or transparent");
	const bool transparent = background == "transparent";
	if (transparent && format && !outputFormat(*format).alpha) {
		std::string withAlpha;
		for (const OutputFormat& f : outputFormats())
			if (f.alpha && !f.stream) withAlpha += (withAlpha.empty() ? "" : " or ") + ("--format " + f.name);
		throw UsageError(command + ": --background transparent: " + outputFormat(*format).name + " (" + outputFormat(*format).description +
		                 ") has no alpha channel; write " + withAlpha + alternatives);
	}
	return transparent;
}

int parseCrf(const Args& args, std::optional<VideoFormat> format) {
	const OutputFormat& f = outputFormat(format.value_or(VideoFormat::Mp4));
	if (f.crfMax < 0) return -1;
	return int(args.number("--crf", f.crfDefault, 0, f.crfMax));
}

void parseDrawingOptions(const Args& args, const std::string& command, SynthOptions& synth) {
	const std::string traj = args.get("--trajectory", "hermite"), diss = args.get("--dissolve", "linear");
	if (traj != "hermite" && traj != "linear" && traj != "monotone") throw UsageError(command + ": --trajectory takes hermite, linear or monotone");
	if (diss != "hermite" && diss != "linear") throw UsageError(command + ": --dissolve takes hermite or linear");
	synth.trajectory = traj == "hermite" ? Trajectory::Hermite : traj == "linear" ? Trajectory::Linear : Trajectory::Monotone;
	synth.dissolve = diss == "hermite" ? Trajectory::Hermite : Trajectory::Linear;
	const std::string warpPath = args.get("--warp", "direct");
	if (warpPath != "direct" && warpPath != "keypose") throw UsageError(command + ": --warp takes direct or keypose");
	synth.warpPath = warpPath == "direct" ? WarpPath::Direct : WarpPath::Keypose;
	const std::string resampling = args.get("--resampling", "sharp");
	if (resampling != "sharp" && resampling != "linear") throw UsageError(command + ": --resampling takes sharp or linear");
	synth.resampling = resampling == "sharp" ? Resampling::Sharp : Resampling::Linear;
	const std::string detail = args.get("--dissolve-detail", "on");
	if (detail != "on" && detail != "off") throw UsageError(command + ": --dissolve-detail takes on or off");
	synth.dissolveDetail = detail == "on";
	const std::string source = args.get("--emotion-source", "auto");
	if (source != "corpus" && source != "au" && source != "auto") throw UsageError(command + ": --emotion-source takes corpus, au or auto");
	synth.emotionSource = source == "corpus" ? EmotionSource::Corpus : (source == "au" ? EmotionSource::ActionUnits : EmotionSource::Auto);
	const std::string skin = args.get("--au-appearance", "on");
	if (skin != "on" && skin != "off" && skin != "learned") throw UsageError(command + ": --au-appearance takes on, learned or off");
	synth.auAppearance = skin != "off";
	synth.auOwnSkin = skin == "on";
}

PauseStyle parsePausesOption(const Args& args, const std::string& command) {
	if (!args.has("--pauses")) return defaultPauseStyle(args.get("--coarticulation", "on") != "off");
	const auto pauses = parsePauseStyle(*args.get("--pauses"));
	if (!pauses) throw UsageError(command + ": --pauses takes natural, still or thesis");
	return *pauses;
}

VideoCommand parseVideoCommand(const Args& args, const std::string& command, bool outputRequired) {
	VideoCommand c;
	c.command = command;
	// Output first, then how it looks, then how it moves, then how it runs: the same order for every command.
	if (auto o = args.get("--output")) c.output = *o;
	else if (outputRequired && args.get("--format", "") != "none") throw UsageError(command + ": -o OUT is required");
	c.format = parseVideoFormat(args, command, c.output, true);
	if (!c.format && args.get("--output")) throw UsageError(command + ": --format none writes no video: drop -o");
	if (c.output == "-" && !(c.format && outputFormat(*c.format).standardOutput)) throw UsageError(command + ": -o - needs --format y4m");
	c.framesDir = args.get("--frames");
	c.landmarksOut = args.get("--landmarks-out");
	c.transparent = parseTransparent(args, command, c.format, " or --frames DIR (RGBA PNG) with --format none");
	if (c.transparent && !c.format && !c.framesDir && !extraFrameSink())
		throw UsageError(command + ": --background transparent with --format none needs --frames DIR (RGBA PNG)");
	if (args.has("--feather") && !c.transparent) throw UsageError(command + ": --feather is for --background transparent");
	c.render.matte.feather = args.number("--feather", 0, 0.5, 500);
	if (!c.format && !c.framesDir && !c.landmarksOut && !extraFrameSink())
		throw UsageError(command + ": --format none writes nothing: give --frames DIR or --landmarks-out F.tsv");
	c.rate = parseFps(args, command);
	if (auto s = args.get("--size")) parseSize(command + ": --size", *s, c.render.synth.width, c.render.synth.height);
	c.render.fit = parseFit(args, command);
	c.crf = parseCrf(args, c.format);
	if (args.has("--preset") && !(c.format && outputFormat(*c.format).preset)) throw UsageError(command + ": --preset is x264's (--format mp4)");
	c.preset = args.get("--preset", "veryfast");
	c.noAudio = args.has("--no-audio");
	c.expression = parseEmotionOption(args, command);
	c.modelPath = args.get("--model", "");
	c.faceName = args.get("--face");
	if (c.faceName && args.has("--model")) throw UsageError(command + ": give --face NAME or --model M.thm, not both");
	if (c.faceName && *c.faceName != kSyntheticFace && !ownFace(*c.faceName)) shippedFace(*c.faceName);  // an unknown name fails before any work
	c.pauses = parsePausesOption(args, command);
	parseDrawingOptions(args, command, c.render.synth);
	c.modulation = parseModulation(args, command);
	c.speechBrows = parseSpeechBrows(args, command, "off");
	c.leadIn = ticksFromSeconds(args.number("--lead-in", 0, 0, 600000) / 1000);
	c.tail = ticksFromSeconds(args.number("--tail", 0, 0, 600000) / 1000);
	c.avOffset = ticksFromSeconds(args.number("--av-offset", 0, -10000, 10000) / 1000);
	if (auto t = args.get("--timeline-out")) {
		c.timelineOut = *t;
		checkWritableFolder(*t);
	}
	if (auto a = args.get("--audio-out")) {
		c.audioOut = *a;
		checkWritableFolder(*a);
	}
	if (args.has("--control-tier") && !args.has("--controls")) throw UsageError(command + ": --control-tier needs --controls F.TextGrid");
	c.coarticulation = parseCoarticulation(args);
	if (auto f = args.get("--controls")) c.controls = args.has("--control-tier") ? loadControlTier(*f, *args.get("--control-tier")) : loadControls(*f);
	if (auto comps = args.get("--components")) {
		try {
			c.components = parseComponentLevels(*comps);
		} catch (const Error& e) {
			throw UsageError(command + ": " + e.what());
		}
	}
	c.render.debugOverlay = args.has("--debug-overlay");
	c.render.threads = unsigned(args.number("--threads", 0, 0, 256));
	c.quiet = args.has("--quiet");
	c.verbose = args.has("--verbose");
	c.jsonProgress = args.has("--json-progress");
	c.timing = args.has("--timing");
	if (!c.modelPath.empty() && ::access(c.modelPath.c_str(), R_OK) != 0) throw Error(c.modelPath, 0, std::string("cannot open model: ") + std::strerror(errno));
	if (!c.output.empty() && c.output != "-") checkWritableFolder(c.output);
	if (c.landmarksOut) checkWritableFolder(*c.landmarksOut);
	if (c.framesDir) checkWritableFolder(fs::path(*c.framesDir).lexically_normal().string());
	return c;
}

std::shared_ptr<const CoarticulationModel> parseCoarticulation(const Args& args) {
	return coarticulationOption(args.get("--coarticulation", "on"));
}

VideoFace loadVideoFace(const VideoCommand& cmd) {
	using Clock = std::chrono::steady_clock;
	const auto tLoad = Clock::now();
	const std::string modelPath = cmd.faceName ? shippedFaceModel(*cmd.faceName, cmd.quiet) : cmd.modelPath;
	if (modelPath.empty()) ensureDefaultFace(cmd.quiet);
	VideoFace f;
	f.model = std::make_unique<FaceModel>(loadRenderModel(modelPath, cmd.components));
	f.face = std::make_unique<Face>(*f.model, cmd.coarticulation);
	f.seconds = std::chrono::duration<double>(Clock::now() - tLoad).count();
	return f;
}

void runVideoCommand(const VideoCommand& cmd, const VideoFace& face, const Performance& perf, std::unique_ptr<AudioSource> audio,
                     std::chrono::steady_clock::time_point started, const std::string& timingPrefix, std::vector<SideOutput> side) {
	using Clock = std::chrono::steady_clock;
	const double loadSeconds = face.seconds;
	const bool withAudio = audio && !cmd.noAudio;
	CliProgress progress(cmd);
	const double beforeRender = std::chrono::duration<double>(Clock::now() - started).count();
	const RenderStats st = renderVideoJob(cmd, *face.face, perf, std::move(audio), std::move(side), &progress, extraFrameSink());  // and an in-process caller's sink (cli/run.h)
	if (cmd.timing)
		std::fprintf(stderr,
		             "timing: %smodel load %.3f s; keyposes %.3f s (%zu); frames drawn %.3f s wall (warp+dissolve %.3f s CPU); "
		             "encode+write %.3f s; %lld frames; first frame out after %.3f s\n",
		             timingPrefix.c_str(), loadSeconds, st.keyposeSeconds, st.keyposes, st.drawSeconds, st.warpSeconds, st.writeSeconds, (long long)st.frames,
		             beforeRender + st.firstFrameSeconds);
	const double secs = std::chrono::duration<double>(Clock::now() - started).count();
	if (!cmd.quiet && !cmd.jsonProgress)
		std::fprintf(stderr, "rendered %s: %lld frames %dx%d at %s fps (%.3f s of %s), %zu keyposes, emotion %s; %.1f s (%.1f frames/s, %.1fx real time)\n",
		             cmd.output.c_str(), (long long)st.frames, st.width, st.height, perf.rate.str().c_str(), toSeconds(perf.duration),
		             withAudio ? "audio" : "transcript", st.keyposes, perf.expression.emotion().label().c_str(), secs, double(st.frames) / secs, toSeconds(perf.duration) / secs);
}

std::vector<SideOutput> timelineOutput(const VideoCommand& cmd, const Performance& perf, const std::vector<PhoneSegment>& phones,
                                       const std::vector<Interval>& words) {
	if (!cmd.timelineOut) return {};
	std::string json = timelineJson(perf, phones, cmd.leadIn, cmd.tail, cmd.avOffset, words);
	return {{*cmd.timelineOut, [json = std::move(json)](const std::string& p) { writeFileAtomically(p, json); }}};
}

}  // namespace talkhead::cli
