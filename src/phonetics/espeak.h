// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

#include "phonetics/transcript.h"

namespace talkhead {

// A phoneme espeak-ng speaks for a text, with its duration.
struct SpokenPhone {
	std::string ipa;
	Ticks duration{0};
};

// espeak-ng voice for a language tag ("pt-BR" → "pt-br", "en-US" → "en-us").
std::string espeakVoiceFor(const std::string& languageTag);

// Phonemises `text` with libespeak-ng (in process, synchronous, phoneme events with IPA names) and
// returns the phones with the durations espeak-ng gives them; pauses are dropped. Throws Error.
std::vector<SpokenPhone> espeakPhones(const std::string& text, const std::string& voice);

// Word-level transcript → phone intervals: each word is phonemised and its phones spread over the
// word's interval in proportion to espeak-ng's own durations; pauses ("", "sil", "sp", "_") stay pauses.
std::vector<Interval> expandWords(const Transcript& words, const std::string& languageTag);

}  // namespace talkhead
