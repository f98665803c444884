// SPDX-License-Identifier: GPL-3.0-or-later
// JSON through nlohmann/json (Debian nlohmann-json3-dev, header-only): its SAX parser builds JsonValue
// directly, so member order and repeated names are kept (readers report them) and no intermediate DOM is
// made; its errors become "path:line: malformed JSON: column C: …".
#include "base/json.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base/error.h"
#include "base/text.h"

namespace talkhead {

const JsonValue* JsonValue::find(const std::string& key) const {
	for (const auto& [k, v] : object)
		if (k == key) return &v;
	return nullptr;
}

namespace {

constexpr std::size_t kMaxDepth = 64;

class Builder : public nlohmann::json_sax<nlohmann::json> {
public:
	explicit Builder(std::size_t maxValues) : left_(maxValues > 0 ? maxValues : std::size_t(-1)) {}
	JsonValue root;
	std::string error;        // set when parsing stopped
	std::size_t errorAt = 0;  // byte offset (1-based, nlohmann's) of the error, 0 = unknown

	bool null() override { return put(JsonValue{}); }
	bool boolean(bool b) override {
		JsonValue v;
		v.kind = JsonValue::Kind::Bool;
		v.boolean = b;
		return put(std::move(v));
	}
	bool number_integer(number_integer_t n) override { return number(double(n)); }
	bool number_unsigned(number_unsigned_t n) override { return number(double(n)); }
	bool number_float(number_float_t n, const string_t&) override { return number(double(n)); }
	bool string(string_t& s) override {
		JsonValue v;
		v.kind = JsonValue::Kind::String;
		v.string = std::move(s);
		return put(std::move(v));
	}
	bool binary(binary_t&) override { return put(JsonValue{}); }  // not produced by the text parser
	bool start_object(std::size_t) override { return open(JsonValue::Kind::Object); }
	bool key(string_t& k) override {
		key_ = std::move(k);
		return true;
	}
	bool end_object() override {
		stack_.pop_back();
		return true;
	}
	bool start_array(std::size_t) override { return open(JsonValue::Kind::Array); }
	bool end_array() override {
		stack_.pop_back();
		return true;
	}
	bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
		errorAt = position;
		// "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error …" → "syntax error …"
		std::string m = e.what();
		if (auto colon = m.find(": "); m.rfind("[json.exception.", 0) == 0 && colon != std::string::npos) {
			const auto at = m.find("column ");
			const auto second = at == std::string::npos ? std::string::npos : m.find(": ", at);
			m = m.substr(second != std::string::npos ? second + 2 : colon + 2);
		}
		error = m;
		return false;
	}

private:
	std::vector<JsonValue*> stack_;
	std::string key_;
	std::size_t left_;  // values still allowed
	bool counted() {
		if (left_-- > 0) return true;
		error = "more values than a request may hold";
		return false;
	}
	bool number(double d) {
		JsonValue v;
		v.kind = JsonValue::Kind::Number;
		v.number = d;
		return put(std::move(v));
	}
	// Places a value: the root, an array element or an object member; returns where it went.
	JsonValue* place(JsonValue&& v) {
		if (stack_.empty()) {
			root = std::move(v);
			return &root;
		}
		JsonValue& top = *stack_.back();
		if (top.kind == JsonValue::Kind::Array) {
			top.array.push_back(std::move(v));
			return &top.array.back();
		}
		top.object.emplace_back(std::move(key_), std::move(v));
		return &top.object.back().second;
	}
	bool put(JsonValue&& v) {
		if (!counted()) return false;
		place(std::move(v));
		return true;
	}
	bool open(JsonValue::Kind kind) {
		if (stack_.size() >= kMaxDepth) {
			error = "nested too deeply (more than " + std::to_string(kMaxDepth) + " levels)";
			return false;
		}
		if (!counted()) return false;
		JsonValue v;
		v.kind = kind;
		stack_.push_back(place(std::move(v)));  // children are added through the pointer: parents never move
		return true;
	}
};

}  // namespace

namespace {

// Reads the top-level object's members up to `key`'s value, then stops.
class MemberFinder : public nlohmann::json_sax<nlohmann::json> {
public:
	MemberFinder(std::string key, bool asJson) : key_(std::move(key)), json_(asJson) {}
	std::optional<std::string> found;
	bool null() override { return value(json_ ? std::optional<std::string>("null") : std::nullopt); }
	bool boolean(bool b) override { return value(json_ ? std::optional<std::string>(b ? "true" : "false") : std::nullopt); }
	bool number_integer(number_integer_t n) override { return value(std::to_string(n)); }
	bool number_unsigned(number_unsigned_t n) override { return value(std::to_string(n)); }
	bool number_float(number_float_t n, const string_t& text) override {
		if (json_) return value(text);
		return value(std::isfinite(n) && n == std::floor(n) && std::fabs(n) < 1e18 ? std::optional<std::string>(std::to_string(std::llround(n))) : std::nullopt);
	}
	bool string(string_t& s) override { return value(json_ ? jsonQuote(s) : s); }
	bool binary(binary_t&) override { return value(std::nullopt); }
	bool start_object(std::size_t) override { return open(); }
	bool key(string_t& k) override {
		here_ = depth_ == 1 && k == key_;
		return true;
	}
	bool end_object() override { return --depth_, here_ = false, true; }
	bool start_array(std::size_t) override { return open(); }
	bool end_array() override { return --depth_, here_ = false, true; }
	bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

private:
	std::string key_;
	bool json_;
	int depth_ = 0;
	bool here_ = false;
	bool open() {
		if (here_) return false;  // the member is an object or an array: no id
		++depth_;
		return true;
	}
	bool value(std::optional<std::string> v) {
		if (!here_ || depth_ != 1) return true;
		found = std::move(v);
		return false;  // done
	}
};

std::optional<std::string> findMember(const std::string& text, const std::string& key, bool asJson) {
	MemberFinder f(key, asJson);
	try {
		nlohmann::json::sax_parse(text, &f, nlohmann::json::input_format_t::json, false, false);
	} catch (const std::exception&) {
	}
	return f.found;
}

}  // namespace

std::optional<std::string> jsonTopLevelMember(const std::string& text, const std::string& key) { return findMember(text, key, false); }
std::optional<std::string> jsonTopLevelMemberJson(const std::string& text, const std::string& key) { return findMember(text, key, true); }

std::string jsonKeepMembers(const std::string& objectText, const std::vector<std::string>& keys) {
	nlohmann::json j = nlohmann::json::parse(objectText, nullptr, false);
	if (!j.is_object()) return "{}";
	nlohmann::json kept = nlohmann::json::object();
	for (const std::string& k : keys) {
		auto it = j.find(k);
		if (it != j.end()) kept[k] = std::move(*it);
	}
	return kept.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

JsonValue parseJson(const std::string& text, const std::string& path, long line, std::size_t maxValues) {
	Builder b(maxValues);
	bool ok = false;
	try {
		ok = nlohmann::json::sax_parse(text, &b, nlohmann::json::input_format_t::json, true, false);
	} catch (const std::exception& e) {  // sax_parse reports through parse_error; anything else is a bug of the input too
		b.error = e.what();
	}
	if (ok) return std::move(b.root);
	// Line and column of the error, counted from the text's first line (JSON lines: `line`).
	const std::size_t at = std::min(b.errorAt > 0 ? b.errorAt - 1 : text.size(), text.size());
	const long lines = long(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
	const std::size_t lineStart = text.rfind('\n', at == 0 ? 0 : at - 1);
	const std::size_t column = at - (lineStart == std::string::npos || at == 0 ? 0 : lineStart + 1) + 1;
	std::string what = b.error.empty() ? "malformed" : b.error;
	if (what.size() > 160) what = safeQuote(what, 160);
	throw Error(path, line + lines, "malformed JSON: " + (b.errorAt > 0 ? "column " + std::to_string(column) + ": " : std::string()) + what);
}

std::string jsonQuote(const std::string& s) {
	// Invalid UTF-8 is replaced (U+FFFD) rather than written as bytes no JSON reader accepts.
	return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

JsonObject& JsonObject::add(std::string_view key, const std::string& text) { return raw(key, jsonQuote(text)); }

JsonObject& JsonObject::add(std::string_view key, double value, const char* format) {
	if (!std::isfinite(value)) return raw(key, "null");
	char b[64];
	std::snprintf(b, sizeof b, format, value);
	return raw(key, b);
}

JsonObject& JsonObject::raw(std::string_view key, std::string_view json) {
	std::string member = jsonQuote(std::string(key));
	member += ": ";
	member += json;
	members_.emplace_back(std::move(nextSeparator_), std::move(member));
	nextSeparator_.clear();
	return *this;
}

JsonObject& JsonObject::then(std::string_view separator) {
	nextSeparator_ = separator;
	return *this;
}

namespace {

template <typename Items, typename Separator, typename Text>
std::string laidOut(char open, char close, const Items& items, const JsonLayout& layout, Separator separatorOf, Text textOf) {
	std::string s(1, open);
	if (items.empty()) return s + close;
	s += layout.lead;
	for (std::size_t i = 0; i < items.size(); ++i) {
		if (i) s += separatorOf(items[i]);
		s += textOf(items[i]);
	}
	s += layout.trail;
	return s + close;
}

}  // namespace

std::string JsonObject::str(const JsonLayout& layout) const {
	return laidOut(
	    '{', '}', members_, layout,
	    [&](const auto& m) { return m.first.empty() ? std::string(layout.separator) : m.first; }, [](const auto& m) -> const std::string& { return m.second; });
}

std::string JsonArray::str(const JsonLayout& layout) const {
	return laidOut(
	    '[', ']', items_, layout, [&](const std::string&) { return std::string(layout.separator); }, [](const std::string& t) -> const std::string& { return t; });
}

}  // namespace talkhead
