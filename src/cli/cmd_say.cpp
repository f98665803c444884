// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead say: text → speech (libespeak-ng) and talking-head video, in one process.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <iterator>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/video_options.h"
#include "media/audio.h"
#include "phonetics/espeak.h"
#include "phonetics/writers.h"

namespace talkhead::cli {

int runSay(const std::vector<std::string>& argv) {
	std::vector<OptionSpec> options = {
	    {"--text-file", "F", "read the text from a file"},
	    {"--lang", "LANG", "pt-BR (default) or en-US (the languages with a viseme table)"},
	    {"--voice", "NAME", "espeak-ng voice (default: the language, e.g. pt-br; mb-br1 etc. need MBROLA)"},
	    {"--rate", "WPM", "speaking rate in words per minute (80–450; default 175)"},
	    {"--pitch", "N", "pitch 0–100 (default 50)"},
	    {"--save-audio", "F.wav", "also write the synthesised speech"},
	    {"--save-transcript", "F.TextGrid", "also write the phone timeline (re-render it with 'talkhead render')"},
	    {"--dry-run", "", "print the viseme timeline (TSV) and render nothing"}};
	for (auto& o : videoOptionSpecs()) options.push_back(o);
	Args args("say", "talkhead say \"TEXT\"|- [--lang pt-BR] [--emotion joy] -o out.mp4 [options]", options,
	          "Speaks the text with libespeak-ng (in process: PCM and phoneme timings in one pass), maps the phones\n"
	          "to context-dependent visemes and renders the talking head with the speech as its audio track.");
	if (!args.parse(argv)) return 0;
	const auto t0 = std::chrono::steady_clock::now();
	// Every option is checked before the text is read or any speech is synthesised.
	if (args.get("--text-file") && !args.positionals().empty()) throw UsageError("say: give the text or --text-file, not both");
	const bool dryRun = args.has("--dry-run");
	if (!args.get("--output") && !dryRun) throw UsageError("say: -o OUT is required (or --dry-run)");
	const VideoCommand cmd = parseVideoCommand(args, "say", !dryRun);
	const Language& lang = Language::get(args.get("--lang", "pt-BR"));
	const int rate = int(args.number("--rate", 0, 80, 450));
	const int pitch = int(args.number("--pitch", -1, 0, 100));
	const std::string voice = args.get("--voice", espeakVoiceFor(lang.tag()));
	const auto saveAudio = args.get("--save-audio"), saveTranscript = args.get("--save-transcript");

	std::string text;
	if (auto f = args.get("--text-file")) {
		text = readTextFile(*f);
	} else if (args.positionals().size() == 1 && args.positionals()[0] == "-") {
		text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
	} else {
		for (const auto& p : args.positionals()) text += (text.empty() ? "" : " ") + p;
	}
	const auto tSpeech = std::chrono::steady_clock::now();
	Speech speech = espeakSpeak(text, voice, rate, pitch);
	const double speechSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tSpeech).count();
	// espeak-ng's phoneme names are IPA; any it has that the tables lack take the nearest known phone.
	const std::vector<PhoneSegment> phones = phoneSegments(speech.phones, lang, UnknownPhone::Nearest);
	Performance perf;
	perf.rate = cmd.rate;
	perf.emotion = cmd.emotion;
	perf.keys = keyposes(phones, cmd.rate.frameLength(), cmd.pauses);
	if (dryRun) {
		std::cout << formatVisemes(phones, perf.keys, "tsv", lang.tag(), "espeak-ng");
		return 0;
	}
	AudioClip audio;
	audio.sampleRate = speech.sampleRate;
	audio.channels = 1;
	audio.samples.reserve(speech.pcm.size());
	for (short v : speech.pcm) audio.samples.push_back(float(v) / 32768.f);
	if (saveAudio) writeWav(*saveAudio, audio);
	if (saveTranscript) writeFileAtomically(*saveTranscript, formatVisemes(phones, perf.keys, "textgrid", lang.tag(), "espeak-ng"));
	perf.duration = audio.duration();
	char prefix[64];
	std::snprintf(prefix, sizeof prefix, "speech synthesis %.3f s; ", speechSeconds);
	runVideoCommand(cmd, perf, clipSource(audio), t0, prefix);
	return 0;
}

}  // namespace talkhead::cli
