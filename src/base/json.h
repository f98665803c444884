// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace talkhead {

// A small JSON reader for the transcript formats (Rhubarb JSON, speech marks): objects, arrays,
// strings (with escapes, \u included), numbers, true/false/null.
struct JsonValue {
	enum class Kind { Null, Bool, Number, String, Array, Object } kind = Kind::Null;
	bool boolean = false;
	double number = 0;
	std::string string;
	std::vector<JsonValue> array;
	std::vector<std::pair<std::string, JsonValue>> object;

	const JsonValue* find(const std::string& key) const;  // object member or nullptr
};

// Parses one JSON value; throws Error("path:line: …") on malformed input. `line` is the line the text
// starts on (for JSON-lines input).
JsonValue parseJson(const std::string& text, const std::string& path, long line = 1);

// Escapes a string for JSON output (quotes included).
std::string jsonQuote(const std::string& s);

}  // namespace talkhead
