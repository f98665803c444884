// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead say: text → speech (libespeak-ng) and talking-head video, in one process.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <iterator>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/run.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/video_options.h"
#include "media/audio.h"
#include "perform/plan.h"
#include "perform/speech_source.h"
#include "perform/utterance.h"
#include "phonetics/espeak.h"
#include "phonetics/writers.h"

namespace talkhead::cli {

int runSay(const std::vector<std::string>& argv) {
	std::vector<OptionSpec> options = {
	    {"--text-file", "F", "read the text from a file"},
	    {"--lang", "LANG", languageOptionHelp("the text's language")},
	    {"--voice", "NAME", "espeak-ng voice (default: the language's, e.g. pt-br, fr; it must speak --lang; mb-br1 etc. need MBROLA)"},
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
	if (!args.get("--output") && !dryRun && args.get("--format", "") != "none") throw UsageError("say: -o OUT is required (or --dry-run)");
	const VideoCommand cmd = parseVideoCommand(args, "say", !dryRun);
	const Language& lang = languageOption(args);
	const int rate = int(args.number("--rate", 0, 80, 450));
	const int pitch = int(args.number("--pitch", -1, 0, 100));
	const std::string voice = args.get("--voice", espeakVoiceFor(lang.tag()));
	if (args.get("--voice"))
		if (const std::string why = voiceLanguageMismatch(voice, lang); !why.empty()) throw UsageError("say: " + why);
	const auto saveAudio = args.get("--save-audio"), saveTranscript = args.get("--save-transcript");
	if (saveAudio) checkWritableFolder(*saveAudio);
	if (saveTranscript) checkWritableFolder(*saveTranscript);

	SpeechSource source;
	source.kind = SpeechSource::Kind::SpokenText;
	if (auto f = args.get("--text-file")) source.text = readTextFile(*f);
	else if (args.positionals().size() == 1 && args.positionals()[0] == "-") source.text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
	else
		for (const auto& p : args.positionals()) source.text += (source.text.empty() ? "" : " ") + p;
	// SSML (D45): breaks, marks, blinks and emotions placed at the words where they occur.
	source.textName = args.get("--text-file", "text");
	source.voice = voice, source.rateWpm = rate, source.pitch = pitch;
	const std::string& textName = source.textName;
	const auto tSpeech = std::chrono::steady_clock::now();
	const TimedSpeech timed = loadSpeech(source, lang);
	const double speechSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tSpeech).count();
	for (const auto& w : timed.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", shownLine(w).c_str());
	const std::vector<PhoneSegment>& phones = timed.phones;
	if (dryRun) {
		std::cout << formatVisemes(phones, keyposes(phones, cmd.rate.frameLength(), cmd.pauses), "tsv", lang.tag(), "espeak-ng");
		return 0;
	}
	const AudioClip& audio = timed.audio;
	const VideoFace face = loadVideoFace(cmd);
	PerformanceSpec spec = performanceSpec(cmd, face);
	spec.phones = phones;
	spec.duration = audio.duration();
	if (timed.ssml) {  // marks reported; blinks, brows and emotions performed
		SpeechEvents events = ssmlEvents(*timed.ssml, timed.eventTimes, *spec.duration, cmd.expression);
		reportMarks(cmd, events.marks);
		spec.controls.push_back(controlTrackOf(std::move(events), textName));
	}
	if (cmd.controls) spec.controls.push_back(*cmd.controls);
	Performance perf = planPerformance(spec);
	char prefix[64];
	std::snprintf(prefix, sizeof prefix, "speech synthesis %.3f s; ", speechSeconds);
	const std::vector<Keypose> keys = perf.timeline.keys;  // the speech's own times, for --save-transcript
	auto sound = applyStimulusTiming(cmd, perf, clipSource(audio));
	// The speech, its timeline and the sidecar appear only with the video (a failed render leaves none).
	std::vector<SideOutput> side = timelineOutput(cmd, perf, phones, timed.words);
	if (saveAudio) side.push_back({*saveAudio, [&audio](const std::string& p) { writeWav(p, audio); }});
	if (saveTranscript) {
		std::string tg = formatVisemes(phones, keys, "textgrid", lang.tag(), "espeak-ng");
		side.push_back({*saveTranscript, [tg](const std::string& p) { writeFileAtomically(p, tg); }});
	}
	runVideoCommand(cmd, face, perf, std::move(sound), t0, prefix, std::move(side));
	return 0;
}

}  // namespace talkhead::cli
