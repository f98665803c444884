// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "base/ticks.h"
#include "perform/utterance.h"
#include "phonetics/language.h"

namespace talkhead {

// Speech whose audio comes in pieces (issue 49 part 2: a TTS that streams PCM): what has arrived becomes
// parts of one utterance as soon as its timing is known, so that the face starts moving before the whole
// audio is there. With the text (given with the first piece), its words are aligned as their audio comes:
// espeak-ng's word durations at the speaker's pace (measured on what was given) say how many words have
// begun; those and one more are aligned with what has arrived as `render --audio A --text T` aligns
// (alignSpeech), and the words that end at least `margin` before its end — all but that last one — are given
// out; the rest waits for more audio. Without text, the phones are
// recognised (align/recognize.h), an utterance at a time, the first of at most `firstRecognized` seconds.
// Parts cut the audio at word ends or pauses, never inside a phone, and together are the audio exactly.
// Recognition gives the same parts for the same pieces; alignment as alignSpeech does (libespeak-ng's
// renditions depend on what it synthesised before in the process, D91).
struct SpeechStreamOptions {
	double margin = 0.25;          // s: a word ending this near the end of what has arrived may go on: it waits
	double lead = 0.6;             // s: the first parts are held until they hold this much (a buffer against gaps)
	double step = 0.2;             // s: the words are looked for again when this much more audio has come
	double firstLook = 0.4;        // s: …and first when this much has come
	// Words are given out when the alignment and its words so far are at least this sure (Alignment and
	// AlignedWord confidence): settled alignments of GRID's clips 0.55–0.62; a text that is not the audio
	// 0.35–0.55 (D97).
	double sure = 0.45;
	double keepAligned = 4;        // s: what was given is aligned again with what comes, up to this far back
	double firstRecognized = 0.6;  // s: audio alone, the first utterance recognised at most this long
	double recognizeEvery = 2.0;   // s: audio alone, streamed: recognised when this much more has come
};

class SpeechStream {
public:
	// `id` goes on every part; `text` is what the whole audio says ("": recognise it); the pieces come at
	// `inputRate` (mono), the parts are at `sampleRate`.
	SpeechStream(std::string id, std::string text, const Language& language, int inputRate, int sampleRate, SpeechStreamOptions options = {});

	using Emit = std::function<void(Utterance part)>;
	// The next piece (mono samples at inputRate in [−1, 1]); `last`: none comes after it. `emit` gets each
	// part ready, in order (the first opens the utterance, the last closes it; after `last`, a part always
	// closes it). Throws Error when the text does not match the audio (the stream is then closed: the caller
	// ends it), SpeechCancelled when `cancel` is set.
	// `look` false: the piece is only kept (the caller knows another is already waiting), unless it is the last.
	void feed(const std::vector<float>& piece, bool last, const Emit& emit, const std::atomic<bool>* cancel = nullptr, bool look = true);

	bool closed() const { return closed_; }
	bool opened() const { return flowing_; }  // a part was given out
	const std::string& id() const { return id_; }
	int inputRate() const { return inputRate_; }
	Ticks received() const;  // the audio so far

private:
	std::string id_, text_;  // text_: what is said from origin_ on
	const Language& language_;
	int inputRate_, sampleRate_;
	SpeechStreamOptions o_;
	bool recognizing_;          // no text: the phones are recognised
	std::vector<float> audio_;  // everything received, at inputRate
	Ticks given_{0};            // the parts so far cover [0, given_)
	std::size_t lastLook_ = 0;  // samples received when the words were last looked for
	int parts_ = 0;
	std::vector<Utterance> held_;  // parts made, not yet given out (the lead)
	bool flowing_ = false;         // the lead was reached: parts go out as they are made
	bool complete_ = false;        // the last piece has come: parts go out as they are made
	Ticks origin_{0};           // where the alignments begin (a word's end given out; 0 at first)
	std::size_t givenWords_ = 0;  // words of text_ given out
	double pace_ = 1;           // espeak-ng's speech seconds per second of the speaker's (measured on the parts given)
	bool closed_ = false;

	// A part [given_, end) with its phones (from 0 of the part) given out; `closes` on the last.
	void give(Ticks end, std::vector<PhoneSegment> phones, std::vector<std::string> warnings, bool closes, const Emit& emit);
	AudioClip inputSpan(Ticks from, Ticks to) const;  // at the input rate
	void alignWords(bool last, const Emit& emit);
	void recognize(bool last, const Emit& emit, const std::atomic<bool>* cancel);
};

}  // namespace talkhead
