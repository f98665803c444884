// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The phonetics module's own: each file of timing readers registers its formats here (one function per
// file, one line in timing_registry.cpp's list). Not part of the installed interface.
#include <optional>
#include <string>
#include <vector>

#include "phonetics/timing_registry.h"

namespace talkhead {

void registerClassicTimingFormats(std::vector<TimingFormat>& out);   // transcript.cpp: TextGrid, .pho, HTK, GRID, TIMIT, TSV, Rhubarb, marks
void registerServiceTimingFormats(std::vector<TimingFormat>& out);   // timing_formats.cpp: Whisper, OpenAI, Deepgram, Gentle, aeneas, MFA, Azure, ElevenLabs, Google TTS, SRT/VTT, CTM, Festival, SMIL
void registerAsrTimingFormats(std::vector<TimingFormat>& out);       // asr_formats.cpp: AssemblyAI, Amazon, Google STT, Rev.ai, Vosk, Speechmatics, whisper.cpp, Scribe, Azure batch
void registerDocumentTimingFormats(std::vector<TimingFormat>& out);  // document_formats.cpp: TTML, ELAN, Transcriber, Rhubarb XML, BAS Partitur, whisper console, CHAT, SBV

// Helpers the readers share.
namespace timing {
// Seconds → ticks, checked (finite, 0 … a day); `where` names the value in the message.
Ticks secondsAt(double seconds, const std::string& path, const std::string& where);
// A number, or a string holding one ("2.680", "1.200s" with `allowSuffixS`).
std::optional<double> number(const JsonValue* v, bool allowSuffixS = false);
const std::string* string(const JsonValue* v);
const JsonValue* array(const JsonValue& v, const char* key);
const JsonValue* object(const JsonValue& v, const char* key);
// Every element of `list` is an object with all of `keys` (and the list is not empty).
bool allHave(const JsonValue& list, std::initializer_list<const char*> keys);
bool anyHave(const JsonValue& list, const char* key);
// The sample's JSON when it is one object, else nullptr.
const JsonValue* jsonObject(const TimingSample& s);
// A registry entry (timing_registry.h's TimingFormat, field by field); `read` empty with a `refusal` for a
// format named and not read.
TimingFormat makeFormat(std::string name, std::string title, std::vector<std::string> extensions, std::string level, std::string takes, int confidence,
                        std::function<bool(const TimingSample&)> signature, std::function<Transcript(const TimingSample&, const ReadOptions&)> read,
                        std::string refusal = "");
// The speakers of a file, and the one ReadOptions::tier chose: the chosen name, or an Error listing them
// when the file holds several and none was chosen (or the name is not there).
std::string chooseSpeaker(const std::vector<std::string>& speakers, const ReadOptions& o, const std::string& path, const std::string& what);
}  // namespace timing

}  // namespace talkhead
