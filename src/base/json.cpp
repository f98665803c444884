// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/json.h"

#include <cstdio>
#include <cstdlib>

#include "base/error.h"
#include "base/text.h"

namespace talkhead {

const JsonValue* JsonValue::find(const std::string& key) const {
	for (const auto& [k, v] : object)
		if (k == key) return &v;
	return nullptr;
}

namespace {

class Parser {
public:
	Parser(const std::string& t, const std::string& path, long line) : t_(t), path_(path), line_(line) {}
	JsonValue document() {
		JsonValue v = value(0);
		skip();
		if (i_ != t_.size()) fail("unexpected text after the JSON value");
		return v;
	}

private:
	[[noreturn]] void fail(const std::string& what) const { throw Error(path_, line_, "malformed JSON: " + what); }
	void skip() {
		while (i_ < t_.size() && (t_[i_] == ' ' || t_[i_] == '\t' || t_[i_] == '\n' || t_[i_] == '\r')) {
			if (t_[i_] == '\n') ++line_;
			++i_;
		}
	}
	bool eat(char c) {
		skip();
		if (i_ < t_.size() && t_[i_] == c) {
			++i_;
			return true;
		}
		return false;
	}
	JsonValue value(int depth) {
		if (depth > 64) fail("nested too deeply");
		skip();
		if (i_ >= t_.size()) fail("unexpected end");
		JsonValue v;
		const char c = t_[i_];
		if (c == '{') {
			++i_;
			v.kind = JsonValue::Kind::Object;
			if (eat('}')) return v;
			do {
				skip();
				if (i_ >= t_.size() || t_[i_] != '"') fail("expected a member name");
				std::string key = string();
				if (!eat(':')) fail("expected ':'");
				v.object.emplace_back(std::move(key), value(depth + 1));
			} while (eat(','));
			if (!eat('}')) fail("expected ',' or '}'");
		} else if (c == '[') {
			++i_;
			v.kind = JsonValue::Kind::Array;
			if (eat(']')) return v;
			do v.array.push_back(value(depth + 1));
			while (eat(','));
			if (!eat(']')) fail("expected ',' or ']'");
		} else if (c == '"') {
			v.kind = JsonValue::Kind::String;
			v.string = string();
		} else if (t_.compare(i_, 4, "true") == 0) {
			v.kind = JsonValue::Kind::Bool;
			v.boolean = true;
			i_ += 4;
		} else if (t_.compare(i_, 5, "false") == 0) {
			v.kind = JsonValue::Kind::Bool;
			i_ += 5;
		} else if (t_.compare(i_, 4, "null") == 0) {
			i_ += 4;
		} else if (c == '-' || (c >= '0' && c <= '9')) {
			const char* start = t_.c_str() + i_;
			char* end = nullptr;
			v.number = std::strtod(start, &end);
			if (end == start) fail("bad number");
			v.kind = JsonValue::Kind::Number;
			i_ += std::size_t(end - start);
		} else {
			fail(std::string("unexpected character '") + c + "'");
		}
		return v;
	}
	unsigned hex4() {
		if (i_ + 4 > t_.size()) fail("bad \\u escape");
		unsigned v = 0;
		for (int k = 0; k < 4; ++k) {
			char h = t_[i_++];
			v <<= 4;
			if (h >= '0' && h <= '9') v |= unsigned(h - '0');
			else if (h >= 'a' && h <= 'f') v |= unsigned(h - 'a' + 10);
			else if (h >= 'A' && h <= 'F') v |= unsigned(h - 'A' + 10);
			else fail("bad \\u escape");
		}
		return v;
	}
	std::string string() {
		++i_;  // opening quote
		std::string out;
		while (i_ < t_.size() && t_[i_] != '"') {
			char c = t_[i_++];
			if (c == '\n') fail("newline in a string");
			if (c != '\\') {
				out += c;
				continue;
			}
			if (i_ >= t_.size()) break;
			char e = t_[i_++];
			switch (e) {
				case '"': out += '"'; break;
				case '\\': out += '\\'; break;
				case '/': out += '/'; break;
				case 'b': out += '\b'; break;
				case 'f': out += '\f'; break;
				case 'n': out += '\n'; break;
				case 'r': out += '\r'; break;
				case 't': out += '\t'; break;
				case 'u': {
					unsigned cp = hex4();
					if (cp >= 0xD800 && cp < 0xDC00 && t_.compare(i_, 2, "\\u") == 0) {
						i_ += 2;
						unsigned lo = hex4();
						cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
					}
					appendUtf8(cp, out);
					break;
				}
				default: fail("bad escape");
			}
		}
		if (i_ >= t_.size()) fail("unterminated string");
		++i_;
		return out;
	}
	const std::string& t_;
	const std::string& path_;
	long line_;
	std::size_t i_ = 0;
};

}  // namespace

JsonValue parseJson(const std::string& text, const std::string& path, long line) { return Parser(text, path, line).document(); }

std::string jsonQuote(const std::string& s) {
	std::string o = "\"";
	for (unsigned char c : s) {
		if (c == '"') o += "\\\"";
		else if (c == '\\') o += "\\\\";
		else if (c == '\n') o += "\\n";
		else if (c == '\t') o += "\\t";
		else if (c < 0x20) {
			char buf[8];
			std::snprintf(buf, sizeof buf, "\\u%04x", c);
			o += buf;
		} else o += char(c);
	}
	return o + "\"";
}

}  // namespace talkhead
