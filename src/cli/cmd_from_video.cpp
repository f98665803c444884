// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead corpus from-video VIDEO [--transcript T | --text "…"] [--emotion LABEL] [--lang L] -o CORPUS_DIR
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "align/align.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/output_dir.h"
#include "base/progress.h"
#include "media/video_reader.h"
#include "phonetics/labels.h"
#include "phonetics/language.h"
#include "track/from_video.h"
#include "track/landmarks.h"

namespace talkhead::cli {

namespace {

// The phones of the video's speech (and its words, where known), from --transcript, or --text/--text-file
// aligned to the audio (the video's own track, or --audio).
std::vector<PhoneSegment> videoSpeech(const Args& args, const std::string& video, const VideoInfo& info, const Language& lang, bool quiet,
                                      std::vector<Interval>& words) {
	const std::string audio = args.get("--audio", video);
	if (!args.has("--audio") && !info.hasAudio)
		throw Error(video, 0, "has no audio track to align the text with (give --audio, or --select-by-shape)");
	Transcript phoneTranscript;
	if (auto t = args.get("--transcript")) {
		phoneTranscript = readTranscript(*t);
	} else {
		const std::string text = args.has("--text") ? *args.get("--text") : readTextFile(*args.get("--text-file"));
		AlignOptions ao;
		ao.languageTag = lang.tag();
		Alignment a = alignSpeechFile(audio, text, ao);
		for (const auto& w : a.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", safeLine(w).c_str());
		if (!quiet) std::fprintf(stderr, "aligned the text to %s (confidence %.2f)\n", audio.c_str(), a.confidence);
		phoneTranscript = a.phones;
		words = a.words.intervals;
	}
	if (phoneTranscript.level == LabelLevel::Word) words = phoneTranscript.intervals;
	// An alignment's phones are canonical IPA; a transcript's notation is decided from its labels.
	return phoneSegments(phoneTranscript, lang, UnknownPhone::Error, args.get("--transcript") ? Notation::Auto : Notation::Ipa);
}

}  // namespace

int runCorpusFromVideo(const std::vector<std::string>& argv) {
	Args args("corpus from-video", "talkhead corpus from-video VIDEO [--transcript T | --text \"…\"] [options] -o CORPUS_DIR",
	          {{"--output", "DIR", "corpus folder to write: corpus.csv, frames/, contact.png, landmarks.tsv (required)", "-o"},
	           {"--transcript", "T", "timed phones or words of the video's speech (TextGrid, .lab, GRID .align, …)"},
	           {"--text", "TEXT", "the words spoken: aligned to the audio with 'talkhead align'"},
	           {"--text-file", "F", "the same, from a file"},
	           {"--audio", "A", "the speech audio, when it is not the video's own audio track"},
	           {"--lang", "LANG", "pt-BR (default) or en-US: the phones' language"},
	           {"--emotion", "LABEL", "emotion label of every frame (default neutral)"},
	           {"--select-by-shape", "", "choose frames by mouth shape, not by phones (automatic without audio)"},
	           {"--per-cdv", "N", "frames kept per (emotion, CDV) (default 1)"},
	           {"--baseface", "FRAME", "frame index (0-based) of the neutral baseface (default: the most neutral found)"},
	           {"--landmarks", "F.tsv", "use this landmarks.tsv ('corpus landmarks') instead of tracking again"},
	           {"--start", "T", "use the video from T seconds (or m:ss)"},
	           {"--duration", "T", "use T seconds of the video"},
	           {"--min-confidence", "C", "tracked frames less consistent than this are never chosen (default 0.6)"},
	           {"--quiet", "", "no progress and no summary", "-q"}},
	          "Turns a video of a face into a viseme corpus for 'talkhead build': tracks the 68 points (dlib), then\n"
	          "picks for each phone the frame at the articulators' inflection point (the extremum of the lip opening\n"
	          "inside the phone) and labels it with its context-dependent viseme; without audio (or with\n"
	          "--select-by-shape), picks for each CDV the frames whose normalised mouth shape best matches the CDV's\n"
	          "articulatory target (phonetics/cdv-mouth-targets.tsv, scaled to the speaker), labelled with --emotion.\n"
	          "The head may move: frames are stored with their points as they are (the builder's Procrustes removes\n"
	          "pose); the baseface is the most neutral frame unless --baseface says which.");
	if (!args.parse(argv)) return 0;
	args.onePositional("give one video");
	const std::string out = args.required("--output", "-o DIR is required");
	const std::string video = args.positionals()[0];
	const int textSources = int(args.has("--transcript")) + int(args.has("--text")) + int(args.has("--text-file"));
	if (textSources > 1) throw UsageError("corpus from-video: give one of --transcript, --text and --text-file");
	bool byShape = args.has("--select-by-shape");
	if (byShape && textSources) throw UsageError("corpus from-video: --select-by-shape chooses without a transcript; drop --transcript/--text");
	FromVideoOptions fo;
	if (auto e = args.get("--emotion")) {
		auto c = canonicalEmotion(*e);
		if (!c) throw UsageError("corpus from-video: unknown emotion '" + *e + "'");
		fo.emotion = *c;
	}
	fo.perCdv = int(args.number("--per-cdv", 1, 1, 100));
	fo.baseface = std::int64_t(args.number("--baseface", -1, 0, 1e9));
	fo.minConfidence = args.number("--min-confidence", fo.minConfidence, 0, 1);
	const std::string langTag = args.get("--lang", "pt-BR");
	const Language& lang = Language::get(langTag);
	TrackOptions to;
	if (auto s = args.get("--start")) to.start = ticksFromSeconds(parseTimeOption("--start", *s));
	if (auto d = args.get("--duration")) to.duration = ticksFromSeconds(parseTimeOption("--duration", *d));
	const bool quiet = args.has("--quiet");
	const auto t0 = std::chrono::steady_clock::now();

	// Speech: with a transcript or text the phones need audio (the video's own track, or --audio).
	VideoInfo info;
	{
		VideoReader probe(video);
		info = probe.info();
	}
	const bool autoShape = !byShape && !textSources;  // said in the summary, so that an error stays one line
	if (autoShape) byShape = true;
	std::vector<PhoneSegment> phones;
	std::vector<Interval> words;
	if (!byShape) {
		phones = videoSpeech(args, video, info, lang, quiet, words);
		// Times in the transcript are relative to the audio, which starts with the video.
	}

	OutputDir dir(out);
	ProgressBar bar(quiet);
	LandmarkTrack track;
	if (auto lm = args.get("--landmarks")) {
		track = readLandmarksTsv(*lm);
		track.info = info;
	} else {
		track = trackVideo(video, to, bar);
	}
	bar.finish();
	VideoCorpusPlan plan = byShape ? selectByShape(track, loadCdvMouthTargets(), fo) : selectByPhones(track, phones, words, fo);
	writeVideoCorpus(video, track, plan, dir.path(""));
	writeFileAtomically(dir.path("landmarks.tsv"), landmarksTsv(track));
	dir.commit();
	if (!quiet) {
		const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		std::fprintf(stderr, "wrote %s/corpus.csv: %zu frames by %s for %zu CDVs, baseface frame %lld; face in %zu of %zu frames; %.1f s\n", out.c_str(),
		             plan.entries.size(), plan.method == "shape" ? (autoShape ? "mouth shape (no transcript or text given)" : "mouth shape") : "phones",
		             std::size_t(visemeLabels().size() - plan.missing.size()), (long long)plan.basefaceFrame, track.foundCount(), track.frames.size(), secs);
		if (!plan.missing.empty()) {
			std::string m;
			for (const auto& c : plan.missing) m += (m.empty() ? "" : " ") + c;
			std::fprintf(stderr, "no frame for the CDVs: %s (the model falls back to neutral or a neighbouring viseme)\n", m.c_str());
		}
	}
	return 0;
}

}  // namespace talkhead::cli
