// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <atomic>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "base/error.h"
#include "phonetics/ssml.h"
#include "phonetics/transcript.h"

namespace talkhead {

// A phoneme espeak-ng speaks for a text, with its duration.
struct SpokenPhone {
	std::string ipa;
	Ticks duration{0};
};

// Bounds on one synthesis (a server's say requests, issue 28): speech longer than maxSeconds (the SSML breaks
// included) stops with an Error saying so, SSML breaks adding up to more than maxBreakSeconds are refused
// before anything is spoken, and a set `cancel` stops the synthesis within a few milliseconds of audio
// (SpeechCancelled). 0 = no bound.
struct SpeechLimits {
	double maxSeconds = 0;
	double maxBreakSeconds = 0;
	const std::atomic<bool>* cancel = nullptr;
};
class SpeechCancelled : public Error {
public:
	SpeechCancelled() : Error("speech synthesis cancelled") {}
};

// A voice name as espeak-ng is given it (issue 28 item 1): the name must be one espeak-ng lists (a voice's
// name, its file's name or one of its languages, case-insensitive, or an MBROLA voice "mb-…"), and a
// "+variant" one of its variants (espeak-ng --voices=variant; a bare number N is the variant mN). Anything
// else — too long, other characters, unknown — throws Error before libespeak-ng sees it: libespeak-ng 1.51
// overflows a buffer on a long variant ("en-us+" and 37 characters abort the process).
std::string checkedEspeakVoice(const std::string& voice);

// espeak-ng voice for a language tag ("pt-BR" → "pt-br", "en-US" → "en-us", "fr" → "fr").
std::string espeakVoiceFor(const std::string& languageTag);

// The language an espeak-ng voice speaks, as espeak-ng lists it, lower case ("fr" → "fr-fr", "en-us+f3" →
// "en-us", "mb-br1" → "pt-br" from its voice file, without MBROLA), and the voice's name ("French (France)";
// empty for MBROLA voices). nullopt when espeak-ng has no such voice.
struct VoiceLanguage {
	std::string language, name;
};
std::optional<VoiceLanguage> espeakVoiceLanguage(const std::string& voice);

class Language;
// The voice must speak the language of the viseme table (say --voice fr with the pt-BR table would give
// French speech Portuguese visemes); regions may differ (a pt voice, the pt-BR table). Empty when it does
// (or espeak-ng does not know the voice: its own error comes later), else why not and which --lang fits.
std::string voiceLanguageMismatch(const std::string& voice, const Language& language);

// Phonemises `text` with libespeak-ng (in process, synchronous, phoneme events with IPA names) and
// returns the phones with the durations espeak-ng gives them; pauses are dropped. Throws Error.
std::vector<SpokenPhone> espeakPhones(const std::string& text, const std::string& voice);

// Text-to-speech in one pass (libespeak-ng, synchronous): the PCM and each phoneme's interval (IPA
// labels; pauses are empty labels), sorted, contiguous from 0 to the end of the PCM.
struct Speech {
	int sampleRate = 0;
	std::vector<short> pcm;  // mono
	Transcript phones;       // phone level, path "espeak-ng"
	// Word level (espeak-ng's word events): one interval per spoken word of the text, labelled with the
	// word as written (a number such as "42" is one word however many it says); it starts at the word
	// event (which can precede its first phoneme event by a word-initial stop's closure) and ends where its
	// last phoneme ends. Gaps between words are not filled. Each interval's `line` is the word's
	// 1-based character position in the text.
	Transcript words;
	// What was changed in the text before espeak-ng saw it (characters outside the voice's script).
	std::vector<std::string> warnings;
};
// rateWpm 0 / pitch −1 = the voice's defaults; wordGap10ms adds a pause of that many 10 ms units between
// words (espeakWORDGAP). Throws Error for an unknown voice (with how to get MBROLA voices for "mb-…"
// names) and for text with nothing to say.
Speech espeakSpeak(const std::string& text, const std::string& voice, int rateWpm = 0, int pitch = -1, int wordGap10ms = 0,
                   const SpeechLimits& limits = {});

// The phones of `speech` with each word-initial stop's closure given to the stop: espeak-ng's phoneme
// event of a word-initial stop comes after its closure while the word event marks the closure's start, so
// the first phone of each word is made to start at its word event (the phone or pause before it ends
// there). What forced alignment (align/align.h) reports and is measured against.
Transcript phonesWithClosures(const Speech& speech);

// The phoneme names (IPA, as espeak-ng's phoneme events name them, stress marks dropped) that espeak-ng
// uses for each of `words` in `voice`, without synthesising sound (espeak_TextToPhonemes): what a
// language's symbol table must cover (issue 28 item 9), each with the first word that has it. Language
// switches ("(en)") are not phonemes and are left out, as in espeakSpeak. Throws Error for an unknown voice.
std::map<std::string, std::string> espeakPhonemeNames(const std::vector<std::string>& words, const std::string& voice);

// Word-level transcript → phone intervals: each word is phonemised and its phones spread over the
// word's interval in proportion to espeak-ng's own durations; pauses ("", "sil", "sp", "_") stay pauses.
std::vector<Interval> expandWords(const Transcript& words, const std::string& languageTag);

// SSML (ssml.h) in one pass: each segment between <break>s spoken by espeakSpeak, joined with pauses of
// exactly the breaks' lengths (the segments' own silence next to a break is cut); `eventTimes` gets, per
// event of `ssml`, the start of the first word at or after it (or the end of its segment's speech).
Speech espeakSpeakSsml(const SsmlText& ssml, const std::string& voice, std::vector<Ticks>& eventTimes, int rateWpm = 0, int pitch = -1,
                       const SpeechLimits& limits = {});

}  // namespace talkhead
