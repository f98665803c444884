// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead say: text → speech (libespeak-ng) and talking-head video, in one process.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/render_video.h"
#include "media/audio.h"
#include "phonetics/espeak.h"
#include "phonetics/labels.h"
#include "phonetics/writers.h"

namespace talkhead::cli {

int runSay(const std::vector<std::string>& argv) {
	Args args("say", "talkhead say \"TEXT\"|- [--lang pt-BR] [--emotion joy] -o out.mp4 [options]",
	          {{"--text-file", "F", "read the text from a file"},
	           {"--lang", "LANG", "pt-BR (default) or en-US (the languages with a viseme table)"},
	           {"--voice", "NAME", "espeak-ng voice (default: the language, e.g. pt-br; mb-br1 etc. need MBROLA)"},
	           {"--rate", "WPM", "speaking rate in words per minute (80–450; default 175)"},
	           {"--pitch", "N", "pitch 0–100 (default 50)"},
	           {"--emotion", "LABEL", "one of the 23 emotion labels or an alias (default neutral)"},
	           {"--model", "M.thm", "face model (default: the embedded default face)"},
	           {"--fps", "N", "frame rate (default 30)"},
	           {"--pauses", "STYLE", "pauses: natural (default: rest soon after speech, a breath before it) or thesis (one silence keypose at each pause midpoint)"},
	           {"--size", "WxH", "output size (default: the model's frame size)"},
	           {"--format", "FORMAT", "mp4 (default) or y4m (e.g. -o - | ffplay -)"},
	           {"--crf", "N", "H.264 quality 0–51 (default 20)"},
	           {"--preset", "NAME", "x264 preset (default veryfast)"},
	           {"--save-audio", "F.wav", "also write the synthesised speech"},
	           {"--save-transcript", "F.TextGrid", "also write the phone timeline (re-render it with 'talkhead render')"},
	           {"--dry-run", "", "print the viseme timeline (TSV) and render nothing"},
	           {"--threads", "N", "worker threads (default: all cores)"},
	           {"--timing", "", "print the time of each stage"},
	           {"--json-progress", "", "machine-readable progress lines on stderr"},
	           {"--quiet", "", "no progress and no summary", "-q"},
	           {"--output", "OUT", "the video to write", "-o"}},
	          "Speaks the text with libespeak-ng (in process: PCM and phoneme timings in one pass), maps the phones\n"
	          "to context-dependent visemes and renders the talking head with the speech as its audio track.");
	if (!args.parse(argv)) return 0;
	std::string text;
	if (auto f = args.get("--text-file")) {
		if (!args.positionals().empty()) throw UsageError("say: give the text or --text-file, not both");
		text = readTextFile(*f);
	} else if (args.positionals().size() == 1 && args.positionals()[0] == "-") {
		text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
	} else {
		for (const auto& p : args.positionals()) text += (text.empty() ? "" : " ") + p;
	}
	const bool dryRun = args.has("--dry-run");
	const auto pauses = parsePauseStyle(args.get("--pauses", "natural"));
	if (!pauses) throw UsageError("say: --pauses takes natural or thesis");
	auto output = args.get("--output");
	if (!output && !dryRun) throw UsageError("say: -o OUT is required (or --dry-run)");
	const std::string langTag = args.get("--lang", "pt-BR");
	const Language& lang = Language::get(langTag);
	const auto emotion = canonicalEmotion(args.get("--emotion", "neutral"));
	if (!emotion) throw Error("unknown emotion '" + args.get("--emotion", "") + "'");
	const int rate = int(args.number("--rate", 0, 80, 450));
	const int pitch = int(args.number("--pitch", -1, 0, 100));
	const auto t0 = std::chrono::steady_clock::now();
	Speech speech = espeakSpeak(text, args.get("--voice", espeakVoiceFor(lang.tag())), rate, pitch);
	const double speechSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	// espeak-ng's phoneme names are IPA; any it has that the tables lack take the nearest known phone.
	std::vector<PhoneSegment> phones = phoneSegments(speech.phones, lang, UnknownPhone::Nearest);
	RenderJob job;
	{
		const std::string fps = args.get("--fps", "30");
		long long n;
		if (!parseInt(fps, n) || n < 1 || n > 240) throw UsageError("say: --fps must be 1–240");
		job.video.fpsNum = int(n);
	}
	const Ticks frame(kTicksPerSecond / job.video.fpsNum);
	job.keys = keyposes(phones, frame, *pauses);
	if (dryRun) {
		std::cout << formatVisemes(phones, job.keys, "tsv", lang.tag(), "espeak-ng");
		return 0;
	}
	AudioClip audio;
	audio.sampleRate = speech.sampleRate;
	audio.channels = 1;
	audio.samples.reserve(speech.pcm.size());
	for (short v : speech.pcm) audio.samples.push_back(float(v) / 32768.f);
	if (auto f = args.get("--save-audio")) writeWav(*f, audio);
	if (auto f = args.get("--save-transcript")) {
		writeFileAtomically(*f, formatVisemes(phones, job.keys, "textgrid", lang.tag(), "espeak-ng"));
	}
	job.duration = audio.duration();
	job.frames = frameCount(job.duration, job.video.fpsNum, job.video.fpsDen);
	job.video.crf = int(args.number("--crf", 20, 0, 51));
	job.video.preset = args.get("--preset", "veryfast");
	job.synth.emotion = *emotion;
	if (auto s = args.get("--size")) parseSize("say: --size", *s, job.synth.width, job.synth.height);
	job.output = *output;
	job.format = args.get("--format", "mp4");
	if (job.format != "mp4" && job.format != "y4m") throw UsageError("say: --format must be mp4 or y4m");
	if (job.output == "-" && job.format != "y4m") throw UsageError("say: -o - needs --format y4m");
	job.modelPath = args.get("--model", "");
	job.audio = &audio;
	job.quiet = args.has("--quiet");
	job.jsonProgress = args.has("--json-progress");
	job.timing = args.has("--timing");
	job.threads = unsigned(args.number("--threads", 0, 0, 256));
	job.started = t0;
	char prefix[64];
	std::snprintf(prefix, sizeof prefix, "speech synthesis %.3f s; ", speechSeconds);
	job.timingPrefix = prefix;
	renderVideo(job);
	return 0;
}

}  // namespace talkhead::cli
