// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <map>
#include <memory>
#include <optional>
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
// starts on (for JSON-lines input). `maxValues` (0: no bound) bounds the values (numbers, strings, arrays,
// objects, …) the text may hold: each costs ~100 bytes here, so a request of 30 MB of "[0,0,…]" would take
// 1.6 GiB (issue 28 item 4); past it parsing stops with an Error saying so.
JsonValue parseJson(const std::string& text, const std::string& path, long line = 1, std::size_t maxValues = 0);

// The value of `key` in the top-level object of `text` — a string, or an integer written as one — as far
// as the text can be read: for a text that is malformed or cut off after the member, too (an error reply
// to a request that could not be parsed still names its id). nullopt when not found.
std::optional<std::string> jsonTopLevelMember(const std::string& text, const std::string& key);

// Escapes a string for JSON output (quotes included).
std::string jsonQuote(const std::string& s);

}  // namespace talkhead
