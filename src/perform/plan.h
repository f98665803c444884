// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/frame_rate.h"
#include "base/ticks.h"
#include "media/audio.h"
#include "perform/controls.h"
#include "perform/performance.h"
#include "perform/phone_timing.h"
#include "phonetics/espeak.h"
#include "phonetics/language.h"
#include "phonetics/ssml.h"
#include "phonetics/transcript.h"
#include "synth/coarticulation.h"

namespace talkhead {

// Planning a performance (issue 30): what `render`, `say`, live sessions and `serve` all do between
// "here is some speech" and "draw these keyposes". Two steps: the speech's phones from one of its sources
// (a timed transcript, text with the audio it is spoken in, espeak-ng's speech), then planPerformance.

// Speech in phones with their CDVs, from one source, and what was learned on the way.
struct TimedSpeech {
	std::vector<PhoneSegment> phones;
	std::vector<Interval> words;      // when the source knows them (word-level files, alignments, espeak-ng)
	AudioClip audio;                  // decoded when the source needed it (an alignment); else empty
	std::string name;                 // the source, for messages: the transcript's path, or the audio's
	std::vector<std::string> notes;   // one line each, for stderr: "aligned: …", "N cues aligned to …"
	std::vector<std::string> warnings;  // the reader's, each "name: what"
	Transcript read;                  // the transcript as read (its level, format, tier and why)
	std::optional<SsmlText> ssml;     // espeak-ng's SSML text (its events: say's blinks, brows, emotions, marks)
	std::vector<Ticks> eventTimes;    // per SSML event (espeakSpeakSsml)
	// Recognised speech (speechFromAudio): each interval of `read` has its confidence; 1 elsewhere.
	std::vector<double> confidence;
	double confidenceAt(Ticks t) const;
	// Where the phones' times came from: given, found by aligning the text to the audio (talkhead's
	// aligner: the coarticulation model's visual lead applies, D104) or recognised (D106).
	PhoneTiming timing = PhoneTiming::Given;
};

// A timed transcript in any format talkhead reads. Words are phonemised in `language`; sentence-level
// cues (subtitles, aeneas, utterance tiers) are aligned each to its own stretch of `audioPath` when given
// (issue 29), else spread by espeak-ng's durations. `wantWords`: a TextGrid's word tier is read too (for
// the timeline sidecar). `onRead` sees the transcript as read, before any alignment (to say which language
// its words are read in before an alignment that fails).
TimedSpeech speechFromTranscript(const std::string& path, const ReadOptions& read, const Language& language, UnknownPhone unknown,
                                 Notation notation, const std::optional<std::string>& audioPath, bool wantWords,
                                 const std::function<void(const Transcript&)>& onRead = {});
// What `audioPath` says, given as text: forced alignment (align/align.h).
TimedSpeech speechFromText(const std::string& text, const std::string& audioPath, const Language& language, UnknownPhone unknown = UnknownPhone::Error);
// What `audioPath` says, recognised from the sound alone (align/recognize.h): the en-US phone recogniser's
// phones, in `language` (another language's nearest phones, said in a note). Notes say the timing was
// recognised and its mean confidence; doubtful recognition and silence are warnings.
TimedSpeech speechFromAudio(const std::string& audioPath, const Language& language);
// The same for a sound in memory (a live `speak` with no timing): its phones in `language`; what a user
// should know goes to `notes` (the summary, a language note) and `warnings` (silence, doubtful recognition).
std::vector<PhoneSegment> recognizedPhones(const AudioClip& audio, const std::string& name, const Language& language,
                                           std::vector<std::string>& notes, std::vector<std::string>& warnings);
// Recognised phones (canonical en-US IPA) in `language`: each takes the language's spelling of it, else its
// nearest phone. Returns how many moved.
int toLanguage(Transcript& phones, const Language& language);
// Loads the speech recogniser now (its plugin and decoders, ~1 s) rather than in the first recognition: a
// server calls it as it starts. Throws Error when it cannot (no pocketsphinx, no model).
void prepareSpeechRecognition();
// `text` aligned to a sound in memory (a live `speak` with its text): its phones; the alignment's warnings
// go to `warnings`. Throws Error when the text does not match the audio.
std::vector<PhoneSegment> alignedPhones(const AudioClip& audio, const std::string& text, const Language& language, std::vector<std::string>& warnings);
// espeak-ng's speech (say): its phones (names it has that the tables lack take the nearest known phone).
TimedSpeech speechFromEspeak(const Speech& speech, const Language& language);

// How pauses are played unless asked: Still with a coarticulation model (D70: its lips rest where the
// speaker's do), else Natural.
PauseStyle defaultPauseStyle(bool withCoarticulation);

// What to perform.
struct PerformanceSpec {
	std::vector<PhoneSegment> phones;  // the speech; keyposes at their midpoints (pauses: `pauses`)
	std::vector<Keypose> keys;         // or the keyposes themselves (a driven mouth, D55), phones empty
	FrameRate rate;
	PauseStyle pauses = PauseStyle::Natural;
	Expression expression;             // the emotion and its intensity
	ModulatorOptions modulation;       // blinks and head motion
	double speechBrows = 0;            // brow raises with speech (D49); 0 = none
	// The video's length: `duration` when set, else the audio's when there is one, else the speech's end.
	std::optional<Ticks> duration;
	std::optional<Ticks> audioDuration;
	std::string source;                // names the speech in messages ("the transcript" is longer than …)
	// Applied in order (SSML events, --controls, a driving video's track).
	std::vector<ControlTrack> controls;
	// D62: predicts each phone keypose's mouth opening from its context (the face shows its nearest exemplar).
	std::shared_ptr<const CoarticulationModel> coarticulation;
	// The face the keyposes are planned against: with `coarticulation`, planning's last step binds each
	// predicted mouth to the face's exemplar nearest it (chooseMouthExemplars), once, after the controls.
	// Null: left to the caller (renderPerformance refuses keyposes left unbound).
	const FaceModel* face = nullptr;
	// Where the phones' times came from (TimedSpeech::timing, Utterance::timing). With `coarticulation`:
	// talkhead's aligner's are moved by the model's visual lead (D104: they come ~20 ms late against the
	// mouth); recognised phones are planned with the model's `recognised` companion when it has one (D106);
	// given times (a transcript, espeak-ng's, a TTS engine's) are taken as they are.
	PhoneTiming timing = PhoneTiming::Given;
	// The video's length as planPerformance sets it.
	Ticks videoDuration() const;
};

// Keyposes, duration, brows with speech, controls, exemplars (with `face`). Throws Error when the speech is longer than the audio
// by more than 0.1 s; `warnings` gets one line for a speech covering a small part of a long audio.
Performance planPerformance(const PerformanceSpec& spec, std::vector<std::string>* warnings = nullptr);

// Timeline: events of a control track past `end` dropped (a driving video longer than the speech).
ControlTrack clippedTo(ControlTrack track, Ticks end);

}  // namespace talkhead
