// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead visemes TRANSCRIPT | --audio A
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <unistd.h>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/frame_rate.h"
#include "base/text.h"
#include "cli/run.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/video_options.h"
#include "phonetics/language.h"
#include "perform/plan.h"
#include "phonetics/writers.h"

namespace talkhead::cli {

namespace {

// Writes text to PATH through a temporary name (or to stdout for "-").
void writeOutput(const std::string& path, const std::string& text) {
	if (path == "-") {
		std::cout << text;
		std::cout.flush();
		return;
	}
	writeFileAtomically(path, text);
}

}  // namespace

int runVisemes(const std::vector<std::string>& argv) {
	Args args("visemes", "talkhead visemes (TRANSCRIPT|- | --audio A) [options]",
	          {{"--lang", "LANG", languageOptionHelp("language of the phones")},
	           {"--audio", "FILE", "no transcript: recognise the phones of this speech (any format libav reads) with PocketSphinx's en-US phone recogniser; the output gets a confidence column"},
	           genericVisemesOption(),
	           {"--format", "FORMAT", "input format (default: detected): " + joined(transcriptFormats())},
	           {"--tier", "NAME|N", "TextGrid tier, by name or 1-based number (default: the phone tier — named like phones, or labels that are phones —, else the word tier); in files of several speakers, channels or ELAN tiers: the one to read"},
	           {"--speaker", "NAME", "the speaker (channel, voice, ELAN tier) to read from a file of several (the same as --tier)"},
	           {"--verbose", "", "also say which format was read and what the plausibility gate checked (units, rates, duration)", "-v"},
	           {"--timing-text", "FILE", "the text a timing file refers to but does not hold: for an aeneas SMIL or TSV sync map, the XHTML or aeneas's parsed (id|text) or plain (a fragment a line) text; for Google Text-to-Speech timepoints, the SSML with the <mark>s"},
	           {"--level", "LEVEL", "what the labels are: auto (default: from tier names and labels), phones, or words (phonemised with espeak-ng)"},
	           {"--sample-rate", "HZ", "TIMIT .phn: the sample rate its times count in (default 16000)"},
	           {"--utterance", "NAME|N", "HTK MLF utterance (name or 1-based index; default the first)"},
	           {"--unknown", "POLICY", "unknown phones: error (default), nearest (the closest known spelling, else an error), silence"},
	           {"--notation", "NAME", "how phones are spelled: auto (default: decided from the labels), ipa, arpabet, sampa (= xsampa), espeak, praat, br1 (MBROLA pt-BR)"},
	           {"--fps", "N", "output frame rate for keypose spacing (default 30)"},
	           {"--pauses", "STYLE", "pauses: natural (default: rest soon after speech, a breath before it), still (rest held; a slow in-breath where the pause allows) or thesis (one silence keypose at each pause midpoint)"},
	           {"--out-format", "FORMAT", "tsv (default), json, textgrid, rhubarb-tsv, rhubarb-json"},
	           {"--output", "OUT", "write here instead of standard output", "-o"}},
	          "Maps a timed transcript to context-dependent visemes (Costa 2015) and keyposes: one row per phone\n"
	          "with start, end, phone (IPA), CDV and keypose time. Word-level input (GRID .align, word speech\n"
	          "marks, TextGrid word or utterance tiers) is phonemised with espeak-ng; viseme-level input (Polly\n"
	          "visemes, Rhubarb cues) maps directly.");
	if (!args.parse(argv)) return 0;
	const auto audio = args.get("--audio");
	if (audio && !args.positionals().empty()) throw UsageError("visemes: give a TRANSCRIPT or --audio, not both");
	if (!audio) args.onePositional("expected one TRANSCRIPT argument (or - for standard input), or --audio A");
	TranscriptOptions to = parseTranscriptOptions(args, "visemes", "--format");
	ReadOptions& ro = to.read;
	const std::string outFormat = args.get("--out-format", "tsv");
	const auto& of = visemeOutputFormats();
	if (std::find(of.begin(), of.end(), outFormat) == of.end())
		throw UsageError("visemes: unknown --out-format '" + outFormat + "' (" + joined(of) + ")");
	const auto rate = FrameRate::parse(args.get("--fps", "30"));
	if (!rate) throw UsageError("visemes: --fps must be 1–240, e.g. 30, 29.97, 12.5 or 30000/1001");
	const auto pauses = parsePauseStyle(args.get("--pauses", "natural"));
	if (!pauses) throw UsageError("visemes: --pauses takes natural, still or thesis");
	const Notation notation = to.notation;
	if (audio) {
		// Recognised phones (perform's speechFromAudio: the same as render's), each with its confidence.
		const Language& lang = languageOption(args, "en-US");
		const TimedSpeech speech = speechFromAudio(*audio, lang);
		for (const std::string& w : speech.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", shownLine(w).c_str());
		for (const std::string& n : speech.notes) std::fprintf(stderr, "talkhead: %s: %s\n", audio->c_str(), n.c_str());
		std::vector<double> confidence;
		for (const PhoneSegment& p : speech.phones) confidence.push_back(speech.confidenceAt(p.start + (p.end - p.start) / 2));
		const std::vector<Keypose> keys = keyposes(speech.phones, rate->frameLength(), *pauses);
		writeOutput(args.get("--output", "-"), formatVisemes(speech.phones, keys, outFormat, lang.tag(), *audio, "ipa", &confidence));
		return 0;
	}
	const Language& lang = transcriptLanguage(args, args.positionals()[0], ro.format);
	ro.knownPhone = [&lang](const std::string& label) { return lang.normalize(label).has_value(); };

	const std::string path = args.positionals()[0];
	Transcript tr = readTranscript(path, ro);
	if (args.has("--verbose")) std::fprintf(stderr, "talkhead: %s: %s (%s)\n", path.c_str(), shownLine(tr.verdict).c_str(), tr.format.c_str());
	for (const std::string& w : tr.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", shownLine(path + ": " + w).c_str());
	noteWordLanguage(args, tr, lang, path);
	// The notation is decided once, here, so the evidence for it can be printed.
	std::string evidence;
	Notation used = notation;
	if (used == Notation::Auto && tr.level == LabelLevel::Phone) used = detectNotation(tr, lang, &evidence);
	std::vector<PhoneSegment> phones = phoneSegments(tr, lang, to.unknown, used, &used);
	std::vector<Keypose> keys = keyposes(phones, rate->frameLength(), *pauses);
	// Which TextGrid tier was read, and which notation the phones were read in (stderr, so the TSV stays
	// clean; JSON also carries the notation).
	if (!tr.tier.empty()) std::fprintf(stderr, "%s\n", shownLine("talkhead: " + path + ": tier '" + tr.tier + "' (" + tr.tierNote + ")").c_str());
	if (tr.level == LabelLevel::Phone && used != Notation::Auto) {
		std::fprintf(stderr, "talkhead: %s: phones read as %s%s\n", path.c_str(), notationName(used).c_str(),
		             notation != Notation::Auto ? " (--notation)" : evidence.empty() ? " (detected)" : (" (detected from " + evidence + ")").c_str());
	}
	writeOutput(args.get("--output", "-"), formatVisemes(phones, keys, outFormat, lang.tag(), path, tr.level == LabelLevel::Phone ? notationName(used) : ""));
	return 0;
}

}  // namespace talkhead::cli
