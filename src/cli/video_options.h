// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/args.h"
#include "media/audio.h"
#include "phonetics/language.h"
#include "perform/controls.h"
#include "perform/plan.h"
#include "perform/utterance.h"
#include "render/output.h"
#include "render/render.h"
#include "render/video_job.h"

namespace talkhead::cli {

// Throws Error naming `path` unless its folder exists and is writable (checked before any work).
void checkWritableFolder(const std::string& path);

// The options `render` and `say` share, with the same names, defaults and checks.
std::vector<OptionSpec> videoOptionSpecs();
// How the face is drawn, for render, say, live and serve alike: --trajectory, --dissolve, --warp,
// --emotion-source, --au-appearance.
std::vector<OptionSpec> drawingOptionSpecs();
void parseDrawingOptions(const Args& args, const std::string& command, SynthOptions& synth);
// --pauses, by default as the library says (defaultPauseStyle: still with a coarticulation model, which is
// the default; natural with --coarticulation off).
PauseStyle parsePausesOption(const Args& args, const std::string& command);

// A render or say: the job's output half (render/video_job.h) and what the command line adds — the
// performance's settings, the model, and how it talks to the terminal.
struct VideoCommand : VideoJob {
	std::string command;                 // "render" or "say", for messages
	std::string modelPath;               // empty = the default face
	std::optional<std::string> faceName; // --face NAME: a shipped face (built on first use) or "synthetic"
	Expression expression;               // --emotion LABEL:INTENSITY
	FrameRate rate;
	PauseStyle pauses = PauseStyle::Natural;
	ModulatorOptions modulation;
	double speechBrows = 0;  // --speech-brows: 0 off, else the raise amount (D49)
	std::optional<ControlTrack> controls;  // --controls F (read and checked with the options)
	std::shared_ptr<const CoarticulationModel> coarticulation;  // --coarticulation F (D62)
	bool quiet = false, jsonProgress = false, timing = false;
	bool verbose = false;  // -v: the timing's plausibility verdict (issue 50)
	std::optional<std::string> timelineOut;    // --timeline-out F.json
	ComponentLevels components;                // --components REGION=N,… (Appendix C reductions)
};

// How a timed transcript is read (visemes, render): the format option (`formatOption`: "--format" or
// "--transcript-format", checked against the formats known), --tier, --timing-text, --level,
// --utterance, --sample-rate, --unknown and --notation. The caller sets read.knownPhone once the language
// is known.
struct TranscriptOptions {
	ReadOptions read;
	UnknownPhone unknown = UnknownPhone::Error;
	Notation notation = Notation::Auto;
};
TranscriptOptions parseTranscriptOptions(const Args& args, const std::string& command, const std::string& formatOption);

// What reading the speech said: its notes (unless -q) and warnings, on stderr.
void reportSpeech(const VideoCommand& cmd, const TimedSpeech& speech);

// SSML marks on stderr, as JSON progress lines with --json-progress, else one line each unless -q.
void reportMarks(const VideoCommand& cmd, const std::vector<Utterance::Mark>& marks);

// --coarticulation on|off|F (D62, D90): the shipped model (on, the default), none (off) or F read.
std::shared_ptr<const CoarticulationModel> parseCoarticulation(const Args& args);

// The face a video command draws (--model, else the default face, made on first use; with the
// --coarticulation model), loaded before its performance is planned against it (PerformanceSpec::face);
// `seconds` is how long that took (--timing).
struct VideoFace {
	std::unique_ptr<FaceModel> model;
	std::unique_ptr<Face> face;  // of *model
	double seconds = 0;
};
VideoFace loadVideoFace(const VideoCommand& cmd);

// The spec of a performance with the command's frame rate, pauses, emotion, modulation and speech brows,
// planned against `face`.
PerformanceSpec performanceSpec(const VideoCommand& cmd, const VideoFace& face);

// (--lead-in / --tail / --av-offset: applyStimulusTiming(cmd, …), render/video_job.h; SideOutput there too.)
// --timeline-out: the sidecar JSON (perform/performance.h timelineJson), or nothing.
std::vector<SideOutput> timelineOutput(const VideoCommand& cmd, const Performance& perf, const std::vector<PhoneSegment>& phones,
                                       const std::vector<Interval>& words = {});

// The language of --lang (default `defaultTag`), for the commands that take it: its viseme table; with
// --generic-visemes, a language without a table maps IPA through phonetics/generic, with one warning line
// on stderr. Throws Error ("no viseme table for language …") otherwise.
const Language& languageOption(const Args& args, const std::string& defaultTag = "pt-BR");
// The language of a transcript: --lang, else the one the file states (an error naming the file when talkhead
// has no table for it), else the default.
const Language& transcriptLanguage(const Args& args, const std::string& transcriptPath, const std::string& format);
// Words are phonemised in one language: when neither --lang nor the file named it, a warning says which.
void noteWordLanguage(const Args& args, const Transcript& transcript, const Language& language, const std::string& path);
// pt-BR, or en-US for a GRID .align (English by definition), for a transcript without --lang.
std::string defaultLanguageFor(const std::string& transcriptPath, const std::string& format);
// The --lang help, naming the languages with a table.
std::string languageOptionHelp(const std::string& what);
// --generic-visemes (also in videoOptionSpecs).
OptionSpec genericVisemesOption();
// --face NAME (issue 48): a face that ships with talkhead (`talkhead faces`), built on first use.
OptionSpec faceOption();

// Reads and checks every shared option (and that the output folders exist and are writable) before any
// work is done; throws UsageError / Error. `outputRequired`: -o must be given.
VideoCommand parseVideoCommand(const Args& args, const std::string& command, bool outputRequired = true);
// --fps, --fit, and --emotion LABEL[:INTENSITY] (canonical label; an unknown one is an Error).
FrameRate parseFps(const Args& args, const std::string& command);
// --format: a file format of the registry (render/output.h; and none, nullopt, when `allowNone`), by
// default from -o's extension; a --format that contradicts the extension is ambiguous: a UsageError.
std::optional<VideoFormat> parseVideoFormat(const Args& args, const std::string& command, const std::string& output, bool allowNone);
// --background opaque|transparent; transparent in a format without alpha (mp4, y4m) is a UsageError that
// names WebM and then `alternatives` (the command's other ways to alpha).
bool parseTransparent(const Args& args, const std::string& command, std::optional<VideoFormat> format, const std::string& alternatives = "");
// --crf for the format: VP9's 0–63 (default 32) for webm, else H.264's 0–51 (default 20).
int parseCrf(const Args& args, std::optional<VideoFormat> format);
Fit parseFit(const Args& args, const std::string& command);
Expression parseEmotionOption(const Args& args, const std::string& command);
// --blinks, --head-motion, --seed (render, say, serve, live).
ModulatorOptions parseModulation(const Args& args, const std::string& command);
// --speech-brows on|off|X (default `fallback`): 0 off, else the raise amount.
double parseSpeechBrows(const Args& args, const std::string& command, const std::string& fallback);

// Renders the performance of `face` to the command's outputs and prints the summary (and, with --timing,
// the stages; `timingPrefix` names the stages before rendering, e.g. "speech 0.020 s; ").
// `started`: when the command began, for the first-frame time.
// `audio` (optional) becomes the MP4's sound track, pulled as the video advances.
// `side`: files written with the video (SideOutput); --audio-out is one too.
void runVideoCommand(const VideoCommand& cmd, const VideoFace& face, const Performance& performance, std::unique_ptr<AudioSource> audio, std::chrono::steady_clock::time_point started,
                     const std::string& timingPrefix = "", std::vector<SideOutput> side = {});

}  // namespace talkhead::cli
