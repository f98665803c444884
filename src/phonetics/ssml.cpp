// SPDX-License-Identifier: GPL-3.0-or-later
#include "phonetics/ssml.h"

#include <cmath>
#include <algorithm>
#include <cctype>
#include <cstring>
#include <regex>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/emotion.h"

namespace talkhead {

bool looksLikeSsml(const std::string& text) {
	static const std::regex tag(R"(<\s*/?\s*(speak|emotion|break|mark|blink|brows)\b)", std::regex::icase);
	return std::regex_search(text, tag);
}

namespace {

class Parser {
public:
	Parser(const std::string& text, const std::string& path) : s_(text), path_(path) {}

	SsmlText run() {
		out_.segments.emplace_back();
		std::vector<std::string> open;  // element names
		// (opened_ holds where each was opened, for "not closed")
		while (i_ < s_.size()) {
			const char c = s_[i_];
			if (c == '<') {
				tag(open);
			} else if (c == '&') {
				entity();
			} else {
				text() += c;
				advance();
			}
		}
		if (!open.empty()) throw Error(path_, opened_.back().first, "column " + std::to_string(opened_.back().second) + ": <" + open.back() + "> is not closed");
		return out_;
	}

private:
	const std::string& s_;
	const std::string& path_;
	std::size_t i_ = 0;
	long line_ = 1, column_ = 1;
	std::vector<std::pair<long, long>> opened_;  // line, column of each open element
	SsmlText out_;

	std::string& text() { return out_.segments.back().text; }
	void advance() {
		if (s_[i_] == '\n') ++line_, column_ = 1;
		else if ((static_cast<unsigned char>(s_[i_]) & 0xC0) != 0x80) ++column_;
		++i_;
	}
	[[noreturn]] void fail(const std::string& what) const { throw Error(path_, line_, "column " + std::to_string(column_) + ": " + what); }
	void spaces() {
		while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) advance();
	}
	std::string word() {
		std::string w;
		while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '-' || s_[i_] == '_' || s_[i_] == ':'))
			w += s_[i_], advance();
		return w;
	}
	void entity() {
		static const std::pair<const char*, char> known[] = {{"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
		for (const auto& [name, ch] : known)
			if (s_.compare(i_, std::strlen(name), name) == 0) {
				text() += ch;
				for (std::size_t k = 0; k < std::strlen(name); ++k) advance();
				return;
			}
		fail("unknown entity (use &amp; &lt; &gt; &quot; &apos;)");
	}
	void event(SsmlText::Event::Kind kind, const std::string& name, double intensity, long line, long column) {
		SsmlText::Event e{kind, out_.segments.size() - 1, text().size(), name, intensity, 0, line, column};
		out_.events.push_back(e);
	}
	struct Tag {
		std::string name;
		bool closing = false, selfClosing = false;
		std::vector<std::pair<std::string, std::string>> attributes;
		long line = 0, column = 0;
	};
	// One tag, read: its name, attributes and whether it closes or is empty.
	Tag readTag() {
		Tag t;
		t.line = line_, t.column = column_;
		advance();  // <
		spaces();
		t.closing = i_ < s_.size() && s_[i_] == '/';
		if (t.closing) advance();
		spaces();
		const std::string name = t.name = toLower(word());
		if (name.empty()) fail("expected a tag name after '<' (write &lt; for a literal '<')");
		for (;;) {
			spaces();
			if (i_ >= s_.size()) fail("unterminated <" + name + ">");
			if (s_[i_] == '>' || s_[i_] == '/') break;
			const std::string key = toLower(word());
			if (key.empty()) fail("expected an attribute name in <" + name + ">");
			spaces();
			if (i_ >= s_.size() || s_[i_] != '=') fail("expected '=' after " + key);
			advance();
			spaces();
			if (i_ >= s_.size() || (s_[i_] != '"' && s_[i_] != '\'')) fail("expected a quoted value for " + key);
			const char quote = s_[i_];
			advance();
			std::string value;
			while (i_ < s_.size() && s_[i_] != quote) value += s_[i_], advance();
			if (i_ >= s_.size()) fail("unterminated value of " + key);
			advance();
			t.attributes.emplace_back(key, value);
		}
		if (s_[i_] == '/') {
			t.selfClosing = true;
			advance();
			if (i_ >= s_.size() || s_[i_] != '>') fail("expected '>' after '/' in <" + name + ">");
		}
		advance();  // >
		return t;
	}
	void tag(std::vector<std::string>& open) {
		const Tag t = readTag();
		const std::string& name = t.name;
		const bool closing = t.closing, selfClosing = t.selfClosing;
		const long line = t.line, column = t.column;
		const auto& attributes = t.attributes;
		auto attribute = [&](const std::string& key) -> const std::string* {
			for (const auto& [k, v] : attributes)
				if (k == key) return &v;
			return nullptr;
		};
		auto allow = [&](std::initializer_list<const char*> keys) {
			for (const auto& attr : attributes)
				if (std::none_of(keys.begin(), keys.end(), [&](const char* a) { return attr.first == a; }))
					throw Error(path_, line, "column " + std::to_string(column) + ": <" + name + "> has no attribute '" + attr.first + "'");
		};
		auto here = [&](const std::string& what) { return Error(path_, line, "column " + std::to_string(column) + ": " + what); };
		if (closing) {
			if (open.empty() || open.back() != name) throw here("</" + name + "> closes nothing open" + (open.empty() ? "" : " (open: <" + open.back() + ">)"));
			open.pop_back();
			opened_.pop_back();
			if (name == "emotion") event(SsmlText::Event::Kind::EmotionEnd, "", 1, line, column);
			return;
		}
		if (name == "speak") {
			if (selfClosing) return;
			open.push_back(name);
			opened_.emplace_back(line, column);
		} else if (name == "emotion") {
			allow({"name", "intensity"});
			const std::string* label = attribute("name");
			if (!label) throw here("<emotion> needs name=\"…\"");
			double intensity = 1;
			if (const std::string* v = attribute("intensity"); v && (!parseDouble(*v, intensity) || !(intensity >= 0 && intensity <= Expression::kMaxIntensity)))
				throw here("<emotion> intensity must be a number from 0 to 1.5");
			if (selfClosing) throw here("<emotion/> must enclose the words it colours");
			open.push_back(name);
			opened_.emplace_back(line, column);
			event(SsmlText::Event::Kind::EmotionStart, *label, intensity, line, column);
		} else if (name == "break") {
			allow({"time"});
			const std::string* t = attribute("time");
			if (!t) throw here("<break> needs time=\"300ms\" or time=\"1.5s\"");
			double seconds = -1;
			std::string v = *t;
			if (endsWith(v, "ms") && parseDouble(v.substr(0, v.size() - 2), seconds)) seconds /= 1000;
			else if (endsWith(v, "s") && parseDouble(v.substr(0, v.size() - 1), seconds)) {
			} else seconds = -1;
			if (!(seconds >= 0 && seconds <= 60)) throw here("<break> time must be like 300ms or 1.5s, at most 60 s");
			if (!selfClosing) throw here("<break> must be empty: <break time=\"…\"/>");
			out_.segments.back().pauseAfter += ticksFromSeconds(seconds);
			out_.segments.emplace_back();
		} else if (name == "mark") {
			allow({"name"});
			const std::string* n = attribute("name");
			if (!n) throw here("<mark> needs name=\"…\"");
			if (!selfClosing) throw here("<mark> must be empty: <mark name=\"…\"/>");
			event(SsmlText::Event::Kind::Mark, *n, 1, line, column);
		} else if (name == "blink") {
			allow({});
			if (!selfClosing) throw here("<blink> must be empty: <blink/>");
			event(SsmlText::Event::Kind::Blink, "", 1, line, column);
		} else if (name == "brows") {
			allow({"up", "down"});
			double up = 0, down = 0;
			for (auto [key, value] : {std::pair<const char*, double*>{"up", &up}, {"down", &down}})
				if (const std::string* v = attribute(key); v && (!parseDouble(*v, *value) || !(*value >= 0 && *value <= 1.5)))
					throw here(std::string("<brows> ") + key + " must be a number from 0 to 1.5");
			if (up == 0 && down == 0) throw here("<brows> needs up=\"…\" or down=\"…\" (0–1.5)");
			if (!selfClosing) throw here("<brows> must be empty: <brows up=\"0.8\"/>");
			event(SsmlText::Event::Kind::Brows, "", up, line, column);
			out_.events.back().frown = down;
		} else {
			throw here("unknown tag <" + name + "> (known: speak, emotion, break, mark, blink, brows)");
		}
	}
};

}  // namespace

SsmlText parseSsml(const std::string& text, const std::string& path) { return Parser(text, path).run(); }

}  // namespace talkhead
