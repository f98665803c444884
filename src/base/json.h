// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
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
// The same member as JSON text, for a scalar: a string quoted (escaped again), a number as written, true,
// false or null. nullopt when not found or an object or an array.
std::optional<std::string> jsonTopLevelMemberJson(const std::string& text, const std::string& key);
// `objectText` (a JSON object) with only the top-level members named in `keys` (sorted by name), on one line
// ("{}" when it is not an object).
std::string jsonKeepMembers(const std::string& objectText, const std::vector<std::string>& keys);

// Escapes a string for JSON output (quotes included).
std::string jsonQuote(const std::string& s);

// Where the whitespace goes in a JSON object or array written by JsonObject / JsonArray: after the opening
// bracket, between two members or items, and before the closing bracket. The default is one line,
// {"a": 1, "b": 2}; files people read put a member or item a line, e.g. {"\n  ", ",\n  ", "\n"}.
struct JsonLayout {
	std::string_view lead = "", separator = ", ", trail = "";
};

// One JSON object, in talkhead's style — {"key": value, "key": value}, members in the order added — for
// events, progress lines, replies, reports and the files talkhead writes (issue 30: no hand
// concatenation). Strings are escaped (jsonQuote); numbers take a printf format, and a number that is not
// finite is written null. An empty object is {}.
class JsonObject {
public:
	JsonObject& add(std::string_view key, const std::string& text);
	JsonObject& add(std::string_view key, const char* text) { return add(key, std::string(text)); }
	JsonObject& add(std::string_view key, bool value) { return raw(key, value ? "true" : "false"); }
	JsonObject& add(std::string_view key, long long value) { return raw(key, std::to_string(value)); }
	JsonObject& add(std::string_view key, int value) { return add(key, static_cast<long long>(value)); }
	JsonObject& add(std::string_view key, long value) { return add(key, static_cast<long long>(value)); }
	JsonObject& add(std::string_view key, unsigned long value) { return raw(key, std::to_string(value)); }
	JsonObject& add(std::string_view key, double value, const char* format);
	// A value that is JSON already (an array, an object, null, a number formatted by the caller).
	JsonObject& raw(std::string_view key, std::string_view json);
	// The next member follows `separator` instead of the layout's (a document whose first members share a
	// line and whose last ones do not).
	JsonObject& then(std::string_view separator);
	bool empty() const { return members_.empty(); }
	std::string str(const JsonLayout& layout = {}) const;

private:
	std::vector<std::pair<std::string, std::string>> members_;  // separator before it ("" = the layout's), member
	std::string nextSeparator_;
};

// One JSON array of values that are JSON already (JsonObject::str(), jsonQuote(…), numbers), laid out as
// JsonObject's; an empty array is [].
class JsonArray {
public:
	JsonArray& raw(std::string json) {
		items_.push_back(std::move(json));
		return *this;
	}
	JsonArray& add(const std::string& text) { return raw(jsonQuote(text)); }
	bool empty() const { return items_.empty(); }
	std::string str(const JsonLayout& layout = {}) const;

private:
	std::vector<std::string> items_;
};

}  // namespace talkhead
