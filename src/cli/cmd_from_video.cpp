// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead corpus from-video VIDEO [--transcript T | --text "…"] [--emotion LABEL] [--lang L] -o CORPUS_DIR
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "align/align.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/run.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/output_dir.h"
#include "base/progress.h"
#include "media/video_reader.h"
#include "phonetics/emotion.h"
#include "phonetics/labels.h"
#include "phonetics/language.h"
#include "track/face_build.h"
#include "track/from_video.h"
#include "track/landmarks.h"

namespace talkhead::cli {

namespace {

Args fromVideoArgs() {
	return Args("corpus from-video",
	            "talkhead corpus from-video VIDEO [--transcript T | --text \"…\"] [options] -o CORPUS_DIR\n"
	            "       talkhead corpus from-video --take VIDEO:EMOTION [--take …] | --takes LIST.tsv [--text \"…\"] [options] -o CORPUS_DIR",
	            {{"--output", "DIR", "corpus folder to write: corpus.csv, frames/, contact.png, landmarks.tsv (required)", "-o"},
	             {"--take", "VIDEO:EMOTION", "one take of the person in one emotion (repeat for each; e.g. anger.mp4:anger)"},
	             {"--takes", "LIST.tsv", "the takes as a list: columns video, emotion [start, duration, transcript, text, audio]"},
	             {"--transcript", "T", "timed phones or words of the video's speech (TextGrid, .lab, GRID .align, …)"},
	             {"--text", "TEXT", "the words spoken: aligned to the audio with 'talkhead align' (with takes: of every take without its own)"},
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
	             {"--min-eye-opening", "F", "nor frames whose eyes are less open than F × the video's median (a blink; default 0.7, 0: any)"},
	             {"--max-shut-eyes", "F", "keep the person's own shut eyes for blinks: the most shut frame whose eyes are open at most F × the median, head frontal, mouth at rest (default 0.4; 0: none, blinks draw the lid)"},
	             {"--quiet", "", "no progress and no summary", "-q"}},
	            "Turns a video of a face into a viseme corpus for 'talkhead build': tracks the 68 points (dlib), then\n"
	            "picks for each phone the frame at the articulators' inflection point (the extremum of the lip opening\n"
	            "inside the phone) and labels it with its context-dependent viseme; without audio (or with\n"
	            "--select-by-shape), picks for each CDV the frames whose normalised mouth shape best matches the CDV's\n"
	            "articulatory target (phonetics/cdv-mouth-targets.tsv, scaled to the speaker), labelled with --emotion.\n"
	            "The head may move: frames are stored with their points as they are (the builder's Procrustes removes\n"
	            "pose); the baseface is the most neutral frame unless --baseface says which. Several takes of one\n"
	            "person, each in its emotion (--take, --takes), make one corpus: the baseface is the neutral take's (else\n"
	            "the first's), and every take's colours are matched to that take's over the face.");
}

// The takes the arguments name: --take/--takes, or the one video with its options.
std::vector<VideoTake> takesOf(const Args& args) {
	std::string text;
	if (auto t = args.get("--text")) text = *t;
	else if (auto f = args.get("--text-file")) text = readTextFile(*f);
	const bool listed = args.has("--take") || args.has("--takes");
	if (!listed) {
		args.onePositional("give one video (or --take VIDEO:EMOTION for each take)");
		VideoTake t;
		t.video = args.positionals()[0];
		t.where = t.video;
		if (auto e = args.get("--emotion")) {
			auto c = canonicalEmotion(*e);
			if (!c) throw UsageError("corpus from-video: unknown emotion '" + *e + "'");
			t.emotion = *c;
		}
		t.transcript = args.get("--transcript", "");
		t.text = text;
		t.audio = args.get("--audio", "");
		if (auto s = args.get("--start")) t.start = ticksFromSeconds(parseTimeOption("--start", *s));
		if (auto d = args.get("--duration")) t.duration = ticksFromSeconds(parseTimeOption("--duration", *d));
		return {t};
	}
	if (!args.positionals().empty()) throw UsageError("corpus from-video: with --take/--takes, name no video as an argument");
	for (const char* o : {"--emotion", "--transcript", "--audio", "--landmarks", "--start", "--duration", "--baseface"})
		if (args.has(o)) throw UsageError(std::string("corpus from-video: ") + o + " is per take: give it in the take list (--takes)");
	std::vector<VideoTake> takes;
	if (auto list = args.get("--takes")) takes = readTakeList(*list);
	for (const std::string& spec : args.all("--take")) takes.push_back(parseTakeSpec(spec));
	for (VideoTake& t : takes)
		if (t.transcript.empty() && t.text.empty()) t.text = text;
	return takes;
}

// One take: tracked, its frames chosen (by phones with speech, else by mouth shape); the alignment's
// confidence and warnings printed.
TakePlan planTake(const VideoTake& take, const Args& args, const FromVideoOptions& options, const Language& lang, bool byShape, bool quiet) {
	ProgressBar bar(quiet);
	TakeSpeechNote note;
	TakePlan tp = planVideoTake(take, lang, options, byShape, args.get("--landmarks", ""), bar, &note);
	bar.finish();
	for (const auto& w : note.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", shownLine(w).c_str());
	if (!quiet && note.alignConfidence) std::fprintf(stderr, "aligned the text to %s (confidence %.2f)\n", note.alignedAudio.c_str(), *note.alignConfidence);
	return tp;
}

}  // namespace

int runCorpusFromVideo(const std::vector<std::string>& argv) {
	Args args = fromVideoArgs();
	if (!args.parse(argv)) return 0;
	if (!args.has("--take") && !args.has("--takes")) args.onePositional("give one video (or --take VIDEO:EMOTION for each take)");
	const std::string out = args.required("--output", "-o DIR is required");
	const int textSources = int(args.has("--transcript")) + int(args.has("--text")) + int(args.has("--text-file"));
	if (textSources > 1) throw UsageError("corpus from-video: give one of --transcript, --text and --text-file");
	const std::vector<VideoTake> takes = takesOf(args);
	bool byShape = args.has("--select-by-shape");
	const bool anySpeech = std::any_of(takes.begin(), takes.end(), [](const VideoTake& t) { return !t.transcript.empty() || !t.text.empty(); });
	if (byShape && anySpeech) throw UsageError("corpus from-video: --select-by-shape chooses without a transcript; drop --transcript/--text");
	const bool allSpeech = std::all_of(takes.begin(), takes.end(), [](const VideoTake& t) { return !t.transcript.empty() || !t.text.empty(); });
	if (anySpeech && !allSpeech) throw UsageError("corpus from-video: some takes have speech and some not: give every take a transcript or text, or none");
	FromVideoOptions fo;
	fo.perCdv = int(args.number("--per-cdv", 1, 1, 100));
	fo.baseface = std::int64_t(args.number("--baseface", -1, 0, 1e9));
	fo.minConfidence = args.number("--min-confidence", fo.minConfidence, 0, 1);
	fo.minEyeOpening = args.number("--min-eye-opening", fo.minEyeOpening, 0, 1);
	fo.maxShutEyes = args.number("--max-shut-eyes", fo.maxShutEyes, 0, 1);
	const Language& lang = Language::get(args.get("--lang", "pt-BR"));
	const bool quiet = args.has("--quiet");
	const auto t0 = std::chrono::steady_clock::now();
	const bool autoShape = !byShape && !anySpeech;  // said in the summary, so that an error stays one line
	if (autoShape) byShape = true;

	std::vector<TakePlan> plans;
	for (const VideoTake& take : takes) {
		if (!quiet && takes.size() > 1 && ::isatty(2)) std::fprintf(stderr, "take %zu of %zu: %s (%s)\n", plans.size() + 1, takes.size(), take.video.c_str(), take.emotion.c_str());
		plans.push_back(planTake(take, args, fo, lang, byShape, quiet));
	}
	// The baseface: the neutral take's (the first neutral one), else the first take's.
	const std::size_t base = basefaceTake(plans);
	OutputDir dir(out);
	const std::vector<ColourMatch> matches = writeTakesCorpus(plans, base, dir.path(""));
	if (plans.size() == 1) {
		writeFileAtomically(dir.path("landmarks.tsv"), landmarksTsv(plans[0].track));
	} else {
		for (std::size_t k = 0; k < plans.size(); ++k)
			writeFileAtomically(dir.path("landmarks-take" + std::to_string(k + 1) + ".tsv"), landmarksTsv(plans[k].track));
	}
	dir.commit();
	if (quiet) return 0;
	const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	for (std::size_t k = 0; k < plans.size(); ++k) {
		const VideoCorpusPlan& plan = plans[k].plan;
		const LandmarkTrack& track = plans[k].track;
		if (plans.size() == 1)
			std::fprintf(stderr, "wrote %s/corpus.csv: %zu frames by %s for %zu CDVs, baseface frame %lld; face in %zu of %zu frames; %.1f s\n", out.c_str(),
			             plan.entries.size(), plan.method == "shape" ? (autoShape ? "mouth shape (no transcript or text given)" : "mouth shape") : "phones",
			             std::size_t(visemeLabels().size() - plan.missing.size()), (long long)plan.basefaceFrame, track.foundCount(), track.frames.size(), secs);
		else
			std::fprintf(stderr, "take %zu (%s): %zu frames by %s for %zu CDVs; face in %zu of %zu frames; colour gain %.2f %.2f %.2f%s\n", k + 1,
			             plans[k].take.emotion.c_str(), plan.entries.size(), plan.method == "shape" ? "mouth shape" : "phones",
			             std::size_t(visemeLabels().size() - plan.missing.size()), track.foundCount(), track.frames.size(), matches[k].gain[0], matches[k].gain[1],
			             matches[k].gain[2], k == base ? " (the baseface's take)" : "");
		if (plan.closedEyes) std::fprintf(stderr, "blinks: the person's own shut eyes, frame %lld\n", (long long)plan.closedEyes->frame);
		else if (plans.size() == 1) std::fprintf(stderr, "blinks: no frame with the eyes shut, the head frontal and the mouth at rest: blinks draw the lid\n");
		if (!plan.missing.empty() && plans.size() == 1) {
			std::string m;
			for (const auto& c : plan.missing) m += (m.empty() ? "" : " ") + c;
			std::fprintf(stderr, "no frame for the CDVs: %s (the model falls back to neutral or a neighbouring viseme)\n", m.c_str());
		}
	}
	if (plans.size() > 1) {
		std::string emotions;
		for (const auto& p : plans) emotions += (emotions.empty() ? "" : ", ") + p.take.emotion;
		std::fprintf(stderr, "wrote %s/corpus.csv: %zu takes (%s), baseface from take %zu; %.1f s. Emotions no take has render from the neutral frames by their action units (--emotion-source auto).\n",
		             out.c_str(), plans.size(), emotions.c_str(), base + 1, secs);
	}
	return 0;
}

}  // namespace talkhead::cli
