// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead render: transcript (+ audio, emotion) → talking-head video.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "align/align.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/drive_options.h"
#include "track/drive_mouth.h"
#include "media/video_reader.h"
#include "cli/video_options.h"
#include "media/audio.h"
#include "phonetics/language.h"

namespace talkhead::cli {

int runRender(const std::vector<std::string>& argv) {
	std::vector<OptionSpec> options = {
	    {"--transcript", "FILE", "timed transcript (TextGrid, .pho, HTK, GRID, speech marks, TSV, Rhubarb; - = stdin)"},
	    {"--text", "TEXT", "instead of --transcript: what --audio says, aligned to it (as 'talkhead align' does)"},
	    {"--text-file", "F", "the same, read from a file"},
	    {"--audio", "FILE", "speech audio (any format libav reads); the video lasts as long as it"},
	    {"--lang", "LANG", languageOptionHelp("language of the transcript")},
	    {"--transcript-format", "FORMAT", "transcript format if detection fails"},
	    {"--tier", "NAME|N", "TextGrid tier, by name or 1-based number (default: the phone tier, else the word tier)"},
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
	Args args("render", "talkhead render (--transcript T [--audio A] | --audio A --text \"…\") [--emotion LABEL] -o OUT.mp4 [options]", options,
	          "Renders a talking-head video (Costa 2015 §5): one keypose per phone at its midpoint (pauses: rest, then\n"
	          "a breath before speech; --pauses thesis for the thesis rule), its appearance\n"
	          "from the face model for (emotion, context-dependent viseme), feature points moving on zero-tangent\n"
	          "Hermite curves between keyposes, forward and backward piecewise-affine warps and a cross-dissolve;\n"
	          "H.264 + AAC MP4 muxed in process.");
	if (!args.parse(argv)) return 0;
	const auto t0 = std::chrono::steady_clock::now();
	if (!args.positionals().empty()) throw UsageError("render: unexpected argument '" + args.positionals()[0] + "'");
	// Every option is checked before any file is read.
	auto transcriptPath = args.get("--transcript");
	const auto drive = args.get("--drive");
	const bool driveMouth = args.has("--drive-mouth");
	if (driveMouth && !drive) throw UsageError("render: --drive-mouth goes with --drive VIDEO");
	if (driveMouth && (transcriptPath || args.get("--text") || args.get("--text-file")))
		throw UsageError("render: --drive-mouth takes the mouth from the video: give no --transcript or --text");
	if (!drive && (args.get("--parts") || args.get("--drive-model") || args.get("--neutral-frames") || args.get("--neutral-seconds") || args.get("--max-turn")))
		throw UsageError("render: --parts, --drive-model, --neutral-frames, --neutral-seconds and --max-turn go with --drive VIDEO");
	const NonVerbalOptions driveOptions = parseNonVerbalOptions(args, "render", "head,brows,eyes");
	// The sound: --audio, else (with --drive) the driving video's own.
	std::optional<std::string> audioPath = args.get("--audio");
	if (!audioPath && drive && VideoReader(*drive).info().hasAudio) audioPath = *drive;
	std::optional<std::string> text = args.get("--text");
	if (text && args.get("--text-file")) throw UsageError("render: give --text or --text-file, not both");
	if (transcriptPath && (text || args.get("--text-file"))) throw UsageError("render: give --transcript or --text, not both");
	if (!transcriptPath && !text && !args.get("--text-file") && !driveMouth) throw UsageError("render: --transcript FILE (or --audio A with --text) is required");
	if ((text || args.get("--text-file")) && !audioPath)
		throw UsageError(drive ? "render: --text needs speech to align to, and the --drive video has no audio: give --audio"
		                       : "render: --text needs --audio (the speech to align the text to)");
	const std::string policy = args.get("--unknown", "error");
	if (policy != "error" && policy != "nearest" && policy != "silence") throw UsageError("render: --unknown must be error, nearest or silence");
	const UnknownPhone unknown = policy == "nearest" ? UnknownPhone::Nearest : policy == "silence" ? UnknownPhone::Silence : UnknownPhone::Error;
	const auto notation = parseNotation(args.get("--notation", "auto"));
	if (!notation) throw UsageError("render: --notation takes auto, ipa, arpabet, sampa, xsampa, espeak, praat or br1");
	const std::string level = args.get("--level", "auto");
	if (level != "auto" && level != "phones" && level != "words") throw UsageError("render: --level takes auto, phones or words");
	const VideoCommand cmd = parseVideoCommand(args, "render");
	if (drive && cmd.controls && !cmd.controls->curves.empty())
		throw UsageError("render: --controls " + cmd.controls->path + " has curves and --drive gives them too: give one");
	const Language& lang = languageOption(args, defaultLanguageFor(transcriptPath.value_or(""), args.get("--transcript-format", "")));
	if (auto f = args.get("--text-file")) text = readTextFile(*f);

	// Timeline.
	ReadOptions ro;
	ro.format = args.get("--transcript-format", "");
	ro.tier = args.get("--tier", "");
	ro.timingText = args.get("--timing-text", "");
	if (level != "auto") ro.level = level == "words" ? LabelLevel::Word : LabelLevel::Phone;
	ro.knownPhone = [&lang](const std::string& label) { return lang.normalize(label).has_value(); };
	ro.sampleRate = int(args.number("--sample-rate", 16000, 1000, 192000));
	AudioClip audio;
	Transcript tr;
	bool aligned = false;         // sentence cues aligned to the audio: canonical IPA phones
	std::vector<Interval> words;  // for the timeline sidecar, when known
	// D55: the driving video, tracked first (its mouth may make the keyposes).
	NonVerbalTrack nv;
	LandmarkTrack driverLandmarks;
	if (drive) nv = trackNonVerbal(*drive, driveOptions, args.get("--drive-model", ""), cmd.quiet, driveMouth ? &driverLandmarks : nullptr);
	if (driveMouth) {
		// No transcript: the keyposes come from the driver's mouth.
	} else if (text) {
		// Forced alignment of the text to the audio (align/align.h), as `talkhead align` does.
		audio = decodeAudio(*audioPath);
		AlignOptions ao;
		ao.languageTag = lang.tag();
		Alignment al;
		try {
			al = alignSpeech(audio, *text, ao);
		} catch (const Error& e) {
			throw Error(*audioPath, 0, e.what());
		}
		for (const std::string& w : al.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", safeLine(*audioPath + ": " + w).c_str());
		if (!cmd.quiet) std::fprintf(stderr, "aligned: %s\n", alignmentSummary(al).c_str());
		tr = al.phones;
		words = al.words.intervals;
		transcriptPath = *audioPath;
	} else {
		tr = readTranscript(*transcriptPath, ro);
		noteWordLanguage(args, tr, lang, *transcriptPath);
		if (tr.level == LabelLevel::Word) words = tr.intervals;
		else if (cmd.timelineOut && tr.format == "textgrid" && *transcriptPath != "-") words = textGridWords(*transcriptPath, tr.tier);
		// Sentence-level cues (subtitles, aeneas, utterance tiers) with the speech at hand: each cue's text is
		// aligned to its own stretch of the audio (issue 29), not spread by espeak-ng's durations.
		const bool sentences = std::any_of(tr.intervals.begin(), tr.intervals.end(), [](const Interval& i) { return i.label.find(' ') != std::string::npos; });
		if (tr.level == LabelLevel::Word && sentences && audioPath) {
			audio = decodeAudio(*audioPath);
			tr = alignCues(tr, audio, lang.tag(), *audioPath);
			aligned = true;
			const auto cues = std::count_if(words.begin(), words.end(), [](const Interval& i) { return !isPauseLabel(i.label); });
			if (!cmd.quiet) std::fprintf(stderr, "talkhead: %s: %zu cues aligned to %s\n", transcriptPath->c_str(), std::size_t(cues), audioPath->c_str());
		}
		for (const std::string& w : tr.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", safeLine(*transcriptPath + ": " + w).c_str());
	}
	std::vector<PhoneSegment> phones;
	if (!driveMouth) phones = phoneSegments(tr, lang, unknown, text || aligned ? Notation::Ipa : *notation);  // an alignment's phones are canonical IPA
	Performance perf;
	perf.rate = cmd.rate;
	perf.emotion = cmd.emotion;
	perf.modulation = cmd.modulation;
	perf.intensity = cmd.intensity;
	std::size_t exemplarChoices = 0;
	if (driveMouth) {
		const DrivenMouth dm = talkhead::driveMouth(driverLandmarks, loadRenderModel(cmd.modelPath, cmd.components), cmd.emotion);
		perf.keys = dm.keys;
		exemplarChoices = dm.exemplarChoices;
	} else {
		perf.keys = keyposes(phones, cmd.rate.frameLength(), cmd.pauses);
	}
	if (cmd.speechBrows > 0) {  // D49
		const auto brows = speechBrows(phones, cmd.speechBrows);
		perf.modulation.browEvents.insert(perf.modulation.browEvents.end(), brows.begin(), brows.end());
	}
	// Duration: the audio's (decoded once without keeping it, unless aligned), or the transcript's.
	perf.duration = driveMouth ? nv.curves().end() + ticksFromSeconds(1 / nv.rate) : phones.back().end;
	std::unique_ptr<AudioSource> sound;
	if (auto a = audioPath) {
		// (At the file's own sample rate: no resampling, and an MP4 index a third of 48 kHz's for 16 kHz speech.)
		const Ticks audioDur = audio.samples.empty() ? audioFileDuration(*a, 0) : audio.duration();
		sound = audio.samples.empty() ? openAudioFile(*a, 0) : clipSource(audio);
		const Ticks tolerance(kTicksPerSecond / 10);
		if (!driveMouth && perf.duration > audioDur + tolerance) {
			char buf[200];
			std::snprintf(buf, sizeof buf, "the transcript (%.3f s) is longer than the audio (%.3f s) by %.3f s", toSeconds(perf.duration),
			              toSeconds(audioDur), toSeconds(perf.duration - audioDur));
			throw Error(*transcriptPath, 0, buf);
		}
		// A transcript covering a small part of a long audio: the face holds still for the rest. Say so.
		const Ticks uncovered = audioDur - perf.duration;
		if (!driveMouth && uncovered > Ticks(10 * kTicksPerSecond) && perf.duration * 2 < audioDur)
			std::fprintf(stderr, "talkhead: warning: %s: the transcript covers %.1f s of %.1f s of audio; the face holds its last keypose, silent, for the other %.1f s\n",
			             a->c_str(), toSeconds(perf.duration), toSeconds(audioDur), toSeconds(uncovered));
		perf.duration = audioDur;
	}
	if (cmd.controls) applyControls(perf, *cmd.controls);
	if (drive) {  // D55: the head, brows, eyes and blinks of the driving video
		ControlTrack driven = controlsOf(nv);
		// A driver longer than the sound: its blinks after the end are not drawn.
		driven.blinks.erase(std::remove_if(driven.blinks.begin(), driven.blinks.end(), [&](Ticks t) { return t > perf.duration; }), driven.blinks.end());
		applyControls(perf, driven);
		const Ticks videoEnd = nv.curves().end() + ticksFromSeconds(1 / nv.rate);
		if (videoEnd + ticksFromSeconds(0.5) < perf.duration)
			std::fprintf(stderr, "talkhead: warning: %s: the video (%.2f s) is shorter than the render (%.2f s); the head holds its last pose after it\n",
			             drive->c_str(), toSeconds(videoEnd), toSeconds(perf.duration));
		if (!cmd.quiet)
			std::fprintf(stderr, "talkhead: %s drives the face: %zu frames, %zu blink(s)%s%s\n", drive->c_str(), nv.frames.size(), nv.blinks.size(),
			             nv.bridged.empty() ? "" : ", some frames bridged",
			             driveMouth ? (", the mouth: " + std::to_string(perf.keys.size()) + " keyposes (" + std::to_string(exemplarChoices) +
			                           " exemplars chosen by shape)").c_str() : "");
	}
	// Which TextGrid tier was read (once everything is checked: an error stays one line).
	if (!tr.tier.empty() && !cmd.quiet) std::fprintf(stderr, "talkhead: %s: tier '%s' (%s)\n", transcriptPath->c_str(), tr.tier.c_str(), tr.tierNote.c_str());
	sound = applyStimulusTiming(cmd, perf, std::move(sound));
	runVideoCommand(cmd, perf, std::move(sound), t0, "", timelineOutput(cmd, perf, phones, words));
	return 0;
}

}  // namespace talkhead::cli
