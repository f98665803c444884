// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead render: transcript (+ audio, emotion) → talking-head video.
#include <chrono>
#include <cstdio>

#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/run.h"
#include "cli/commands.h"
#include "cli/drive_options.h"
#include "cli/video_options.h"
#include "media/audio.h"
#include "perform/plan.h"
#include "perform/speech_source.h"
#include "phonetics/language.h"

namespace talkhead::cli {

namespace {

// render's own options, then the driving video's and the video options render and say share.
std::vector<OptionSpec> renderOptionSpecs() {
	std::vector<OptionSpec> options = {
	    {"--transcript", "FILE", "timed transcript (TextGrid, .pho, HTK, GRID, speech marks, TSV, Rhubarb; - = stdin)"},
	    {"--text", "TEXT", "instead of --transcript: what --audio says, aligned to it (as 'talkhead align' does)"},
	    {"--text-file", "F", "the same, read from a file"},
	    {"--dialog", "TEXT", "with --audio: what it probably says (Rhubarb's name): aligned as --text is, but when it does not match the audio, the phones are recognised from the audio instead (a warning, not an error)"},
	    {"--audio", "FILE", "speech audio (any format libav reads); the video lasts as long as it. Alone (no --transcript or --text) its phones are recognised from the sound (en-US phone recogniser, PocketSphinx)"},
	    {"--lang", "LANG", languageOptionHelp("language of the transcript")},
	    {"--transcript-format", "FORMAT", "transcript format if detection fails"},
	    {"--tier", "NAME|N", "TextGrid tier, by name or 1-based number (default: the phone tier, else the word tier); in files of several speakers, channels or ELAN tiers: the one to read"},
	           {"--speaker", "NAME", "the speaker (channel, voice, ELAN tier) to read from a file of several (the same as --tier)"},
	    {"--timing-text", "FILE", "the text a timing file refers to but does not hold: for an aeneas SMIL or TSV sync map, the XHTML or aeneas's parsed (id|text) or plain (a fragment a line) text; for Google Text-to-Speech timepoints, the SSML with the <mark>s"},
	    {"--level", "LEVEL", "what the transcript's labels are: auto (default), phones, or words (phonemised with espeak-ng)"},
	    {"--sample-rate", "HZ", "TIMIT .phn: the sample rate its times count in (default 16000)"},
	    {"--unknown", "POLICY", "unknown phones: error (default), nearest (the closest known spelling, else an error), silence"},
	    {"--notation", "NAME", "how phones are spelled: auto (default: decided from the labels), ipa, arpabet, sampa, espeak, praat, br1"},
	    {"--drive", "VIDEO", "a person's video drives the face: head motion, brows, eyes and blinks from it (the mouth from the transcript); its audio unless --audio"},
	    {"--drive-mouth", "", "with --drive: the mouth from the video too (no transcript): per frame the model actor's exemplar of the driver's mouth class"},
	    {"--parts", "LIST", "with --drive: what the video drives (default head,brows,eyes)"},
	    {"--drive-model", "F.dat", "with --drive: dlib 68-point predictor"}};
	for (auto& o : nonVerbalOptionSpecs()) options.push_back(o);
	for (auto& o : videoOptionSpecs()) options.push_back(o);
	return options;
}

// The speech the flags name (perform/speech_source.h): --transcript, or --text / --text-file with the
// sound (--audio, else with --drive the driving video's own); none with --drive-mouth alone. The text of
// --text-file is read once every option is checked.
SpeechSource parseSpeechSource(const Args& args, const Driving& drive) {
	SpeechSource s;
	s.audio = args.get("--audio");
	if (!s.audio && drive.hasAudio()) s.audio = *drive.video;
	const auto transcript = args.get("--transcript"), dialog = args.get("--dialog");
	const auto text = dialog ? dialog : args.get("--text"), textFile = args.get("--text-file");
	if (dialog && (args.get("--text") || textFile)) throw UsageError("render: give --dialog or --text, not both");
	s.textIsHint = bool(dialog);
	if (text && textFile) throw UsageError("render: give --text or --text-file, not both");
	if (transcript && (text || textFile)) throw UsageError("render: give --transcript or --text, not both");
	if (!transcript && !text && !textFile && !drive.mouth && !s.audio)
		throw UsageError("render: --transcript FILE, --audio A with --text, or --audio A alone (its phones recognised) is required");
	if ((text || textFile) && !s.audio)
		throw UsageError(drive.video ? "render: --text needs speech to align to, and the --drive video has no audio: give --audio"
		                             : "render: --text needs --audio (the speech to align the text to)");
	if (transcript) s.kind = SpeechSource::Kind::Transcript, s.transcript = *transcript;
	else if (text || textFile) s.kind = SpeechSource::Kind::AlignedText, s.text = text.value_or(""), s.textName = dialog ? "dialog" : textFile.value_or("text");
	else if (!drive.mouth) s.kind = SpeechSource::Kind::RecognizedAudio;  // audio alone: its phones recognised
	return s;
}

}  // namespace

int runRender(const std::vector<std::string>& argv) {
	const std::vector<OptionSpec> options = renderOptionSpecs();
	Args args("render", "talkhead render (--transcript T [--audio A] | --audio A [--text \"…\"]) [--emotion LABEL] -o OUT.mp4 [options]", options,
	          "Renders a talking-head video (Costa 2015 §5): one keypose per phone at its midpoint (pauses: rest, then\n"
	          "a breath before speech; --pauses thesis for the thesis rule), its appearance\n"
	          "from the face model for (emotion, context-dependent viseme), feature points moving on zero-tangent\n"
	          "Hermite curves between keyposes, forward and backward piecewise-affine warps and a cross-dissolve;\n"
	          "H.264 + AAC MP4 muxed in process.");
	if (!args.parse(argv)) return 0;
	const auto t0 = std::chrono::steady_clock::now();
	if (!args.positionals().empty()) throw UsageError("render: unexpected argument '" + args.positionals()[0] + "'");
	// Every option is checked before any file is read.
	Driving drive = parseDriving(args, "render");
	SpeechSource source = parseSpeechSource(args, drive);
	TranscriptOptions to = parseTranscriptOptions(args, "render", "--transcript-format");
	const VideoCommand cmd = parseVideoCommand(args, "render");
	if (drive.video && cmd.controls && !cmd.controls->curves.empty())
		throw UsageError("render: --controls " + cmd.controls->path + " has curves and --drive gives them too: give one");
	const Language& lang = transcriptLanguage(args, source.transcript, args.get("--transcript-format", ""));
	if (auto f = args.get("--text-file")) source.text = readTextFile(*f);
	to.read.knownPhone = [&lang](const std::string& label) { return lang.normalize(label).has_value(); };
	source.read = to.read, source.unknown = to.unknown, source.notation = to.notation, source.wantWords = bool(cmd.timelineOut);
	drive.track(cmd.quiet);  // D55: first (its mouth may make the keyposes)
	// None with --drive-mouth: the keyposes come from the driver's mouth.
	const TimedSpeech speech = loadSpeech(source, lang, [&](const Transcript& t) { noteWordLanguage(args, t, lang, source.transcript); });
	const std::optional<std::string>& audioPath = source.audio;
	reportSpeech(cmd, speech);
	const VideoFace face = loadVideoFace(cmd);
	PerformanceSpec spec = performanceSpec(cmd, face);
	spec.phones = speech.phones;
	spec.timing = speech.timing;
	spec.source = speech.name;
	if (drive.mouth) drive.mouthKeys(spec, *face.model, cmd.expression.emotion());
	// The sound (decoded once without keeping it, unless aligned; at the file's own sample rate).
	std::unique_ptr<AudioSource> sound;
	if (audioPath) {
		spec.audioDuration = speech.audio.samples.empty() ? audioFileDuration(*audioPath, 0) : speech.audio.duration();
		sound = speech.audio.samples.empty() ? openAudioFile(*audioPath, 0) : clipSource(speech.audio);
	}
	if (cmd.controls) spec.controls.push_back(*cmd.controls);
	// D55: the head, brows, eyes and blinks of the driving video (its blinks after the sound's end not drawn).
	if (drive.video) spec.controls.push_back(clippedTo(controlsOf(drive.nv), spec.videoDuration()));
	std::vector<std::string> warnings;
	Performance perf = planPerformance(spec, &warnings);
	for (const std::string& w : warnings) std::fprintf(stderr, "talkhead: warning: %s\n", shownLine(*audioPath + ": " + w).c_str());
	drive.report(perf, cmd.quiet);
	// Which TextGrid tier was read (once everything is checked: an error stays one line).
	if (!speech.read.tier.empty() && !cmd.quiet)
		std::fprintf(stderr, "%s\n", shownLine("talkhead: " + speech.name + ": tier '" + speech.read.tier + "' (" + speech.read.tierNote + ")").c_str());
	sound = applyStimulusTiming(cmd, perf, std::move(sound));
	runVideoCommand(cmd, face, perf, std::move(sound), t0, "", timelineOutput(cmd, perf, speech.phones, speech.words));
	return 0;
}

}  // namespace talkhead::cli
