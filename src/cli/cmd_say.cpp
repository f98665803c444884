// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead say: text → speech (libespeak-ng) and talking-head video, in one process.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <map>
#include <optional>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/video_options.h"
#include "media/audio.h"
#include "perform/plan.h"
#include "perform/utterance.h"
#include "phonetics/espeak.h"
#include "phonetics/labels.h"
#include "phonetics/ssml.h"
#include "phonetics/writers.h"

namespace talkhead::cli {

namespace {

std::string primaryLanguage(const std::string& tag) { return toLower(tag.substr(0, tag.find('-'))); }

// The voice must speak --lang's language (item 11): `--voice fr` with the default pt-BR table would give
// French speech Portuguese visemes. Regions may differ (pt voice, pt-BR table). A voice espeak-ng does not
// have is left to espeakSpeak's error.
void checkVoiceSpeaks(const std::string& voice, const Language& lang) {
	const auto v = espeakVoiceLanguage(voice);
	if (!v || primaryLanguage(v->language) == primaryLanguage(lang.tag())) return;
	static const std::map<std::string, std::string> names = {{"pt", "Portuguese"}, {"en", "English"}, {"es", "Spanish"}, {"fr", "French"},
	                                                         {"de", "German"},     {"it", "Italian"}, {"nl", "Dutch"}};
	const std::string primary = primaryLanguage(v->language);
	const auto n = names.find(primary);
	const std::string name = n != names.end() ? n->second : !v->name.empty() ? v->name : v->language;
	std::string table;
	for (const auto& a : Language::available())
		if (toLower(a) == v->language) table = a;
	for (const auto& a : Language::available())
		if (table.empty() && primaryLanguage(a) == primary) table = a;
	throw UsageError("say: voice '" + voice + "' speaks " + name + " (" + v->language + ") but --lang is " + lang.tag() + "; add --lang " +
	                 (table.empty() ? primary + " --generic-visemes" : table));
}

// One line naming the espeak-ng phoneme names the table lacks (they take the nearest known phone).
void warnUnknownPhones(const Transcript& phones, const Language& lang) {
	std::vector<std::string> unknown;
	for (const auto& iv : phones.intervals)
		if (!iv.label.empty() && !lang.normalize(iv.label) && std::find(unknown.begin(), unknown.end(), iv.label) == unknown.end())
			unknown.push_back(iv.label);
	if (unknown.empty()) return;
	std::string list;
	for (const auto& u : unknown) {
		const auto near = lang.nearest(u);
		std::string to;
		if (near)
			for (const auto& p : *near) to += (to.empty() ? "" : " ") + p;
		list += (list.empty() ? "" : ", ") + u + " -> " + (near ? to : "silence");
	}
	std::fprintf(stderr, "talkhead: warning: espeak-ng phones unknown to the %s table, substituted: %s\n", lang.tag().c_str(), list.c_str());
}

}  // namespace

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
	if (!args.get("--output") && !dryRun) throw UsageError("say: -o OUT is required (or --dry-run)");
	const VideoCommand cmd = parseVideoCommand(args, "say", !dryRun);
	const Language& lang = languageOption(args);
	const int rate = int(args.number("--rate", 0, 80, 450));
	const int pitch = int(args.number("--pitch", -1, 0, 100));
	const std::string voice = args.get("--voice", espeakVoiceFor(lang.tag()));
	if (args.get("--voice")) checkVoiceSpeaks(voice, lang);
	const auto saveAudio = args.get("--save-audio"), saveTranscript = args.get("--save-transcript");
	if (saveAudio) checkWritableFolder(*saveAudio);
	if (saveTranscript) checkWritableFolder(*saveTranscript);

	std::string text;
	if (auto f = args.get("--text-file")) {
		text = readTextFile(*f);
	} else if (args.positionals().size() == 1 && args.positionals()[0] == "-") {
		text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
	} else {
		for (const auto& p : args.positionals()) text += (text.empty() ? "" : " ") + p;
	}
	// SSML (D45): breaks, marks, blinks and emotions placed at the words where they occur.
	std::optional<SsmlText> ssml;
	const std::string textName = args.get("--text-file", "text");
	if (looksLikeSsml(text)) {
		ssml = parseSsml(text, textName);
		for (const auto& e : ssml->events)  // checked before any speech is synthesised
			if (e.kind == SsmlText::Event::Kind::EmotionStart && !canonicalEmotion(e.name))
				throw Error(textName, e.line, "column " + std::to_string(e.column) + ": unknown emotion '" + e.name + "'");
	}
	std::vector<Ticks> eventTimes;
	const auto tSpeech = std::chrono::steady_clock::now();
	Speech speech = ssml ? espeakSpeakSsml(*ssml, voice, eventTimes, rate, pitch) : espeakSpeak(text, voice, rate, pitch);
	for (const auto& w : speech.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", safeLine(w).c_str());
	const double speechSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tSpeech).count();
	// espeak-ng's phoneme names are IPA; any it has that the tables lack take the nearest known phone (said
	// once on stderr: the tables are meant to know every name their voice uses).
	warnUnknownPhones(speech.phones, lang);
	const TimedSpeech timed = speechFromEspeak(speech, lang);
	const std::vector<PhoneSegment>& phones = timed.phones;
	if (dryRun) {
		std::cout << formatVisemes(phones, keyposes(phones, cmd.rate.frameLength(), cmd.pauses), "tsv", lang.tag(), "espeak-ng");
		return 0;
	}
	AudioClip audio;
	audio.sampleRate = speech.sampleRate;
	audio.channels = 1;
	audio.samples.reserve(speech.pcm.size());
	for (short v : speech.pcm) audio.samples.push_back(float(v) / 32768.f);
	PerformanceSpec spec = performanceSpec(cmd);
	spec.phones = phones;
	spec.duration = audio.duration();
	if (ssml) {  // D45: marks reported, blinks, brows and emotions as a control track
		SpeechEvents events = ssmlEvents(*ssml, eventTimes, *spec.duration, cmd.emotion, cmd.intensity);
		for (const auto& m : events.marks) {
			if (cmd.jsonProgress) std::fprintf(stderr, "{\"type\": \"mark\", \"name\": %s, \"time\": %.3f}\n", jsonQuote(m.name).c_str(), toSeconds(m.time));
			else if (!cmd.quiet) std::fprintf(stderr, "talkhead: mark %s at %.3f s\n", jsonQuote(m.name).c_str(), toSeconds(m.time));
		}
		ControlTrack track;
		track.path = textName;
		track.blinks = std::move(events.blinks);
		track.brows = std::move(events.brows);
		track.emotions = std::move(events.emotions);
		spec.controls.push_back(std::move(track));
	}
	if (cmd.controls) spec.controls.push_back(*cmd.controls);
	Performance perf = planPerformance(spec);
	char prefix[64];
	std::snprintf(prefix, sizeof prefix, "speech synthesis %.3f s; ", speechSeconds);
	const std::vector<Keypose> keys = perf.keys;  // the speech's own times, for --save-transcript
	auto sound = applyStimulusTiming(cmd, perf, clipSource(audio));
	// The speech, its timeline and the sidecar appear only with the video (a failed render leaves none).
	std::vector<SideOutput> side = timelineOutput(cmd, perf, phones, speech.words.intervals);
	if (saveAudio) side.push_back({*saveAudio, [&audio](const std::string& p) { writeWav(p, audio); }});
	if (saveTranscript) {
		std::string tg = formatVisemes(phones, keys, "textgrid", lang.tag(), "espeak-ng");
		side.push_back({*saveTranscript, [tg](const std::string& p) { writeFileAtomically(p, tg); }});
	}
	runVideoCommand(cmd, perf, std::move(sound), t0, prefix, std::move(side));
	return 0;
}

}  // namespace talkhead::cli
