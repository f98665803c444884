// SPDX-License-Identifier: GPL-3.0-or-later
// The registry of timing formats (issue 50, D96): positive signatures, detection without fallback.
#include "phonetics/timing_registry.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/timing_readers.h"

namespace talkhead {

// ---- The sample ---------------------------------------------------------------------------------------

TimingSample::TimingSample(std::string text, std::string path) : text_(std::move(text)), path_(std::move(path)) {
	const std::string lower = toLower(path_);
	const auto slash = lower.find_last_of('/');
	const auto dot = lower.rfind('.');
	if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) extension_ = lower.substr(dot);
}

std::string_view TimingSample::trimmed() const { return trim(text_); }

const std::vector<std::string>& TimingSample::firstLines() const {
	if (!linesRead_) {
		linesRead_ = true;
		std::size_t start = 0;
		while (start < text_.size() && lines_.size() < 200) {
			std::size_t e = text_.find('\n', start);
			if (e == std::string::npos) e = text_.size();
			lines_.emplace_back(trim(std::string_view(text_).substr(start, e - start)));
			start = e + 1;
		}
	}
	return lines_;
}

bool TimingSample::looksLikeJson() const {
	const std::string_view t = trimmed();
	return !t.empty() && (t.front() == '{' || t.front() == '[');
}

bool TimingSample::looksLikeXml() const {
	const std::string_view t = trimmed();
	return !t.empty() && t.front() == '<';
}

std::string TimingSample::xmlRoot() const {
	if (!looksLikeXml()) return "";
	const std::string_view t = trimmed();
	// The first element that is not a declaration, comment, processing instruction or DOCTYPE.
	for (std::size_t p = 0; (p = t.find('<', p)) != std::string_view::npos; ++p) {
		if (p + 1 >= t.size()) break;
		const char c = t[p + 1];
		if (c == '?' || c == '!') continue;
		std::size_t e = p + 1;
		while (e < t.size() && !std::isspace(static_cast<unsigned char>(t[e])) && t[e] != '>' && t[e] != '/') ++e;
		std::string name(t.substr(p + 1, e - p - 1));
		if (const auto colon = name.find(':'); colon != std::string::npos) name = name.substr(colon + 1);
		return name;
	}
	return "";
}

namespace {

// The spans of top-level JSON values one after another (whitespace between them), with their first line;
// nullopt when the text is not such a sequence (a brace inside a string does not count).
std::optional<std::vector<std::pair<long, std::string_view>>> jsonValues(std::string_view t) {
	std::vector<std::pair<long, std::string_view>> out;
	long line = 1;
	std::size_t i = 0;
	while (i < t.size()) {
		while (i < t.size() && std::isspace(static_cast<unsigned char>(t[i]))) line += t[i++] == '\n';
		if (i >= t.size()) break;
		if (t[i] != '{' && t[i] != '[') return std::nullopt;
		const std::size_t start = i;
		const long startLine = line;
		int depth = 0;
		bool str = false, esc = false;
		for (; i < t.size(); ++i) {
			const char c = t[i];
			if (c == '\n') ++line;
			if (str) {
				if (esc) esc = false;
				else if (c == '\\') esc = true;
				else if (c == '"') str = false;
				continue;
			}
			if (c == '"') str = true;
			else if (c == '{' || c == '[') ++depth;
			else if ((c == '}' || c == ']') && --depth == 0) break;
			if (depth > 512) return std::nullopt;
		}
		if (i >= t.size()) return std::nullopt;  // cut off: the parser names where
		out.emplace_back(startLine, t.substr(start, ++i - start));
		if (out.size() > 1'000'000) return std::nullopt;
	}
	return out;
}

}  // namespace

void TimingSample::parseJsonOnce() const {
	if (jsonParsed_) return;
	jsonParsed_ = true;
	if (!looksLikeJson()) return;
	// Bounded as serve's requests are (issue 28): a timing file of 64 MiB at most holds ~10⁷ values.
	constexpr std::size_t kMaxValues = 20'000'000;
	try {
		json_ = std::make_unique<JsonValue>(parseJson(text_, path_, 1, kMaxValues));
		return;
	} catch (const Error& e) {
		jsonError_ = e.what();
	}
	// Several values one after another (JSON lines, or pretty-printed objects as Vosk prints them).
	const auto values = jsonValues(text_);
	if (!values || values->size() < 2) return;
	std::vector<std::pair<long, JsonValue>> stream;
	try {
		for (const auto& [line, span] : *values) stream.emplace_back(line, parseJson(std::string(span), path_, line, kMaxValues));
	} catch (const Error& e) {
		jsonError_ = e.what();
		return;
	}
	stream_ = std::move(stream);
	jsonError_.clear();
}

const JsonValue* TimingSample::json() const {
	parseJsonOnce();
	return json_.get();
}

const std::vector<std::pair<long, JsonValue>>& TimingSample::jsonStream() const {
	parseJsonOnce();
	return stream_;
}

const std::string& TimingSample::jsonError() const {
	parseJsonOnce();
	return jsonError_;
}

// ---- Shared helpers --------------------------------------------------------------------------------------

namespace timing {

Ticks secondsAt(double seconds, const std::string& path, const std::string& where) {
	if (!std::isfinite(seconds) || seconds < 0 || seconds > 86400) {
		char b[200];
		std::snprintf(b, sizeof b, "%s: time %g s is not from 0 to 86400 s (a day)", where.c_str(), seconds);
		throw Error(path, 0, b);
	}
	return ticksFromSeconds(seconds);
}

std::optional<double> number(const JsonValue* v, bool allowSuffixS) {
	if (!v) return std::nullopt;
	if (v->kind == JsonValue::Kind::Number) return v->number;
	if (v->kind != JsonValue::Kind::String) return std::nullopt;
	std::string_view s = trim(v->string);
	if (allowSuffixS && !s.empty() && s.back() == 's') s.remove_suffix(1);
	double d;
	if (parseDouble(s, d)) return d;
	return std::nullopt;
}

const std::string* string(const JsonValue* v) { return v && v->kind == JsonValue::Kind::String ? &v->string : nullptr; }

const JsonValue* array(const JsonValue& v, const char* key) {
	const JsonValue* a = v.kind == JsonValue::Kind::Object ? v.find(key) : nullptr;
	return a && a->kind == JsonValue::Kind::Array ? a : nullptr;
}

const JsonValue* object(const JsonValue& v, const char* key) {
	const JsonValue* a = v.kind == JsonValue::Kind::Object ? v.find(key) : nullptr;
	return a && a->kind == JsonValue::Kind::Object ? a : nullptr;
}

bool allHave(const JsonValue& list, std::initializer_list<const char*> keys) {
	if (list.kind != JsonValue::Kind::Array || list.array.empty()) return false;
	for (const JsonValue& e : list.array) {
		if (e.kind != JsonValue::Kind::Object) return false;
		for (const char* k : keys)
			if (!e.find(k)) return false;
	}
	return true;
}

bool anyHave(const JsonValue& list, const char* key) {
	return list.kind == JsonValue::Kind::Array &&
	       std::any_of(list.array.begin(), list.array.end(), [&](const JsonValue& e) { return e.kind == JsonValue::Kind::Object && e.find(key); });
}

const JsonValue* jsonObject(const TimingSample& s) {
	const JsonValue* j = s.json();
	return j && j->kind == JsonValue::Kind::Object ? j : nullptr;
}

TimingFormat makeFormat(std::string name, std::string title, std::vector<std::string> extensions, std::string level, std::string takes, int confidence,
                        std::function<bool(const TimingSample&)> signature, std::function<Transcript(const TimingSample&, const ReadOptions&)> read,
                        std::string refusal) {
	TimingFormat f;
	f.name = std::move(name);
	f.title = std::move(title);
	f.extensions = std::move(extensions);
	f.level = std::move(level);
	f.takes = std::move(takes);
	f.confidence = confidence;
	f.signature = std::move(signature);
	f.read = std::move(read);
	f.refusal = std::move(refusal);
	return f;
}

std::string chooseSpeaker(const std::vector<std::string>& speakers, const ReadOptions& o, const std::string& path, const std::string& what) {
	std::string list;
	for (const std::string& s : speakers) list += (list.empty() ? "" : ", ") + safeQuote(s, 40);
	if (!o.tier.empty()) {
		if (std::find(speakers.begin(), speakers.end(), o.tier) != speakers.end()) return o.tier;
		throw Error(path, 0, "no " + what + " '" + safeQuote(o.tier, 40) + "' in this file (its " + what + "s: " + list + ")");
	}
	if (speakers.size() <= 1) return speakers.empty() ? "" : speakers.front();
	throw Error(path, 0, "words of " + std::to_string(speakers.size()) + " " + what + "s (" + list + "); the face is one of them: choose with {{tier}} " +
	                         (what == "speaker" ? "SPEAKER" : "NAME"));
}

}  // namespace timing

// ---- The registry ---------------------------------------------------------------------------------------

const std::vector<TimingFormat>& timingFormats() {
	static const std::vector<TimingFormat> all = [] {
		std::vector<TimingFormat> v;
		registerClassicTimingFormats(v);
		registerServiceTimingFormats(v);
		registerAsrTimingFormats(v);
		registerDocumentTimingFormats(v);
		return v;
	}();
	return all;
}

const TimingFormat* findTimingFormat(const std::string& name) {
	for (const TimingFormat& f : timingFormats())
		if (f.name == name) return &f;
	return nullptr;
}

namespace {

std::string readNames() {
	std::string k;
	for (const TimingFormat& f : timingFormats())
		if (f.read) k += (k.empty() ? "" : ", ") + f.name;
	return k;
}

// What an unmatched file looks like, in a few words.
std::string looksLike(const TimingSample& s) {
	if (const JsonValue* j = s.json()) {
		if (j->kind == JsonValue::Kind::Object) {
			std::string members;
			int n = 0;
			for (const auto& [k, v] : j->object) {
				if (n++ == 6) {
					members += ", …";
					break;
				}
				members += (members.empty() ? "" : ", ") + ("'" + safeQuote(k, 30) + "'");
			}
			return "JSON whose members are " + (members.empty() ? std::string("none") : members);
		}
		return "a JSON array";
	}
	if (!s.jsonStream().empty()) return "a stream of " + std::to_string(s.jsonStream().size()) + " JSON values";
	if (const std::string root = s.xmlRoot(); !root.empty()) return "XML whose root element is <" + safeQuote(root, 40) + ">";
	for (const std::string& l : s.firstLines())
		if (!l.empty()) return "a text file whose first line is '" + safeQuote(l, 50) + "'";
	return "an empty file";
}

}  // namespace

std::optional<std::string> detectTimingFormat(const TimingSample& sample, std::string* why) {
	std::vector<const TimingFormat*> matches;
	for (const TimingFormat& f : timingFormats())
		if (f.signature && f.signature(sample)) matches.push_back(&f);
	if (matches.empty()) {
		if (why) {
			if (sample.looksLikeJson() && !sample.json() && sample.jsonStream().empty() && !sample.jsonError().empty()) *why = sample.jsonError();
			else
				*why = "no timing format talkhead reads matches this file (" + looksLike(sample) + "); formats read: " + readNames() +
				       " (`talkhead formats` describes them; {{format}} names one)";
		}
		return std::nullopt;
	}
	int best = 0;
	for (const TimingFormat* f : matches) best = std::max(best, f->confidence);
	std::vector<const TimingFormat*> top;
	for (const TimingFormat* f : matches)
		if (f->confidence == best) top.push_back(f);
	if (top.size() > 1) {
		if (why) {
			std::string names, picks;
			for (const TimingFormat* f : top) {
				names += (names.empty() ? "" : " and ") + f->title;
				picks += (picks.empty() ? "" : " or ") + ("{{format}} " + f->name);
			}
			*why = "ambiguous: the file fits both " + names + "; choose with " + picks;
		}
		return std::nullopt;
	}
	return top.front()->name;
}

Transcript readTimingSample(const TimingSample& sample, const ReadOptions& o) {
	const TimingFormat* f = nullptr;
	if (!o.format.empty()) {
		f = findTimingFormat(o.format);
		if (!f) throw Error("unknown transcript format '" + o.format + "' (known: " + readNames() + ")");
	} else {
		std::string why;
		const auto name = detectTimingFormat(sample, &why);
		if (!name) {
			// A JSON parser's message already names the file and line.
			if (startsWith(why, sample.path() + ":")) throw Error(why);
			throw Error(sample.path(), 0, why);
		}
		f = findTimingFormat(*name);
	}
	if (!f->read) throw Error(sample.path(), 0, f->title + ": " + f->refusal);
	Transcript tr;
	try {
		tr = f->read(sample, o);
	} catch (const Error& e) {
		// Every message names the file.
		if (!sample.path().empty() && !startsWith(e.what(), sample.path())) throw Error(sample.path(), 0, e.what());
		throw;
	}
	if (tr.format.empty()) tr.format = f->name;
	return tr;
}

std::string formatsTable(bool markdown) {
	std::string out;
	if (markdown) out += "| format | what writes it | extensions | level | taken from the file |\n|---|---|---|---|---|\n";
	else out += "format\twhat writes it\textensions\tlevel\ttaken from the file\n";
	for (const TimingFormat& f : timingFormats()) {
		std::string ext = joined(f.extensions, " ");
		const std::string level = f.read ? f.level : "not read: " + f.refusal;
		if (markdown) out += "| `" + f.name + "` | " + f.title + " | " + ext + " | " + level + " | " + f.takes + " |\n";
		else out += f.name + "\t" + f.title + "\t" + ext + "\t" + level + "\t" + f.takes + "\n";
	}
	return out;
}

}  // namespace talkhead

namespace talkhead {

namespace {
// An XML attribute's value in the first `limit` bytes: name="v" or name='v'.
std::string xmlAttribute(std::string_view t, std::string_view name, std::size_t limit = 200000) {
	t = t.substr(0, limit);
	for (std::size_t p = 0; (p = t.find(name, p)) != std::string_view::npos; p += name.size()) {
		if (p > 0 && !std::isspace(static_cast<unsigned char>(t[p - 1]))) continue;
		std::size_t q = p + name.size();
		if (q >= t.size() || t[q] != '=' || q + 1 >= t.size() || (t[q + 1] != '"' && t[q + 1] != '\'')) continue;
		const std::size_t e = t.find(t[q + 1], q + 2);
		if (e == std::string_view::npos) return "";
		return std::string(t.substr(q + 2, e - q - 2));
	}
	return "";
}
}  // namespace

std::string statedLanguage(const TimingSample& s) {
	using timing::array;
	using timing::object;
	using timing::string;
	if (const JsonValue* j = s.json(); j && j->kind == JsonValue::Kind::Object) {
		if (const JsonValue* w = array(*j, "words"); w && timing::anyHave(*w, "alignedWord")) return "en-US";  // Gentle aligns English only
		for (const char* k : {"language", "language_code", "languageCode", "lang"})
			if (const std::string* l = string(j->find(k)); l && !l->empty()) return *l;
		for (const char* parent : {"result", "params"})
			if (const JsonValue* r = object(*j, parent))
				if (const std::string* l = string(r->find("language")); l && !l->empty()) return *l;
		if (const JsonValue* m = object(*j, "metadata"))
			if (const JsonValue* c = object(*m, "transcription_config"))
				if (const std::string* l = string(c->find("language"))) return *l;
		const JsonValue* results = j->find("results");
		if (const JsonValue* r = object(*j, "response")) results = r->find("results");
		if (results && results->kind == JsonValue::Kind::Object)
			if (const std::string* l = string(results->find("language_code"))) return *l;
		if (results && results->kind == JsonValue::Kind::Array)
			for (const JsonValue& r : results->array)
				if (const std::string* l = string(r.find("languageCode")); l && !l->empty()) return *l;
		if (const JsonValue* f = array(*j, "fragments"); f && !f->array.empty())
			if (const std::string* l = string(f->array[0].find("language"))) return *l;
		return "";
	}
	if (s.looksLikeXml()) {
		const std::string_view t = s.trimmed();
		if (std::string l = xmlAttribute(t, "xml:lang"); !l.empty()) return l;
		if (std::string l = xmlAttribute(t, "LANG_REF"); !l.empty()) return l;
		if (std::string l = xmlAttribute(t, "LANG_ID"); !l.empty()) return l;
		return "";
	}
	const auto& lines = s.firstLines();
	if (!lines.empty() && startsWith(lines[0], "WEBVTT")) {
		for (std::size_t i = 1; i < lines.size() && !lines[i].empty(); ++i)
			if (startsWith(lines[i], "Language:")) return std::string(trim(std::string_view(lines[i]).substr(9)));
		return "";
	}
	for (const std::string& l : lines)
		if (startsWith(l, "@Languages:")) {
			const auto w = splitWhitespace(std::string_view(l).substr(11));
			if (!w.empty()) {
				std::string first = w[0];
				if (!first.empty() && first.back() == ',') first.pop_back();
				return first;
			}
		}
	return "";
}

}  // namespace talkhead
