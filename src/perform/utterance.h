// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "base/ticks.h"
#include "media/audio.h"
#include "perform/controls.h"
#include "perform/phone_timing.h"
#include "perform/timeline.h"
#include "phonetics/espeak.h"
#include "phonetics/language.h"
#include "phonetics/ssml.h"

namespace talkhead {

// Something to say: the sound and the phones in it, times relative to the sound's first sample.
struct Utterance {
	std::string id;                     // the client's, as JSON text (serve: a quoted string or a number), echoed as is
	AudioClip audio;                    // mono at the session's sample rate (empty: a silent utterance)
	std::vector<PhoneSegment> phones;   // with CDVs (phoneSegments), from 0
	using Mark = TimelineMark;
	std::vector<Mark> marks;            // reported when reached
	std::vector<BrowEvent> brows;       // SSML brow events (relative)
	std::vector<Ticks> blinks;          // SSML blinks (relative)
	std::vector<std::string> warnings;  // what was changed on the way (espeak-ng's text warnings)
	// A part of a streamed speech (perform/stream.h): only the first part opens the utterance (its start is
	// reported), only the last closes it (its end); the parts in between continue it where the one before
	// ends. A whole utterance does both.
	bool opens = true, closes = true;
	// Where the phones' times came from: PerformanceSpec::timing.
	PhoneTiming timing = PhoneTiming::Given;
	Ticks duration() const;             // the sound's length, or the phones' end when longer
};

// The utterance espeak-ng speaks for `text` (plain or SSML: breaks, marks, blinks, brows; emotion
// elements are refused — send an emotion command) in `voice` (empty: the language's default), resampled to
// `sampleRate`. rateWpm 0 / pitch −1: the voice's defaults. `limits` bound the synthesis (a server's).
// Throws Error (unknown voice, nothing to say, bad SSML, over a limit) or SpeechCancelled.
Utterance speakText(const std::string& text, const Language& language, const std::string& voice, int sampleRate, int rateWpm = 0,
                    int pitch = -1, const SpeechLimits& limits = {});

// An utterance from a sound the caller has (any format libav decodes, in `audioPath`) and its timing in any
// transcript format talkhead reads (`transcript`, named `transcriptName` in errors). A sound longer than
// maxSeconds (> 0) is refused while it is decoded, before it takes the memory (decodeAudio). Throws Error.
Utterance utteranceFromAudio(const std::string& audioPath, const std::string& transcript, const std::string& transcriptName,
                             const Language& language, int sampleRate, double maxSeconds = 0);

// What an SSML text's events (D45) come to on its speech's timeline — the one place they are read, for
// `say`, live sessions and serve. `times` are espeakSpeakSsml's (one per event), clamped to `end`. Emotion
// elements nest: each end returns to the emotion around it, `outer` outside every element; each change
// ramps over 0.2 s. Brows last 0.8 s.
struct SpeechEvents {
	std::vector<Utterance::Mark> marks;
	std::vector<Ticks> blinks;
	std::vector<BrowEvent> brows;
	std::vector<ControlTrack::EmotionChange> emotions;
};
SpeechEvents ssmlEvents(const SsmlText& ssml, const std::vector<Ticks>& times, Ticks end, const Expression& outer = {});

// A control track of the events (blinks, brows, emotion changes; the marks are reported, not performed),
// named `path` in messages.
ControlTrack controlTrackOf(SpeechEvents events, const std::string& path);

// Text (plain, or SSML with emotions) spoken by espeak-ng in one pass, as `say` speaks it. SSML's emotion
// names are checked before any speech is made (an error names `textName`, its line and column).
struct SpokenText {
	Speech speech;
	std::optional<SsmlText> ssml;
	std::vector<Ticks> eventTimes;  // per SSML event (espeakSpeakSsml)
};
SpokenText speakWithEvents(const std::string& text, const std::string& textName, const std::string& voice, int rateWpm = 0, int pitch = -1);

// espeak-ng's 16-bit PCM as float samples (mono, its rate).
AudioClip audioOf(const Speech& speech);

}  // namespace talkhead
