// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>

#include "base/json.h"
#include "phonetics/transcript.h"

namespace talkhead {

// Timing files of today's speech pipelines (issue 29, D59), read into the one Transcript form. Words come
// out at word level (phonemised later with espeak-ng, in the file's language or --lang), phones at phone
// level, visemes at viseme level. Each throws Error naming the file (and line or JSON path) and what is
// wrong; none guesses: a file whose times are not there, or whose text is only referenced, is an error
// that says what to give instead.

// JSON: the Whisper family (whisper-timestamped, WhisperX, faster-whisper: segments[].words[]; OpenAI
// verbose_json: words[]), Deepgram (results.channels[0].alternatives[0].words[]), Gentle (words[] with
// phones and durations: phone level), aeneas sync maps (fragments[] with begin/end/lines: sentence
// level), MFA 3.x JSON (tiers.phones / tiers.words entries), Azure Speech viseme events and word
// boundaries, ElevenLabs character alignment. `format` names one ("whisper", "openai", …) or is empty to
// detect it from the members.
// Deepgram's diarized words of several speakers: --tier (ReadOptions::tier) names the speaker.
Transcript readJsonTiming(const std::string& text, const std::string& path, const std::string& format = "", const ReadOptions& options = {});

// SubRip (.srt) and WebVTT (.vtt) cues: each cue's text (tags and inline timestamps removed) over its
// interval, at word level; a cue of several words is one "word" interval spread by espeak-ng's durations.
Transcript readSubtitles(const std::string& text, const std::string& path, const ReadOptions& o = {});
bool looksLikeSubtitles(const std::string& text);

// NIST CTM ("utterance channel start duration label [confidence]"), as Kaldi, NeMo's forced aligner and
// sclite write it: word level, or phone level when the labels are phones (Kaldi's position suffixes _B
// _I _E _S dropped). One utterance and channel per file (else an error naming them).
Transcript readCtm(const std::string& text, const std::string& path, const ReadOptions& o);
bool looksLikeCtm(const std::string& text);

// Azure Speech viseme events ([{"id": 0–21, "offset_ms": T}] or the SDK's {"VisemeId", "AudioOffset"} in
// 100-ns units; each lasts until the next) and ElevenLabs' character timestamps ({"characters",
// "character_start_times_seconds", "character_end_times_seconds"}, grouped into words at spaces). `where`
// names the value in messages.
Transcript azureVisemes(const JsonValue& list, const std::string& where);
Transcript characterAlignment(const JsonValue& alignment, const std::string& where);

// aeneas's SMIL sync map (EPUB3 media overlays: <par> with <text src="….xhtml#f000001"/> and <audio
// clipBegin clipEnd/>) with the text it refers to (ReadOptions::timingText); without it, an error saying
// what to give. Sentence level, like aeneas JSON.
Transcript readSmil(const std::string& text, const std::string& path, const std::string& textPath);
// A transcript whose labels are fragment ids (aeneas TSV, SMIL), each replaced by its text from `textPath`:
// XHTML (elements with those ids), aeneas's parsed "id|text" lines, or plain text (line k = f00000k).
Transcript withFragmentText(const Transcript& ids, const std::string& path, const std::string& textPath);
// Google Text-to-Speech timepoints ({"timepoints": [{"markName", "timeSeconds"}]}) with the SSML they came
// from: the words after each <mark/> span from its time to the next mark's (the last words: as long as
// espeak-ng says them, with a warning).
Transcript googleTimepoints(const JsonValue& v, const std::string& path, const std::string& ssmlPath);

// Festival's utterance files (EST_File utterance, as utt.save writes them): the Segment relation's phones.
Transcript readFestivalUtterance(const std::string& text, const std::string& path);

// The language a timing file names (Whisper's "fr", OpenAI's "english", aeneas's "eng"), as a tag of
// Language::available() ("fr", "en-US"), or nullopt when it names none or one without a table.
std::optional<std::string> timingFileLanguage(const std::string& text);

}  // namespace talkhead
