// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Forced alignment of speech audio to its text (issue 10 §2; docs/decisions.md D30).
//
// Method: espeak-ng speaks the same text (in process) in a few voices at the input's speaking rate; the
// input and each rendition become MFCC + Δ features (25 ms / 10 ms, normalised per utterance over the
// speech frames); dynamic time warping with slope limits and free pauses matches them; the renditions'
// phone and word boundaries, known from espeak-ng's events, are carried through the warping paths and the
// median over the renditions is kept. The mean warping cost, relative to the cost of unrelated frame
// pairs, gives a confidence in [0, 1].
#include <string>
#include <vector>

#include "base/ticks.h"
#include "media/audio.h"
#include "phonetics/transcript.h"

namespace talkhead {

// Method parameters; the defaults are the measured best (docs/decisions.md D30, bench/align.sh).
struct AlignTuning {
	int renditions = 3;           // how many of the default voices (when AlignOptions::voices is empty)
	int wordGap10ms = 0;          // pause espeak-ng puts between the rendition's words (10 ms units)
	double padSeconds = 0.15;     // silence added before and after each rendition
	int maxSlope = 3;             // DTW slope limit on speech frames
	bool matchChannel = true;     // give the renditions the input's speech level and background noise
	double snapEdgesSeconds = 0.3;  // the utterance's first and last boundaries go to the voice-activity edges
	bool inputPauses = false;     // the input's silent frames (voice activity) may stretch freely
	bool deltaDeltas = false;     // MFCC + Δ (+ ΔΔ)
	bool matchRate = true;        // render at the input's speaking rate
	int rateIterations = 1;       // refinements of that rate
	double minPhoneSeconds = 0.01;
	double minPauseSeconds = 0.03;   // shorter pauses of the result go to their neighbours
	// Voice activity: peak level (99th percentile of 25 ms frames) below which audio is silent, the least
	// spread between quiet (5th percentile) and loud frames for speech, and the thresholds' places between
	// (speech above vadFraction, grown over frames above vadLowFraction).
	double silentBelowDb = -55, minRangeDb = 12, vadFraction = 0.35, vadLowFraction = 0.25;
	// Confidence: along the warping path on speech, the fraction of the rendition's speech frames closer
	// (static MFCCs) to the input frame than the frame the path matched, averaged; it maps linearly from
	// rankMatch (confidence 1) to rankMismatch (confidence 0).
	double rankMatch = 0.10, rankMismatch = 0.30;
};

struct AlignOptions {
	std::string languageTag = "pt-BR";  // a language with a viseme table: "pt-BR", "en-US" (Language::get)
	// espeak-ng voices of the reference renditions; empty = the language's voice plus two variants
	// (e.g. "en-us", "en-us+m3", "en-us+f2").
	std::vector<std::string> voices;
	// Below this confidence alignSpeech throws "the text does not match the audio"; below doubtfulBelow it
	// adds a warning. Set mismatchBelow to 0 to always get an alignment.
	double mismatchBelow = 0.15;
	double doubtfulBelow = 0.4;
	AlignTuning tuning;
};

// A word of the alignment with its own confidence.
struct AlignedWord {
	Ticks start{0}, end{0};
	std::string text;
	double confidence = 0;
};

struct Alignment {
	// Both cover [0, the audio's duration) without gaps: pauses are intervals with empty labels.
	Transcript words;   // level Word: the text's words as written
	Transcript phones;  // level Phone: canonical IPA of the language's inventory (phonetics/<tag>/)
	std::vector<AlignedWord> wordList;  // the spoken words only, in order, with their confidences
	double confidence = 0;              // 0 (the text does not fit the audio) … 1 (a close match)
	Ticks speechStart{0}, speechEnd{0};  // where the voice-activity measure found speech
	int renditions = 0;                  // reference renditions the result is the median of
	std::vector<std::string> warnings;   // e.g. a doubtful match; for the caller to print
};

// Aligns `text` with the speech in `audio` (any sample rate and channel count; channels are averaged).
// Throws Error for empty text, text with nothing to say, audio without speech (silence or steady noise:
// "no speech in the audio …"), and text that does not match the audio ("the text does not match the
// audio (confidence 0.12)") unless options.mismatchBelow is 0.
Alignment alignSpeech(const AudioClip& audio, const std::string& text, const AlignOptions& options = {});

// The words of `text` as espeak-ng speaks them at `rate` words per minute in the language's first voice:
// each as the text writes it, with its start and end from the first word's start (a streamed speak
// estimates from them how many words the audio so far holds, perform/stream.h).
struct RenderedWord {
	std::string text;
	Ticks start{0}, end{0};
};
std::vector<RenderedWord> renderedWords(const std::string& text, const AlignOptions& options = {}, int rate = 175);

// Voice activity over 10-ms frames of `levels` (align::frameLevels: dBFS of 25-ms windows): which frames
// are speech, and the first and last. Throws Error "no speech in the audio: …" for silence, a steady sound
// and audio shorter than one frame.
struct VoiceActivity {
	std::vector<bool> speech;
	int first = -1, last = -1;
};
VoiceActivity detectVoiceActivity(const std::vector<float>& levels, const AlignTuning& tuning = {});

// Sentence-level cues (subtitles, aeneas fragments, utterance tiers: word-level intervals of several words)
// aligned each to its own stretch of `audio` (issue 29): a phone-level transcript in canonical IPA over
// the cues' span, pauses where the cues are silent or empty. Errors name `audioName` and the cue's line.
Transcript alignCues(const Transcript& cues, const AudioClip& audio, const std::string& languageTag, const std::string& audioName);

// Decodes a file (audio, or the audio track of a video: decodeAudio at 16 kHz) and aligns it; errors name
// the file.
Alignment alignSpeechFile(const std::string& path, const std::string& text, const AlignOptions& options = {});

// The alignment as a Praat TextGrid (long text format) with interval tiers "words" and "phones" over
// [0, duration]; `talkhead render --transcript` reads its "phones" tier.
std::string alignmentTextGrid(const Alignment& alignment, Ticks duration);

// One line for a command's summary: "12 words, 41 phones, speech 0.49–2.21 s, confidence 0.83 (lowest:
// 'soon' 0.61)".
std::string alignmentSummary(const Alignment& alignment);

}  // namespace talkhead
