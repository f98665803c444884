// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/ticks.h"

namespace talkhead {

// What the labels of a transcript are.
enum class LabelLevel { Phone, Word, Viseme };

// One labelled interval [start, end) of a timed transcript.
struct Interval {
	Ticks start{0}, end{0};
	std::string label;  // as written in the file (trimmed); empty = pause
	long line = 0;      // source line, for error messages (0 = unknown)
};

// The intervals (sorted by start; one that overlaps the interval before it starts where that one ends,
// one of no length is dropped) made contiguous: every gap becomes an empty interval, a pause — from
// `from` and to `to` where given. Transcripts are validated with it; alignments are written with it.
std::vector<Interval> withPauses(const std::vector<Interval>& sorted, std::optional<Ticks> from = {}, std::optional<Ticks> to = {});

// A timed transcript in the one internal representation: intervals sorted by start, non-overlapping.
struct Transcript {
	std::string path;                   // for error messages ("-" = standard input)
	std::string format;                 // transcriptFormats(): textgrid, pho, …, whisper, srt, ctm, …
	LabelLevel level = LabelLevel::Phone;
	std::string visemeScheme;           // for Viseme level: "polly" or "rhubarb"
	std::vector<Interval> intervals;
	// TextGrids: the tier read, and why ("phones", "words; also 'IVR - words': choose with {{tier}}").
	std::string tier, tierNote;
	// The level was a guess (phone level, tier labels neither clearly phones nor words): an unknown phone
	// that looks like a word then says "use {{level}} words".
	bool levelGuessed = false;
	// What the reader did that a user should know (words without times left out, spoken noise read from
	// the words tier, sentences spread over their span): one line each, for stderr.
	std::vector<std::string> warnings;
	// What the file itself says (issue 50): its language as written ("zho", "en_us", "English"; empty when
	// it names none), the duration it states (seconds), its speakers and the one read (empty: one speaker),
	// and the unit its times were written in ("s", "ms", "samples at 20000 Hz", "100 ns") — the gate's
	// messages name it.
	std::string language;
	std::optional<double> statedDuration;
	std::vector<std::string> speakers;
	std::string speaker;
	std::string unit = "s";
	// The plausibility gate's verdict (plausibility.h): what was checked and passed, one line for -v.
	std::string verdict;
};

struct ReadOptions {
	std::string format;     // empty = detect from the content
	std::string tier;       // TextGrid tier name or 1-based number (empty = the phone tier, else the word tier);
	                        // a speaker, channel or ELAN tier in files of several (--tier, --speaker)
	std::string utterance;  // HTK MLF utterance name or 1-based index (empty = the first)
	int sampleRate = 16000; // TIMIT .phn: times are sample numbers at this rate
	// Phone or Word level as the user said (--level); nullopt = decided from tier names and labels.
	std::optional<LabelLevel> level{};
	// Whether a label is a phone of the transcript's language (tier choice and level detection); without it,
	// labels of up to 3 characters count as phones.
	std::function<bool(const std::string&)> knownPhone{};
	// The text a timing file refers to but does not hold (--timing-text): aeneas SMIL and TSV sync maps (the
	// XHTML with the fragments' ids, or aeneas's parsed "id|text" or plain one-fragment-a-line text), Google
	// Text-to-Speech timepoints (the SSML with the <mark>s). A path; empty = none.
	std::string timingText{};
};

// Labels that mean no speech in any language: empty, "_", "#", sil, sp, spn (MFA's spoken noise), and
// noise tags in angle brackets or braces (<unk>, <noise>, {LG}, {NS}).
bool isPauseLabel(std::string_view label);

// The formats read, for --format and messages.
const std::vector<std::string>& transcriptFormats();

// Reads a transcript from text (UTF-8, or UTF-16 with or without a BOM). Validation (spec §5.2 and
// docs/decisions.md): rows are sorted by start; overlaps, negative or reversed times and malformed lines
// are errors naming the file and line; zero-length intervals are dropped; gaps become pauses; empty
// labels are pauses.
Transcript parseTranscript(const std::string& bytes, const std::string& path, const ReadOptions& options = {});
// From a file, or standard input when path is "-".
Transcript readTranscript(const std::string& path, const ReadOptions& options = {});

// Every tier of a Praat TextGrid (long or short text format): interval tiers' intervals, and point tiers'
// points as intervals whose start and end are the point's time. Throws Error naming the file and line.
struct TextGridTier {
	std::string name, cls;  // cls: IntervalTier or TextTier
	long line = 0;
	std::vector<Interval> intervals;
};
std::vector<TextGridTier> readTextGridTiers(const std::string& text, const std::string& path);
// The word tier of a TextGrid file beside the tier `readTier` that was read: the first other interval
// tier whose name has "word" in it ("words", "IVR - words", "ORT-Word"); empty when there is none.
std::vector<Interval> textGridWords(const std::string& path, const std::string& readTier);

// Detects the format from the content (nullopt when nothing matches).
std::optional<std::string> detectTranscriptFormat(const std::string& text);

}  // namespace talkhead
