// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Speech recognised from audio alone (issue 49; docs/decisions.md D95): timed phones for a voice that came
// with no timings and no text — what most neural TTS engines return, and a recorded voice-over.
//
// Method: the audio's voice activity (align.h) splits it into utterances at pauses; CMU PocketSphinx's
// phone-loop decoder (en-US acoustic model, phone trigram language model; the pocketsphinx plugin, loaded
// on first use) turns each into ARPAbet phones; those become the en-US table's phones. The audio is read
// twice as a stream (levels, then the utterances one at a time), so memory does not grow with its length.
// Each phone's confidence is its utterance's: how speech-like the rate of phones recognised in it is, and
// how much its spectrum changes.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "base/ticks.h"
#include "media/audio.h"
#include "phonetics/transcript.h"

namespace talkhead {

struct RecognizeOptions {
	// PocketSphinx's model folder (en-us/ and en-us-phone.lm.bin); empty = $TALKHEAD_SPHINX_MODEL, else
	// Debian's /usr/share/pocketsphinx/model/en-us.
	std::string modelDir;
	// PocketSphinx's beams: 1e-10 decodes GRID's 11 clips 6× faster than Rhubarb's 1e-20 and keeps 89 % of
	// its phones (D95).
	double beam = 1e-10, phoneBeam = 1e-10, languageWeight = 2.0;
	int threads = 0;                      // decoders run at once (0: up to 2, as the machine has cores)
	double longestUtteranceSeconds = 30;  // longer speech is cut at its quietest frame
	// Live (a server's speak): the first utterance at most this long (> 0), each next one at most twice the
	// one before, up to longestUtteranceSeconds — so that the first phones of a long speech come quickly.
	double firstUtteranceSeconds = 0;
	// Called in order as soon as an utterance and those before it are decoded (on a decoder's thread): its
	// phones (canonical en-US IPA, absolute times, no pauses; none when it is not speech), their confidence,
	// and where the utterance ends — what comes later lies after it. Returning false stops the recognition
	// (it then throws Error "…: stopped").
	std::function<bool(Ticks upTo, const std::vector<Interval>& phones, const std::vector<double>& confidence)> progress;
	double paddingSeconds = 0.2;          // audio kept before and after each stretch of speech
	double joinPausesSeconds = 0.5;       // stretches of speech closer than this are one utterance
	// Confidence. PocketSphinx's phone loop gives no posterior (every phone scores 1), and its acoustic
	// scores relative to each frame's best are *closer* to the best on noise and music than on speech, so
	// they say nothing; what does is the phone rate. Speech gives 8–16 phones per second of voice activity;
	// music and noise 0.2–2 (D95). An utterance's confidence maps its rate linearly from `unsureRate` (0) to
	// `sureRate` (1); the recognition is doubtful (a warning) when the mean over the speech falls below
	// `doubtfulBelow`.
	double unsureRate = 2.5, sureRate = 7.0, doubtfulBelow = 0.5;
	// …and how much its spectrum changes (median |Δ cepstrum| over its voice frames: speech 1.27–2.36, a
	// melody 0.88, noise bursts 0.69; D95) from `steadyChange` (0) to `speechChange` (1). The lower of the two
	// is the utterance's confidence; an utterance whose spectrum changes less than `dropBelow` says is not speech:
	// its phones are left out (the rate alone never drops one: French read by the en-US model is slow).
	double steadyChange = 0.95, speechChange = 1.2, dropBelow = 0.25;
};

struct Recognition {
	Transcript phones;                // level Phone, canonical IPA of en-US; pauses are empty labels; covers [0, duration)
	std::vector<double> confidence;   // per interval of `phones` (1 for pauses)
	double meanConfidence = 0;        // over the speech's phones, weighted by their length
	Ticks duration{0};
	Ticks speechSeconds{0};           // how much of it the voice activity called speech
	int utterances = 0;
	std::vector<std::string> warnings;  // silence, doubtful recognition: one line each
};

// Recognises the phones of the audio that `open` gives (called twice: each call must give a new source
// over the same audio, at any sample rate and channel count). `name` names it in errors. Silence gives
// one pause and a warning; audio shorter than 25 ms, and a source that reads nothing, are Errors.
Recognition recognizePhones(const std::function<std::unique_ptr<AudioSource>()>& open, const std::string& name, const RecognizeOptions& options = {});
// The same over a file (decoded by libav, streamed) or a clip in memory.
Recognition recognizePhonesFile(const std::string& path, const RecognizeOptions& options = {});
Recognition recognizePhonesClip(const AudioClip& clip, const std::string& name, const RecognizeOptions& options = {});

// Loads the plugin and opens the decoders now (~1 s), so that the first recognition does not wait for them
// (a server calls it as it starts). Throws Error as recognition would (no plugin, no model).
void warmRecognizer(const RecognizeOptions& options = {});

// One line for a command's summary: "recognised (no timing given): 41 phones, speech 0.49–2.21 s, mean
// confidence 0.71".
std::string recognitionSummary(const Recognition& recognition);

}  // namespace talkhead
