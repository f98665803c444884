// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>

#include "phonetics/transcript.h"

namespace talkhead {

// The plausibility gate every timed transcript passes before anything is rendered, whatever its reader
// (issue 50, D96): the median length of a phone (12 ms – 1 s), a word (20 ms – 5 s) or a viseme; the most
// phones (words) in any 2 s of speech (at most 50 phones, 25 words — from the fastest real files on hand,
// see docs/decisions.md D96); the end within 10 % (+0.5 s) of a duration the file or the audio states.
// A transcript that fails but passes with its times ×1000, ÷1000, ÷10⁷ or ÷ a sample rate is an Error that
// names the unit the times look like; one that fails otherwise is an Error saying what is implausible.
// Returns the verdict (one line: what was checked and passed), for -v.
std::string checkTimingPlausibility(const Transcript& tr, std::optional<double> audioSeconds = {});

// Labels that are not speech never reach the phonemiser (word level): bracketed sound events ("[Applause.]",
// "(laughs)") become pauses, speaker labels at the start of a cue ("The First Minister (Nicola Sturgeon):",
// ">> ANNA:") and override codes ({\an8}) are dropped, and pinyin tone numbers (ni3 hao3) are removed when
// most words carry one. Each kind is counted in one warning on the transcript.
void cleanSpeechLabels(Transcript& tr);

// The length of a speaker label at the start of a cue ("Anna Smith: …", ">> ANNA: …", "The First Minister
// (Nicola Sturgeon): …"; the colon included), 0 when there is none.
std::size_t speakerLabelLength(const std::string& label);

// A language name as timing files write it (ISO 639-1 "fr", ISO 639-3 "zho", BCP 47 "en-US"/"en_us", or an
// English name "english") as talkhead's tag: one of Language::available() ("en-US", "fr"), else the
// primary subtag in ISO 639-1 ("zh") so that Language::get names the language it has no table for; empty
// when it is no language name.
std::string languageTagOf(const std::string& name);

}  // namespace talkhead
