// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/json.h"
#include "phonetics/transcript.h"

namespace talkhead {

// One registry of the timing formats talkhead reads (issue 50, D96). Every format registers a name (its
// --format), the extensions its writers use, a POSITIVE signature (what must be in the file, not what may
// be) and a confidence; detection runs every signature and takes the one that matches. There is no
// fallback: a file no signature matches is an error naming what it looks like (when a registered format
// names it and is refused) and the formats that are read; two matches at the same confidence are an error
// naming both and the --format that picks one.

// What a signature looks at, computed once per file: the decoded text, its extension, and — for text that
// starts like JSON — the parsed value (or the values of a stream of JSON objects, as Vosk and Polly print).
class TimingSample {
public:
	TimingSample(std::string text, std::string path);
	const std::string& text() const { return text_; }
	std::string_view trimmed() const;            // the text without leading/trailing white space
	const std::string& path() const { return path_; }
	const std::string& extension() const { return extension_; }  // lower case, with the dot (".json"); empty if none
	// The first `n` lines (trimmed, CR dropped), for line formats.
	const std::vector<std::string>& firstLines() const;
	// The one JSON value of the text (nullptr: not JSON, or malformed — jsonError() says why).
	const JsonValue* json() const;
	// Two or more JSON values one after another (Vosk's printed results, Polly's speech-mark lines): each
	// with the line it starts on. Empty when the text is one value or not JSON.
	const std::vector<std::pair<long, JsonValue>>& jsonStream() const;
	const std::string& jsonError() const;
	bool looksLikeJson() const;                   // starts with { or [
	bool looksLikeXml() const;                    // starts with < (an XML declaration, a root element)
	// The XML root element's local name ("tt", "ANNOTATION_DOCUMENT"), empty when not XML.
	std::string xmlRoot() const;

private:
	void parseJsonOnce() const;
	std::string text_, path_, extension_;
	mutable bool jsonParsed_ = false;
	mutable std::unique_ptr<JsonValue> json_;
	mutable std::vector<std::pair<long, JsonValue>> stream_;
	mutable std::string jsonError_;
	mutable std::vector<std::string> lines_;
	mutable bool linesRead_ = false;
};

struct TimingFormat {
	std::string name;                     // --format (lower case, no spaces): "assemblyai"
	std::string title;                    // for people: "AssemblyAI transcript (JSON)"
	std::vector<std::string> extensions;  // ".json"
	std::string level;                    // phones, words, sentences, visemes (or "phones or words")
	std::string takes;                    // what it takes from the file: "times in ms; language; speakers; duration"
	// 3: a member or marker only this format has; 2: a shape only it has among the registered ones; 1: a
	// generic shape (a TSV of numbers and labels) that a more specific format outranks.
	int confidence = 2;
	std::function<bool(const TimingSample&)> signature;
	// Reads the file. Empty for a format named and refused: `refusal` then says what to export instead.
	std::function<Transcript(const TimingSample&, const ReadOptions&)> read;
	std::string refusal;
};

// Every registered format, in the order `talkhead formats` lists them.
const std::vector<TimingFormat>& timingFormats();
const TimingFormat* findTimingFormat(const std::string& name);

// The format of a file, or nullopt when no signature matches (or two do); `why` (optional) gets the
// message the reader would give.
std::optional<std::string> detectTimingFormat(const TimingSample& sample, std::string* why = nullptr);

// Reads with the registered format `format` (empty: detected). Throws Error naming the file.
Transcript readTimingSample(const TimingSample& sample, const ReadOptions& options);

// The language a file states, as written ("zho", "en_us", "eng"; Gentle's English as "en-US"): JSON
// members (language, language_code, languageCode, whisper.cpp's result.language, Speechmatics'
// metadata.transcription_config.language, Google's results[].languageCode, aeneas's fragments), XML
// (xml:lang, ELAN's LANG_REF and LANGUAGE), WebVTT's "Language:" header, CHAT's @Languages. Empty: none.
std::string statedLanguage(const TimingSample& sample);

// The registry as a table (name, title, extensions, level, what it takes), for `talkhead formats` and the
// README; `markdown` gives a Markdown table.
std::string formatsTable(bool markdown);

}  // namespace talkhead
