// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <functional>
#include <optional>
#include <string>

#include "perform/plan.h"
#include "phonetics/transcript.h"

namespace talkhead {

// The speech half of a job (issue 46): where a performance's phones and sound come from. Each front end
// fills one — the CLI's render and say from their flags, a batch row from its columns, Python from its
// keywords, a program linking the library by hand — and loadSpeech reads it, the one place that decides
// how each kind of source becomes timed phones.
struct SpeechSource {
	enum class Kind {
		None,         // no speech: the keyposes come from elsewhere (a driven mouth, D55)
		Transcript,   // a timed transcript in any format talkhead reads, with `audio` when there is a sound
		AlignedText,  // `text` is what `audio` says: forced alignment (align/align.h)
		SpokenText,   // `text` (plain or SSML) spoken by espeak-ng in one pass: its phones and its sound
		RecognizedAudio,  // no timing and no text: `audio`'s phones recognised from the sound (align/recognize.h)
	};
	Kind kind = Kind::None;
	std::string transcript;               // Transcript: its path ("-": standard input)
	std::string text;                     // AlignedText, SpokenText
	std::string textName = "text";        // the text in messages (its file's path when it came from one)
	std::optional<std::string> audio;     // the sound's path: optional for Transcript and None, required for AlignedText and RecognizedAudio
	// AlignedText: the text is a hint (Rhubarb's dialog): when it does not match the audio, the phones are
	// recognised from the audio instead, with a warning, rather than an error.
	bool textIsHint = false;
	// Transcript: how it is read.
	ReadOptions read;
	UnknownPhone unknown = UnknownPhone::Error;
	Notation notation = Notation::Auto;
	bool wantWords = false;  // a TextGrid's word tier too (for a timeline sidecar)
	// SpokenText: espeak-ng's voice (empty: the language's), words per minute and pitch (0 / −1: the voice's).
	std::string voice;
	int rateWpm = 0, pitch = -1;
};

// The source's speech in `language`: its phones with their CDVs, its words when known, and its sound when
// reading needed it (an alignment) or made it (espeak-ng; then `ssml` and `eventTimes` too). A Transcript's
// `onRead` sees the transcript as read, before any alignment. Kind::None gives no phones. Throws FieldError
// naming the field a source lacks (`audio` for AlignedText, `text`, `transcript`), Error for what the
// files hold.
TimedSpeech loadSpeech(const SpeechSource& source, const Language& language, const std::function<void(const Transcript&)>& onRead = {});

}  // namespace talkhead
