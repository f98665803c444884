// SPDX-License-Identifier: GPL-3.0-or-later
// Timing files of today's speech pipelines (issue 29, D59): JSON of ASR and aligners, subtitles, CTM, and
// TTS services' viseme and character timings.
#include "phonetics/timing_formats.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/espeak.h"
#include "phonetics/plausibility.h"
#include "phonetics/timing_readers.h"

namespace talkhead {

namespace {

constexpr double kMaxSeconds = 86400;

// Kaldi's word-position suffix of a phone (ah_B, dh_I, t_E, ay_S; Gentle and Kaldi CTMs) dropped.
std::string withoutPositionSuffix(std::string label) {
	const auto u = label.rfind('_');
	if (u != std::string::npos && u + 2 == label.size() && std::string("BIES").find(label[u + 1]) != std::string::npos) label.resize(u);
	return label;
}

// Words with start/end seconds and a text under one of `textKeys`. Words without times (WhisperX leaves
// numbers and unaligned words without) are skipped and counted.
void addWords(Transcript& tr, const JsonValue& words, const std::vector<const char*>& textKeys, const std::string& path, const std::string& where,
              int& untimed) {
	long k = 0;
	for (const JsonValue& w : words.array) {
		const std::string here = where + "[" + std::to_string(k++) + "]";
		if (w.kind != JsonValue::Kind::Object) throw Error(path, 0, here + " is not an object");
		const std::string* text = nullptr;
		for (const char* key : textKeys)
			if ((text = timing::string(w.find(key)))) break;
		if (!text) throw Error(path, 0, here + " has no " + textKeys.front());
		const auto s = timing::number(w.find("start")), e = timing::number(w.find("end"));
		if (!s || !e) {
			++untimed;
			continue;
		}
		if (*e < *s) throw Error(path, 0, here + " ('" + safeQuote(*text) + "') ends before it starts");
		tr.intervals.push_back({timing::secondsAt(*s, path, here), timing::secondsAt(*e, path, here), std::string(trim(*text)), k});
	}
}

void untimedWarning(Transcript& tr, int untimed, const char* what) {
	if (untimed > 0)
		tr.warnings.push_back(std::to_string(untimed) + " " + what + (untimed > 1 ? "s have" : " has") + " no times (not aligned) and " +
		                      (untimed > 1 ? "are" : "is") + " left out: the mouth rests there");
}

// WhisperX's diarized speaker of a word (its own "speaker", else its segment's); empty when none.
std::string whisperSpeaker(const JsonValue& word, const JsonValue& segment) {
	if (const std::string* w = timing::string(word.find("speaker"))) return *w;
	if (const std::string* g = timing::string(segment.find("speaker"))) return *g;
	return "";
}

Transcript whisper(const JsonValue& v, const std::string& path, const ReadOptions& o) {
	Transcript tr;
	tr.format = "whisper";
	tr.level = LabelLevel::Word;
	int untimed = 0;
	const JsonValue* segments = timing::array(v, "segments");
	// WhisperX with diarization: words of several speakers; one is read (--speaker), as for Deepgram.
	std::vector<std::string> speakers;
	for (const JsonValue& seg : segments->array)
		if (const JsonValue* words = timing::array(seg, "words"))
			for (const JsonValue& w : words->array)
				if (const std::string sp = whisperSpeaker(w, seg); !sp.empty() && std::find(speakers.begin(), speakers.end(), sp) == speakers.end()) speakers.push_back(sp);
	const bool choose = speakers.size() > 1 || !o.tier.empty();
	if (choose) tr.speaker = timing::chooseSpeaker(speakers, o, path, "speaker");
	tr.speakers = speakers;
	long s = 0;
	for (const JsonValue& seg : segments->array) {
		const std::string where = "segments[" + std::to_string(s++) + "].words";
		const JsonValue* words = timing::array(seg, "words");
		if (!words) continue;
		if (!choose) {
			addWords(tr, *words, {"text", "word"}, path, where, untimed);
			continue;
		}
		JsonValue mine;
		mine.kind = JsonValue::Kind::Array;
		for (const JsonValue& w : words->array)
			if (whisperSpeaker(w, seg) == tr.speaker) mine.array.push_back(w);
		addWords(tr, mine, {"text", "word"}, path, where, untimed);
	}
	if (tr.intervals.empty() && untimed == 0)
		throw Error(path, 0, "a Whisper JSON without word timestamps (segments[].words[]): run it with word timestamps (whisper --word_timestamps True, whisper-timestamped, WhisperX, faster-whisper word_timestamps=True)");
	untimedWarning(tr, untimed, "word");
	return tr;
}

Transcript openai(const JsonValue& v, const std::string& path) {
	Transcript tr;
	tr.format = "openai";
	tr.level = LabelLevel::Word;
	int untimed = 0;
	addWords(tr, *timing::array(v, "words"), {"word", "text"}, path, "words", untimed);
	untimedWarning(tr, untimed, "word");
	return tr;
}

Transcript deepgram(const JsonValue& v, const std::string& path, const ReadOptions& o) {
	const JsonValue* results = v.find("results");
	const JsonValue* channels = results ? timing::array(*results, "channels") : nullptr;
	if (!channels || channels->array.empty()) throw Error(path, 0, "a Deepgram answer without results.channels");
	if (channels->array.size() > 1) throw Error(path, 0, "a Deepgram answer with " + std::to_string(channels->array.size()) + " channels: give one channel's");
	const JsonValue* alts = timing::array(channels->array[0], "alternatives");
	if (!alts || alts->array.empty()) throw Error(path, 0, "results.channels[0] has no alternatives");
	const JsonValue* words = timing::array(alts->array[0], "words");
	if (!words) throw Error(path, 0, "results.channels[0].alternatives[0] has no words");
	// Diarized words of several speakers share one channel: the face is one of them (--tier SPEAKER).
	std::vector<long> speakers;
	for (const JsonValue& w : words->array)
		if (const auto sp = timing::number(w.find("speaker")); sp && std::find(speakers.begin(), speakers.end(), long(*sp)) == speakers.end()) speakers.push_back(long(*sp));
	std::sort(speakers.begin(), speakers.end());
	JsonValue chosen = *words;
	if (speakers.size() > 1 || !o.tier.empty()) {
		std::string list;
		for (long sp : speakers) list += (list.empty() ? "" : ", ") + std::to_string(sp);
		long want = -1;
		double d;
		if (!o.tier.empty() && parseDouble(o.tier, d)) want = long(d);
		if (o.tier.empty())
			throw Error(path, 0, "words of " + std::to_string(speakers.size()) + " speakers (Deepgram diarization) in one channel; the face is one of them: choose with {{tier}} SPEAKER (" + list + ")");
		if (std::find(speakers.begin(), speakers.end(), want) == speakers.end()) throw Error(path, 0, "{{tier}} " + safeQuote(o.tier) + ": no such speaker (" + list + ")");
		chosen.array.clear();
		for (const JsonValue& w : words->array)
			if (timing::number(w.find("speaker")) == std::optional<double>(double(want))) chosen.array.push_back(w);
	}
	Transcript tr;
	tr.format = "deepgram";
	tr.level = LabelLevel::Word;
	int untimed = 0;
	addWords(tr, chosen, {"word", "punctuated_word"}, path, "results.channels[0].alternatives[0].words", untimed);
	untimedWarning(tr, untimed, "word");
	if (speakers.size() > 1) tr.tierNote = "speaker " + o.tier;
	return tr;
}

// Gentle: phone level, each aligned word's phones laid from its start by their durations (ARPAbet in lower
// case with Kaldi's position suffixes, which go).
Transcript gentle(const JsonValue& v, const std::string& path) {
	Transcript tr;
	tr.format = "gentle";
	tr.level = LabelLevel::Phone;
	int missing = 0;
	long k = 0;
	for (const JsonValue& w : timing::array(v, "words")->array) {
		const std::string here = "words[" + std::to_string(k++) + "]";
		// "success", and "not-found-in-transcript" (spoken, with times and phones, but not in the text): both
		// are speech; "not-found-in-audio" has no times.
		const auto s = timing::number(w.find("start"));
		const JsonValue* phones = timing::array(w, "phones");
		if (!s || !phones) {
			++missing;
			continue;
		}
		Ticks t = timing::secondsAt(*s, path, here);
		long p = 0;
		for (const JsonValue& ph : phones->array) {
			const std::string* name = timing::string(ph.find("phone"));
			const auto d = timing::number(ph.find("duration"));
			if (!name || !d || *d < 0) throw Error(path, 0, here + ".phones[" + std::to_string(p) + "] needs phone and duration");
			std::string label = withoutPositionSuffix(*name);
			const Ticks e = t + timing::secondsAt(*d, path, here);
			// Gentle's ARPAbet, in the upper case that says so (lower-case "y" is also an espeak-ng or br1 phone).
			for (char& ch : label) ch = char(std::toupper(static_cast<unsigned char>(ch)));
			tr.intervals.push_back({t, e, label == "OOV" ? std::string() : label, k});
			t = e;
			++p;
		}
	}
	// A word's phones can run past the next word's start (durations summed in seconds by a microsecond; a
	// trailing "sil" by seconds): they end where the next word starts.
	int cut = 0;
	std::stable_sort(tr.intervals.begin(), tr.intervals.end(), [](const Interval& a, const Interval& b) { return a.start < b.start; });
	for (std::size_t i = 1; i < tr.intervals.size(); ++i)
		if (tr.intervals[i].start < tr.intervals[i - 1].end) {
			cut += tr.intervals[i - 1].end - tr.intervals[i].start > ticksFromSeconds(0.001);
			tr.intervals[i - 1].end = std::max(tr.intervals[i - 1].start, tr.intervals[i].start);
		}
	if (cut > 0) tr.warnings.push_back(std::to_string(cut) + " phone" + (cut > 1 ? "s" : "") + " ran past the next word's start and end there");
	if (missing > 0)
		tr.warnings.push_back(std::to_string(missing) + " word" + (missing > 1 ? "s" : "") +
		                      " of the transcript Gentle did not find in the audio left out: the mouth rests there");
	if (tr.intervals.empty()) throw Error(path, 0, "Gentle aligned no word");
	return tr;
}

// aeneas: fragments with begin/end (strings) and lines of text (sentence level, phonemised and spread).
Transcript aeneas(const JsonValue& v, const std::string& path) {
	Transcript tr;
	tr.format = "aeneas";
	tr.level = LabelLevel::Word;
	long k = 0;
	for (const JsonValue& f : timing::array(v, "fragments")->array) {
		const std::string here = "fragments[" + std::to_string(k++) + "]";
		const auto b = timing::number(f.find("begin")), e = timing::number(f.find("end"));
		if (!b || !e) throw Error(path, 0, here + " needs begin and end");
		std::string text;
		if (const JsonValue* lines = timing::array(f, "lines"))
			for (const JsonValue& l : lines->array)
				if (l.kind == JsonValue::Kind::String) text += (text.empty() ? "" : " ") + l.string;
		if (*e < *b) throw Error(path, 0, here + " ends before it begins");
		tr.intervals.push_back({timing::secondsAt(*b, path, here), timing::secondsAt(*e, path, here), std::string(trim(text)), k});
	}
	if (k > 0) tr.warnings.push_back("an aeneas sync map times sentences, not words: each sentence's phones are spread by espeak-ng's durations (approximate; talkhead align times them from the audio)");
	return tr;
}

// MFA 3.x JSON: {"tiers": {"phones": {"type": "interval", "entries": [[start, end, label], …]}, "words": …}}.
Transcript mfaJson(const JsonValue& v, const std::string& path) {
	const JsonValue* tiers = v.find("tiers");
	if (!tiers || tiers->kind != JsonValue::Kind::Object) throw Error(path, 0, "'tiers' must be an object");
	const JsonValue* chosen = nullptr;
	std::string name;
	LabelLevel level = LabelLevel::Phone;
	for (const char* want : {"phones", "words"})
		for (const auto& [k, t] : tiers->object)
			if (!chosen && toLower(k).find(want) != std::string::npos) chosen = &t, name = k, level = std::string(want) == "phones" ? LabelLevel::Phone : LabelLevel::Word;
	if (!chosen) throw Error(path, 0, "MFA JSON without a phones or words tier");
	const JsonValue* entries = timing::array(*chosen, "entries");
	if (!entries) throw Error(path, 0, "tier '" + safeQuote(name) + "' has no entries");
	Transcript tr;
	tr.format = "mfa-json";
	tr.level = level;
	tr.tier = name;
	tr.tierNote = level == LabelLevel::Phone ? "phones" : "words";
	long k = 0;
	for (const JsonValue& e : entries->array) {
		const std::string here = "tiers." + name + ".entries[" + std::to_string(k++) + "]";
		if (e.kind != JsonValue::Kind::Array || e.array.size() != 3 || e.array[2].kind != JsonValue::Kind::String)
			throw Error(path, 0, here + " must be [start, end, label]");
		const auto s = timing::number(&e.array[0]), en = timing::number(&e.array[1]);
		if (!s || !en) throw Error(path, 0, here + ": start and end must be numbers");
		tr.intervals.push_back({timing::secondsAt(*s, path, here), timing::secondsAt(*en, path, here), e.array[2].string, k});
	}
	return tr;
}

// Azure word boundaries: [{"Text", "AudioOffset" (100 ns), "Duration" (100 ns or "hh:mm:ss.fffffff")}]
// or the same in milliseconds: {"text", "offset_ms", "duration_ms"}.
Transcript azureWords(const JsonValue& list, const std::string& path) {
	Transcript tr;
	tr.format = "azure-words";
	tr.level = LabelLevel::Word;
	long k = 0;
	for (const JsonValue& w : list.array) {
		const std::string here = "[" + std::to_string(k++) + "]";
		const std::string* text = timing::string(w.find("Text"));
		if (!text) text = timing::string(w.find("text"));
		std::optional<double> start, length;
		if (const auto o = timing::number(w.find("AudioOffset"))) start = *o / 1e7;
		else if (const auto m = timing::number(w.find("offset_ms"))) start = *m / 1000;
		if (const auto d = timing::number(w.find("duration_ms"))) length = *d / 1000;
		else if (const JsonValue* d = w.find("Duration")) {
			if (const auto n = timing::number(d)) length = *n / 1e7;
			else if (const std::string* s = timing::string(d)) {  // "00:00:00.3500000"
				int h = 0, m = 0;
				double sec = 0;
				if (std::sscanf(s->c_str(), "%d:%d:%lf", &h, &m, &sec) == 3) length = h * 3600.0 + m * 60.0 + sec;
			}
		}
		if (!text || !start || !length) throw Error(path, 0, here + " needs Text, AudioOffset and Duration (or text, offset_ms, duration_ms)");
		const std::string* type = timing::string(w.find("BoundaryType"));
		if (type && *type != "WordBoundary" && *type != "Word") continue;  // punctuation and sentence boundaries
		tr.intervals.push_back({timing::secondsAt(*start, path, here), timing::secondsAt(*start + *length, path, here), std::string(trim(*text)), k});
	}
	return tr;
}



}  // namespace


Transcript azureVisemes(const JsonValue& list, const std::string& where) {
	if (list.kind != JsonValue::Kind::Array || list.array.empty()) throw Error(where + ": viseme events must be a non-empty array of {id, offset_ms}");
	if (list.array.size() > 100000) throw Error(where + ": more than 100 000 viseme events");
	Transcript t;
	t.path = where;
	t.format = "azure";
	t.level = LabelLevel::Viseme;
	t.visemeScheme = "azure";
	long n = 0;
	for (const JsonValue& e : list.array) {
		const std::string here = where + "[" + std::to_string(n++) + "]";
		if (e.kind != JsonValue::Kind::Object) throw Error(here + " is not an object");
		const JsonValue* id = e.find("id");
		if (!id) id = e.find("VisemeId");
		const JsonValue* ms = e.find("offset_ms");
		const JsonValue* ticks = e.find("AudioOffset");
		const auto idv = timing::number(id);
		const auto time = ms ? timing::number(ms) : ticks ? std::optional<double>(timing::number(ticks).value_or(-1) / 1e4) : std::nullopt;
		if (!idv || !time) throw Error(here + " needs 'id' and 'offset_ms' (or VisemeId and AudioOffset)");
		if (*idv != std::floor(*idv) || *idv < 0 || *idv > 21) {
			char b[96];
			std::snprintf(b, sizeof b, ": viseme id %g is not 0-21", *idv);
			throw Error(here + b);
		}
		if (!(*time >= 0 && *time <= kMaxSeconds * 1000)) throw Error(here + ": the offset must be a number from 0 (milliseconds, or AudioOffset in 100 ns)");
		const Ticks t0 = ticksFromSeconds(*time / 1000);
		if (!t.intervals.empty()) {
			if (t0 < t.intervals.back().start) throw Error(here + " comes before the one before it");
			t.intervals.back().end = t0;
		}
		t.intervals.push_back({t0, t0, std::to_string(int(*idv)), n});
	}
	// Events at the same instant: the later one wins; the last lasts 50 ms unless the caller knows the sound.
	std::vector<Interval> kept;
	for (const Interval& i : t.intervals)
		if (i.end > i.start || &i == &t.intervals.back()) kept.push_back(i);
	kept.back().end = kept.back().start + ticksFromSeconds(0.05);
	t.intervals = std::move(kept);
	return t;
}

Transcript characterAlignment(const JsonValue& a, const std::string& where) {
	const JsonValue* chars = a.find("characters");
	const JsonValue* starts = a.find("character_start_times_seconds");
	const JsonValue* ends = a.find("character_end_times_seconds");
	if (!chars || !starts || !ends || chars->kind != JsonValue::Kind::Array || starts->kind != JsonValue::Kind::Array || ends->kind != JsonValue::Kind::Array)
		throw Error(where + " needs the arrays characters, character_start_times_seconds and character_end_times_seconds");
	const std::size_t n = chars->array.size();
	if (n == 0 || starts->array.size() != n || ends->array.size() != n) throw Error(where + ": the three arrays must be equally long and not empty");
	Transcript t;
	t.path = where;
	t.format = "elevenlabs";
	t.level = LabelLevel::Word;
	Interval word;
	bool open = false;
	for (std::size_t i = 0; i < n; ++i) {
		if (chars->array[i].kind != JsonValue::Kind::String) throw Error(where + ".characters[" + std::to_string(i) + "] is not a string");
		const std::string& c = chars->array[i].string;
		const auto s = timing::number(&starts->array[i]), e = timing::number(&ends->array[i]);
		if (!s || !e || !(*s >= 0 && *s <= kMaxSeconds) || !(*e >= 0 && *e <= kMaxSeconds))
			throw Error(where + ": character " + std::to_string(i) + "'s times must be numbers from 0 (seconds)");
		if (*e < *s) throw Error(where + ": character " + std::to_string(i) + " ends before it starts");
		const Ticks ts = ticksFromSeconds(*s), te = ticksFromSeconds(*e);
		const bool space = std::all_of(c.begin(), c.end(), [](char ch) { return ch == ' ' || ch == '\t' || ch == '\n'; });
		if (space) {
			if (open) t.intervals.push_back(word), open = false;
			continue;
		}
		if (!open) {
			if (!t.intervals.empty() && ts < t.intervals.back().end) throw Error(where + ": character " + std::to_string(i) + " starts before the word before it ends");
			word = Interval{ts, te, c, long(i + 1)};
			open = true;
		} else {
			word.label += c;
			word.end = std::max(word.end, te);
		}
	}
	if (open) t.intervals.push_back(word);
	if (t.intervals.empty()) throw Error(where + " holds no word");
	return t;
}

// ---- Text a timing file refers to (--timing-text) ---------------------------------------------------

namespace {

// &amp; &lt; &gt; &quot; &apos; &#N; &#xN; decoded; tags dropped (a space for a block or a break, so that
// words stay apart); whitespace collapsed.
std::string plainOfMarkup(std::string_view s) {
	std::string out;
	for (std::size_t i = 0; i < s.size();) {
		if (s[i] == '<') {
			const std::size_t e = s.find('>', i);
			const std::string_view tag = s.substr(i + 1, e == std::string_view::npos ? std::string_view::npos : e - i - 1);
			i = e == std::string_view::npos ? s.size() : e + 1;
			// Inline elements (<em>, <span>, SSML's <emphasis>) join the text; blocks and breaks part it.
			std::string name;
			for (char c : tag.substr(tag.empty() || tag[0] != '/' ? 0 : 1)) {
				if (!std::isalnum(static_cast<unsigned char>(c))) break;
				name += char(std::tolower(static_cast<unsigned char>(c)));
			}
			static const char* const kParting[] = {"br", "p", "div", "li", "h1", "h2", "h3", "h4", "h5", "h6", "tr", "td", "th", "break", "s", "section", "body"};
			if (std::find_if(std::begin(kParting), std::end(kParting), [&](const char* t) { return name == t; }) != std::end(kParting)) out += ' ';
		} else if (s[i] == '&') {
			const std::size_t e = s.find(';', i);
			const std::string_view name = e == std::string_view::npos || e - i > 10 ? std::string_view() : s.substr(i + 1, e - i - 1);
			long long code = -1;
			if (name == "amp") code = '&';
			else if (name == "lt") code = '<';
			else if (name == "gt") code = '>';
			else if (name == "quot") code = '"';
			else if (name == "apos") code = '\'';
			else if (name == "nbsp") code = ' ';
			else if (name.size() > 1 && name[0] == '#') {
				const bool hex = name[1] == 'x' || name[1] == 'X';
				code = std::strtoll(std::string(name.substr(hex ? 2 : 1)).c_str(), nullptr, hex ? 16 : 10);
				if (code <= 0 || code > 0x10FFFF) code = -1;
			}
			if (code < 0) {
				out += s[i++];
				continue;
			}
			appendUtf8(unsigned(code), out);
			i = e + 1;
		} else
			out += s[i++];
	}
	std::string collapsed;
	for (const std::string& w : splitWhitespace(out)) collapsed += (collapsed.empty() ? "" : " ") + w;
	return collapsed;
}

// A start tag's attribute value (name="v" or name='v'), or nullopt.
std::optional<std::string> attribute(std::string_view tag, std::string_view name) {
	for (std::size_t p = 0; (p = tag.find(name, p)) != std::string_view::npos; p += name.size()) {
		if (p == 0 || !std::isspace(static_cast<unsigned char>(tag[p - 1]))) continue;
		std::size_t q = p + name.size();
		while (q < tag.size() && std::isspace(static_cast<unsigned char>(tag[q]))) ++q;
		if (q >= tag.size() || tag[q] != '=') continue;
		++q;
		while (q < tag.size() && std::isspace(static_cast<unsigned char>(tag[q]))) ++q;
		if (q >= tag.size() || (tag[q] != '"' && tag[q] != '\'')) continue;
		const std::size_t e = tag.find(tag[q], q + 1);
		if (e == std::string_view::npos) return std::nullopt;
		return std::string(tag.substr(q + 1, e - q - 1));
	}
	return std::nullopt;
}

// The fragments' text, by id, from aeneas's three input text forms: "unparsed" XHTML (elements with an
// id), "parsed" (id|text per line), or "plain" (one fragment per line, ids f000001, f000002, … in order).
struct FragmentText {
	std::map<std::string, std::string> byId;
	std::string form;
};

FragmentText readFragmentText(const std::string& textPath) {
	const std::string t = readTextFile(textPath);
	FragmentText ft;
	if (t.find('<') != std::string::npos && t.find("id=") != std::string::npos) {
		ft.form = "XHTML";
		for (std::size_t p = 0; (p = t.find('<', p)) != std::string::npos;) {
			const std::size_t e = t.find('>', p);
			if (e == std::string::npos) break;
			const std::string_view tag(t.data() + p + 1, e - p - 1);
			p = e + 1;
			if (tag.empty() || tag[0] == '/' || tag[0] == '!' || tag[0] == '?' || tag.back() == '/') continue;
			const auto id = attribute(tag, "id");
			if (!id) continue;
			std::string name(tag.substr(0, std::min(tag.size(), tag.find_first_of(" \t\r\n"))));
			// The content up to the matching end tag (same-named elements nested inside counted).
			int depth = 1;
			std::size_t q = p, end = t.size();
			while (depth > 0) {
				const std::size_t open = t.find("<" + name, q), close = t.find("</" + name, q);
				if (close == std::string::npos) break;
				if (open != std::string::npos && open < close) {
					const std::size_t oe = t.find('>', open);
					if (oe != std::string::npos && t[oe - 1] != '/') ++depth;
					q = open + 1;
				} else {
					if (--depth == 0) end = close;
					q = close + 1;
				}
			}
			ft.byId.emplace(*id, plainOfMarkup(std::string_view(t).substr(p, end - p)));
		}
		if (ft.byId.empty()) throw Error(textPath, 0, "XHTML with no element that has an id: the sync map's fragments cannot be found in it");
		return ft;
	}
	std::vector<std::pair<long, std::string>> lines;
	long no = 0;
	for (const std::string& l : split(t, '\n')) {
		++no;
		const std::string line(trim(l));
		if (!line.empty()) lines.emplace_back(no, line);
	}
	if (lines.empty()) throw Error(textPath, 0, "the text is empty");
	const bool parsed = std::all_of(lines.begin(), lines.end(), [](const auto& l) {
		const std::size_t bar = l.second.find('|');
		return bar != std::string::npos && bar > 0 && l.second.find_first_of(" \t") > bar;
	});
	ft.form = parsed ? "parsed (id|text)" : "plain (one fragment a line)";
	long k = 0;
	for (const auto& [line, text] : lines) {
		char id[32];
		std::snprintf(id, sizeof id, "f%06ld", ++k);
		const std::size_t bar = parsed ? text.find('|') : std::string::npos;
		const std::string key = parsed ? text.substr(0, bar) : id;
		if (!ft.byId.emplace(key, plainOfMarkup(parsed ? std::string_view(text).substr(bar + 1) : std::string_view(text))).second)
			throw Error(textPath, line, "the fragment id '" + safeQuote(key) + "' is given twice");
	}
	return ft;
}

// SMIL clock values: "00:00:02.680", "02:05.5", "2.68s", "2680ms", "0.5min", "1h", "2.68".
std::optional<double> smilClock(std::string_view v) {
	v = trim(v);
	double d;
	if (v.find(':') != std::string_view::npos) {
		double total = 0;
		const auto parts = split(v, ':');
		if (parts.size() > 3) return std::nullopt;
		for (const std::string& p : parts) {
			if (!parseDouble(p, d) || d < 0) return std::nullopt;
			total = total * 60 + d;
		}
		return total;
	}
	for (const auto& [unit, scale] : std::vector<std::pair<const char*, double>>{{"ms", 0.001}, {"min", 60}, {"h", 3600}, {"s", 1}})
		if (endsWith(v, unit)) return parseDouble(v.substr(0, v.size() - std::strlen(unit)), d) ? std::optional<double>(d * scale) : std::nullopt;
	return parseDouble(v, d) ? std::optional<double>(d) : std::nullopt;
}

}  // namespace

Transcript withFragmentText(const Transcript& ids, const std::string& path, const std::string& textPath) {
	const FragmentText ft = readFragmentText(textPath);
	Transcript tr = ids;
	tr.level = LabelLevel::Word;
	for (Interval& i : tr.intervals) {
		if (i.label.empty()) continue;
		const auto it = ft.byId.find(i.label);
		if (it == ft.byId.end())
			throw Error(path, i.line, "the fragment '" + safeQuote(i.label) + "' is not in " + textPath + " (read as " + ft.form + " text)");
		i.label = it->second;
	}
	tr.warnings.push_back("an aeneas sync map times sentences, not words: each sentence's phones are spread by espeak-ng's durations (approximate; talkhead align times them from the audio)");
	return tr;
}

Transcript readSmil(const std::string& text, const std::string& path, const std::string& textPath) {
	Transcript ids;
	ids.format = "smil";
	ids.level = LabelLevel::Word;
	long line = 1;
	std::size_t counted = 0;
	auto lineAt = [&](std::size_t p) {
		line += std::count(text.begin() + std::ptrdiff_t(counted), text.begin() + std::ptrdiff_t(p), '\n');
		counted = p;
		return line;
	};
	for (std::size_t p = 0; (p = text.find("<par", p)) != std::string::npos;) {
		const long here = lineAt(p);
		const std::size_t end = text.find("</par>", p);
		if (end == std::string::npos) throw Error(path, here, "a <par> that does not end");
		const std::string_view par(text.data() + p, end - p);
		p = end + 6;
		const std::size_t ts = par.find("<text"), as = par.find("<audio");
		if (ts == std::string_view::npos || as == std::string_view::npos) throw Error(path, here, "a <par> needs a <text src> and an <audio clipBegin clipEnd>");
		const std::string_view textTag = par.substr(ts, par.find('>', ts) - ts), audioTag = par.substr(as, par.find('>', as) - as);
		const auto src = attribute(textTag, "src");
		const auto b = attribute(audioTag, "clipBegin"), e = attribute(audioTag, "clipEnd");
		if (!src || src->find('#') == std::string::npos) throw Error(path, here, "<text> needs src=\"file#id\"");
		if (!b || !e) throw Error(path, here, "<audio> needs clipBegin and clipEnd");
		const auto bs = smilClock(*b), es = smilClock(*e);
		if (!bs || !es) throw Error(path, here, "clipBegin '" + safeQuote(*b) + "' or clipEnd '" + safeQuote(*e) + "' is not a SMIL clock value");
		if (*es < *bs) throw Error(path, here, "the clip ends before it begins");
		const std::string where = "line " + std::to_string(here);
		ids.intervals.push_back({timing::secondsAt(*bs, path, where), timing::secondsAt(*es, path, where), src->substr(src->find('#') + 1), here});
	}
	if (ids.intervals.empty()) throw Error(path, 0, "a SMIL file with no <par> (text and audio clip)");
	if (textPath.empty())
		throw Error(path, 0, "a SMIL sync map (aeneas, EPUB3 media overlays) names its text only by reference (<text src=\"…#" + safeQuote(ids.intervals.front().label) +
		                         "\"/>), not the words: write it as aeneas JSON, SRT or VTT, which carry the text; or give the text it refers to ({{timing-text}} FILE: the XHTML, or aeneas's plain or parsed text)");
	return withFragmentText(ids, path, textPath);
}

Transcript googleTimepoints(const JsonValue& v, const std::string& path, const std::string& ssmlPath) {
	if (ssmlPath.empty())
		throw Error(path, 0, "Google Text-to-Speech timepoints hold only the times of your SSML <mark>s, not the words: give the SSML they came from ({{timing-text}} FILE), or the audio with its text (talkhead render {{audio}} A {{text}} T aligns it)");
	std::map<std::string, double> time;
	long k = 0;
	for (const JsonValue& t : timing::array(v, "timepoints")->array) {
		const std::string here = "timepoints[" + std::to_string(k++) + "]";
		const std::string* name = timing::string(t.find("markName"));
		const auto s = timing::number(t.find("timeSeconds"));
		if (!name || !s) throw Error(path, 0, here + " needs markName and timeSeconds");
		timing::secondsAt(*s, path, here);
		time[*name] = *s;
	}
	// The SSML: its text between marks, every other tag dropped (its words kept).
	const std::string ssml = readTextFile(ssmlPath);
	struct Piece {
		std::string mark;
		std::size_t from;
		long line;
	};
	std::vector<Piece> pieces;
	std::string lang;
	for (std::size_t p = 0; (p = ssml.find('<', p)) != std::string::npos;) {
		const std::size_t e = ssml.find('>', p);
		if (e == std::string::npos) throw Error(ssmlPath, 0, "a tag that does not end");
		const std::string_view tag(ssml.data() + p + 1, e - p - 1);
		if (startsWith(tag, "speak")) {
			if (auto l = attribute(tag, "xml:lang")) lang = *l;
		} else if (startsWith(tag, "mark")) {
			const auto name = attribute(tag, "name");
			if (!name) throw Error(ssmlPath, long(std::count(ssml.begin(), ssml.begin() + std::ptrdiff_t(p), '\n') + 1), "<mark> without a name");
			pieces.push_back({*name, e + 1, long(std::count(ssml.begin(), ssml.begin() + std::ptrdiff_t(p), '\n') + 1)});
		}
		p = e + 1;
	}
	if (pieces.empty()) throw Error(ssmlPath, 0, "no <mark name=…/> in the SSML: the timepoints cannot be placed");
	Transcript tr;
	tr.format = "google";
	tr.level = LabelLevel::Word;
	const std::string before = plainOfMarkup(std::string_view(ssml).substr(0, ssml.find("<mark")));
	if (!before.empty()) tr.warnings.push_back("the words before the first <mark> ('" + safeQuote(before) + "') have no time and are left out");
	for (std::size_t i = 0; i < pieces.size(); ++i) {
		const auto t = time.find(pieces[i].mark);
		if (t == time.end()) throw Error(ssmlPath, pieces[i].line, "<mark name=\"" + safeQuote(pieces[i].mark) + "\"/> has no timepoint in " + path);
		const std::size_t to = i + 1 < pieces.size() ? ssml.rfind('<', ssml.find("<mark", pieces[i].from)) : ssml.size();
		const std::string words = plainOfMarkup(std::string_view(ssml).substr(pieces[i].from, to - pieces[i].from));
		if (words.empty()) continue;
		double end;
		if (i + 1 < pieces.size()) {
			const auto n = time.find(pieces[i + 1].mark);
			if (n == time.end()) throw Error(ssmlPath, pieces[i + 1].line, "<mark name=\"" + safeQuote(pieces[i + 1].mark) + "\"/> has no timepoint in " + path);
			end = n->second;
		} else {
			// No mark after the last words: as long as espeak-ng says them.
			double d = 0;
			for (const SpokenPhone& ph : espeakPhones(words, espeakVoiceFor(lang.empty() ? "en" : lang))) d += toSeconds(ph.duration);
			end = t->second + d;
			tr.warnings.push_back("the words after the last <mark> ('" + safeQuote(words) + "') have no end time: they last as long as espeak-ng says them (end the SSML with a <mark/>)");
		}
		if (end < t->second) throw Error(ssmlPath, pieces[i].line, "the timepoints of <mark name=\"" + safeQuote(pieces[i].mark) + "\"/> and the next mark go backwards");
		tr.intervals.push_back({timing::secondsAt(t->second, path, pieces[i].mark), timing::secondsAt(end, path, pieces[i].mark), words, pieces[i].line});
	}
	if (tr.intervals.empty()) throw Error(ssmlPath, 0, "no words after the <mark>s");
	return tr;
}

namespace {

Transcript readJsonValue(const JsonValue& v, const std::string& path, const std::string& f, const ReadOptions& o) {
	const bool object = v.kind == JsonValue::Kind::Object;
	Transcript tr;
	auto need = [&](bool ok, const char* what) {
		if (!ok) throw Error(path, 0, std::string("not a ") + f + " file: " + what);
	};
	if (f == "whisper") need(object && timing::array(v, "segments"), "no segments[]"), tr = whisper(v, path, o);
	else if (f == "openai") need(object && timing::array(v, "words"), "no words[] (ask for timestamp_granularities[]=word)"), tr = openai(v, path);
	else if (f == "deepgram") need(object, "not an object"), tr = deepgram(v, path, o);
	else if (f == "gentle") need(object && timing::array(v, "words"), "no words[]"), tr = gentle(v, path);
	else if (f == "aeneas") need(object && timing::array(v, "fragments"), "no fragments[]"), tr = aeneas(v, path);
	else if (f == "google") need(object && timing::array(v, "timepoints"), "no timepoints[]"), tr = googleTimepoints(v, path, o.timingText);
	else if (f == "mfa-json") need(object, "not an object"), tr = mfaJson(v, path);
	else if (f == "azure") tr = azureVisemes(object && v.find("visemes") ? *v.find("visemes") : v, path);
	else if (f == "azure-words") need(v.kind == JsonValue::Kind::Array, "not an array"), tr = azureWords(v, path);
	else if (f == "elevenlabs") {
		const JsonValue* a = object ? (v.find("alignment") ? v.find("alignment") : v.find("normalized_alignment")) : nullptr;
		tr = characterAlignment(a && a->kind == JsonValue::Kind::Object ? *a : v, path);
	} else
		throw Error("unknown JSON timing format '" + f + "'");
	tr.path = path;
	tr.format = f;
	if (object) {
		if (const std::string* l = timing::string(v.find("language"))) tr.language = *l;
		if (const auto d = timing::number(v.find("duration")); d && f == "openai") tr.statedDuration = *d;
	}
	if (tr.intervals.empty()) throw Error(path, 0, "the " + f + " file holds no timed " + (tr.level == LabelLevel::Phone ? "phone" : "word"));
	return tr;
}

// A JSON format's registry entry: the value parsed once by the sample.
TimingFormat jsonFormat(std::string name, std::string title, std::string level, std::string takes, int confidence, std::function<bool(const JsonValue&)> sig) {
	return timing::makeFormat(
	    name, std::move(title), {".json"}, std::move(level), std::move(takes), confidence, [sig](const TimingSample& s) { return s.json() && sig(*s.json()); },
	    [name](const TimingSample& s, const ReadOptions& o) {
		    if (!s.json()) throw Error(s.jsonError().empty() ? s.path() + ": not JSON" : s.jsonError());
		    return readJsonValue(*s.json(), s.path(), name, o);
	    });
}

bool isObject(const JsonValue& v) { return v.kind == JsonValue::Kind::Object; }

}  // namespace

void registerServiceTimingFormats(std::vector<TimingFormat>& v) {
	using timing::allHave;
	v.push_back(jsonFormat("whisper", "Whisper family JSON: openai-whisper, whisper-timestamped, WhisperX, faster-whisper (segments[].words[])", "words",
	                       "times in s; language", 2, [](const JsonValue& j) {
		                       const JsonValue* seg = timing::array(j, "segments");
		                       if (!isObject(j) || !seg || timing::array(j, "words") || j.find("transcription")) return false;
		                       if (seg->array.empty()) return j.find("text") != nullptr;
		                       return std::all_of(seg->array.begin(), seg->array.end(), [](const JsonValue& e) {
			                       return isObject(e) && (e.find("text") || (e.find("start") && e.find("end")));
		                       });
	                       }));
	v.push_back(jsonFormat("openai", "OpenAI transcription verbose_json (words[])", "words", "times in s; language; duration", 2, [](const JsonValue& j) {
		const JsonValue* w = timing::array(j, "words");
		if (!isObject(j) || !w || !allHave(*w, {"start", "end"})) return false;
		return std::all_of(w->array.begin(), w->array.end(), [](const JsonValue& e) { return e.find("word") || e.find("text"); });
	}));
	v.push_back(jsonFormat("gentle", "Gentle forced aligner JSON", "phones", "phones with durations; English", 3, [](const JsonValue& j) {
		const JsonValue* w = timing::array(j, "words");
		return isObject(j) && w && (timing::anyHave(*w, "alignedWord") || timing::anyHave(*w, "case"));
	}));
	v.push_back(jsonFormat("deepgram", "Deepgram pre-recorded answer (results.channels[])", "words", "times in s; speakers (diarize); language", 3, [](const JsonValue& j) {
		const JsonValue* r = timing::object(j, "results");
		return r && timing::array(*r, "channels");
	}));
	v.push_back(jsonFormat("aeneas", "aeneas sync map JSON (fragments[])", "sentences", "times in s; language", 3,
	                       [](const JsonValue& j) { return isObject(j) && timing::array(j, "fragments") && allHave(*timing::array(j, "fragments"), {"begin", "end"}); }));
	v.push_back(jsonFormat("mfa-json", "Montreal Forced Aligner 3.x JSON (tiers)", "phones or words", "times in s", 3,
	                       [](const JsonValue& j) { return timing::object(j, "tiers") != nullptr; }));
	v.push_back(jsonFormat("azure", "Azure Speech viseme events", "visemes (Azure's 0–21)", "offset_ms, or AudioOffset in 100 ns (the SDK)", 3, [](const JsonValue& j) {
		if (isObject(j)) return timing::array(j, "visemes") != nullptr;
		return j.kind == JsonValue::Kind::Array && (timing::anyHave(j, "VisemeId") || (timing::anyHave(j, "offset_ms") && timing::anyHave(j, "id")));
	}));
	v.push_back(jsonFormat("azure-words", "Azure Speech SDK word boundaries (AudioOffset in 100 ns)", "words", "times in 100 ns (AudioOffset), Duration as a time span or 100 ns", 3,
	                       [](const JsonValue& j) {
		                       if (j.kind != JsonValue::Kind::Array || !(timing::anyHave(j, "Text") || timing::anyHave(j, "text"))) return false;
		                       if (timing::anyHave(j, "offset_ms")) return true;
		                       if (!timing::anyHave(j, "AudioOffset")) return false;
		                       // The SDK's events carry a BoundaryType, or their Duration as a time span ("00:00:00.3"); the batch
		                       // synthesis files (milliseconds) neither.
		                       return timing::anyHave(j, "BoundaryType") || std::any_of(j.array.begin(), j.array.end(), [](const JsonValue& e) {
			                              return isObject(e) && timing::string(e.find("Duration"));
		                              });
	                       }));
	v.push_back(jsonFormat("elevenlabs", "ElevenLabs text-to-speech with timestamps (character alignment)", "words", "times in s (characters grouped into words)", 3,
	                       [](const JsonValue& j) {
		                       if (!isObject(j)) return false;
		                       if (timing::object(j, "alignment") || timing::object(j, "normalized_alignment")) return true;
		                       return timing::array(j, "characters") && timing::array(j, "character_start_times_seconds");
	                       }));
	v.push_back(jsonFormat("google", "Google Cloud Text-to-Speech timepoints (with the SSML, {{timing-text}})", "words", "times in s; the marks' SSML", 3,
	                       [](const JsonValue& j) { return isObject(j) && timing::array(j, "timepoints"); }));
	v.push_back({"srt", "SubRip subtitles", {".srt"}, "words or cues (sentences)", "times hh:mm:ss,mmm", 2,
	             [](const TimingSample& s) { return !startsWith(s.trimmed(), "WEBVTT") && looksLikeSubtitles(s.text()); },
	             [](const TimingSample& s, const ReadOptions& o) { return readSubtitles(s.text(), s.path(), o); }, ""});
	v.push_back({"vtt", "WebVTT captions (YouTube's inline word times, Teams' <v> voices)", {".vtt"}, "words or cues (sentences)",
	             "times; inline word times; language (Language:); voices as speakers", 3, [](const TimingSample& s) { return startsWith(s.trimmed(), "WEBVTT"); },
	             [](const TimingSample& s, const ReadOptions& o) { return readSubtitles(s.text(), s.path(), o); }, ""});
	v.push_back({"ctm", "NIST/Kaldi CTM (sclite, Kaldi, NeMo forced aligner)", {".ctm"}, "words or phones", "times in s; recordings and channels as speakers; alternations (first)",
	             2, [](const TimingSample& s) { return !s.looksLikeJson() && looksLikeCtm(s.text()); },
	             [](const TimingSample& s, const ReadOptions& o) { return readCtm(s.text(), s.path(), o); }, ""});
	v.push_back({"festival", "Festival utterance (EST_File utterance)", {".utt"}, "phones", "the Segment relation's end times", 3,
	             [](const TimingSample& s) { return startsWith(s.trimmed(), "EST_File utterance"); },
	             [](const TimingSample& s, const ReadOptions&) { return readFestivalUtterance(s.text(), s.path()); }, ""});
	v.push_back({"smil", "aeneas SMIL sync map (with its text, {{timing-text}})", {".smil"}, "sentences", "clip times", 3,
	             [](const TimingSample& s) { return s.xmlRoot() == "smil"; },
	             [](const TimingSample& s, const ReadOptions& o) { return readSmil(s.text(), s.path(), o.timingText); }, ""});
}

Transcript readJsonTiming(const std::string& text, const std::string& path, const std::string& format, const ReadOptions& o) {
	ReadOptions ro = o;
	ro.format = format;
	return readTimingSample(TimingSample(text, path), ro);
}

// ---- Subtitles ------------------------------------------------------------------------------------------

namespace {

// "00:00:01,660" (SRT), "00:01.660" or "00:00:01.660" (WebVTT).
std::optional<double> cueTime(std::string_view s) {
	s = trim(s);
	int h = 0, m = 0, sec = 0, frac = 0, digits = 0;
	std::vector<int> parts;
	std::size_t i = 0;
	auto num = [&](int& out) {  // at most 6 digits (no overflow)
		std::size_t start = i;
		out = 0;
		while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) {
			if (i - start >= 6) return false;
			out = out * 10 + (s[i++] - '0');
		}
		return i > start;
	};
	int a = 0;
	if (!num(a)) return std::nullopt;
	parts.push_back(a);
	while (i < s.size() && s[i] == ':') {
		++i;
		if (!num(a)) return std::nullopt;
		parts.push_back(a);
	}
	if (i >= s.size() || (s[i] != ',' && s[i] != '.')) return std::nullopt;
	++i;
	const std::size_t f0 = i;
	if (!num(frac)) return std::nullopt;
	digits = int(i - f0);
	if (i != s.size() || parts.size() < 2 || parts.size() > 3) return std::nullopt;
	if (parts.size() == 3) h = parts[0], m = parts[1], sec = parts[2];
	else m = parts[0], sec = parts[1];
	if (m > 59 || sec > 59) return std::nullopt;
	return h * 3600.0 + m * 60.0 + sec + frac / std::pow(10.0, digits);
}

// Cue text without tags (<i>, <c.x>, <v Name>, <00:00:01.000>) and entities.
std::string cueText(const std::string& raw) {
	std::string out;
	bool tag = false;
	for (char c : raw) {
		if (c == '<') tag = true;
		else if (c == '>') tag = false;
		else if (!tag) out += c;
	}
	for (const auto& [e, r] : {std::pair<const char*, const char*>{"&amp;", "&"}, {"&lt;", "<"}, {"&gt;", ">"}, {"&nbsp;", " "}, {"&lrm;", ""}, {"&rlm;", ""}})
		for (std::size_t p; (p = out.find(e)) != std::string::npos;) out.replace(p, std::strlen(e), r);
	return std::string(trim(out));
}

}  // namespace

bool looksLikeSubtitles(const std::string& text) {
	const std::string_view t = trim(text);
	if (startsWith(t, "WEBVTT")) return true;
	for (const std::string& l : split(std::string(t.substr(0, 2000)), '\n')) {
		const auto arrow = l.find("-->");
		if (arrow != std::string::npos) return cueTime(std::string_view(l).substr(0, arrow)).has_value();
	}
	return false;
}

namespace {

// "<00:05:04.199>" tags inside a cue line: the line's words, each from its tag (the first from `from`).
struct TimedPiece {
	double start;
	std::string text;
};
std::vector<TimedPiece> inlineTimes(const std::string& line, double from) {
	std::vector<TimedPiece> out{{from, ""}};
	for (std::size_t i = 0; i < line.size();) {
		if (line[i] == '<') {
			const std::size_t e = line.find('>', i);
			if (e == std::string::npos) break;
			if (const auto t = cueTime(std::string_view(line).substr(i + 1, e - i - 1))) out.push_back({*t, ""});
			i = e + 1;
			continue;
		}
		out.back().text += line[i++];
	}
	return out;
}

bool hasInlineTime(const std::string& line) {
	for (std::size_t p = 0; (p = line.find('<', p)) != std::string::npos; ++p) {
		const std::size_t e = line.find('>', p);
		if (e != std::string::npos && cueTime(std::string_view(line).substr(p + 1, e - p - 1))) return true;
	}
	return false;
}

// A WebVTT voice: "<v Anna>" or "<v.loud Anna>".
std::string voiceOf(const std::string& body) {
	const auto p = body.find("<v");
	if (p == std::string::npos || p + 2 >= body.size() || (body[p + 2] != ' ' && body[p + 2] != '.')) return "";
	const auto e = body.find('>', p);
	if (e == std::string::npos) return "";
	std::string inside = body.substr(p + 2, e - p - 2);
	if (!inside.empty() && inside[0] == '.') inside = inside.substr(std::min(inside.size(), inside.find(' ')));
	return std::string(trim(inside));
}

}  // namespace

Transcript readSubtitles(const std::string& text, const std::string& path, const ReadOptions& o) {
	Transcript tr;
	const bool vtt = startsWith(trim(text), "WEBVTT");
	tr.format = vtt ? "vtt" : "srt";
	tr.level = LabelLevel::Word;
	std::vector<std::string> ls = split(text, '\n');
	for (std::string& l : ls)
		if (!l.empty() && l.back() == '\r') l.pop_back();
	struct Cue {
		double a, b;
		std::vector<std::string> lines;
		long no;
	};
	std::vector<Cue> cues;
	auto timing = [&](const std::string& l, long no) -> std::optional<std::pair<double, double>> {
		const auto arrow = l.find("-->");
		if (arrow == std::string::npos) return std::nullopt;
		const auto a = cueTime(std::string_view(l).substr(0, arrow));
		std::string rest(trim(std::string_view(l).substr(arrow + 3)));
		const auto sp = rest.find_first_of(" \t");  // WebVTT cue settings after the end time
		const auto b = cueTime(sp == std::string::npos ? std::string_view(rest) : std::string_view(rest).substr(0, sp));
		if (!a || !b) throw Error(path, no, "expected 'START --> END' cue times (00:00:01,660 or 00:01.660), found '" + safeQuote(l) + "'");
		if (*b < *a) throw Error(path, no, "the cue ends before it starts");
		if (*b > kMaxSeconds) throw Error(path, no, "a cue after 86400 s (a day)");
		return std::make_pair(*a, *b);
	};
	for (std::size_t i = 0; i < ls.size(); ++i) {
		const auto t = timing(ls[i], long(i + 1));
		if (!t) continue;
		Cue c{t->first, t->second, {}, long(i + 1)};
		std::size_t j = i + 1;
		// The body ends at a blank line — or at the next timing line, which some writers put right after it.
		for (; j < ls.size() && !trim(ls[j]).empty() && ls[j].find("-->") == std::string::npos; ++j) c.lines.push_back(ls[j]);
		cues.push_back(std::move(c));
		i = (j < ls.size() && ls[j].find("-->") != std::string::npos) ? j - 1 : j;
	}
	if (cues.empty()) throw Error(path, 0, std::string("no cues ('START --> END' lines) in this ") + (vtt ? "WebVTT" : "SubRip") + " file");

	// Voices (<v Name>, Teams and others): the speakers. Zoom and others write "Name: text" instead: when most
	// cues start so and two names or more do, those are the speakers (the name is not spoken).
	std::vector<std::string> voices;
	for (const Cue& c : cues)
		for (const std::string& l : c.lines)
			if (const std::string v = voiceOf(l); !v.empty() && std::find(voices.begin(), voices.end(), v) == voices.end()) voices.push_back(v);
	std::vector<std::string> named(cues.size());
	if (voices.empty()) {
		std::size_t labelled = 0;
		std::vector<std::string> names;
		for (std::size_t k = 0; k < cues.size(); ++k) {
			if (cues[k].lines.empty()) continue;
			const std::string first = cueText(cues[k].lines.front());
			if (const std::size_t n = speakerLabelLength(first)) {
				std::string name(trim(std::string_view(first).substr(0, n - 1)));
				if (startsWith(name, ">>")) name = std::string(trim(std::string_view(name).substr(2)));
				named[k] = name;
				++labelled;
				if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
			}
		}
		if (names.size() >= 2 && labelled * 2 >= cues.size()) voices = names;
		else named.assign(cues.size(), "");
	}
	tr.speakers = voices;
	tr.speaker = timing::chooseSpeaker(voices, o, path, "voice");

	const bool inlineTimed = std::any_of(cues.begin(), cues.end(), [](const Cue& c) { return std::any_of(c.lines.begin(), c.lines.end(), hasInlineTime); });
	bool sentences = false;
	if (inlineTimed) {
		// Rolling auto-captions (YouTube): a line with inline word times holds new words, each from its time to
		// the next; lines that repeat what was shown before are left out.
		std::string last;
		std::size_t repeats = 0;
		for (const Cue& c : cues) {
			for (const std::string& l : c.lines) {
				const std::string plain = cueText(l);
				if (plain.empty()) continue;
				if (plain == last) {
					++repeats;
					continue;
				}
				if (hasInlineTime(l)) {
					const auto pieces = inlineTimes(l, c.a);
					for (const TimedPiece& p : pieces)
						if (p.start > kMaxSeconds) throw Error(path, c.no, "an inline word time after 86400 s (a day)");
					for (std::size_t k = 0; k < pieces.size(); ++k) {
						const std::string w = cueText(pieces[k].text);
						if (w.empty()) continue;
						const double end = k + 1 < pieces.size() ? pieces[k + 1].start : c.b;
						tr.intervals.push_back({ticksFromSeconds(pieces[k].start), ticksFromSeconds(std::max(end, pieces[k].start)), w, c.no});
					}
				} else {
					tr.intervals.push_back({ticksFromSeconds(c.a), ticksFromSeconds(c.b), plain, c.no});
					sentences |= plain.find(' ') != std::string::npos;
				}
				last = plain;
			}
		}
		// A cue's last word ends where the cue does, which may be where it starts: it lasts until the next word
		// (at most 0.4 s).
		for (std::size_t k = 0; k < tr.intervals.size(); ++k) {
			Interval& iv = tr.intervals[k];
			if (iv.end > iv.start) continue;
			const Ticks cap = iv.start + Ticks(kTicksPerSecond * 4 / 10);
			iv.end = k + 1 < tr.intervals.size() ? std::min(cap, std::max(iv.start, tr.intervals[k + 1].start)) : cap;
		}
		if (repeats) tr.warnings.push_back(std::to_string(repeats) + " repeated caption line" + (repeats > 1 ? "s" : "") + " (rolling captions) left out; words timed by their inline times");
	} else {
		// whisper --highlight_words: each word's cue repeats its segment with the word in <u>…</u>, and the cues
		// between words hold the segment without one. The underlined word is what is said then.
		const bool highlighted = std::any_of(cues.begin(), cues.end(), [](const Cue& c) {
			return std::any_of(c.lines.begin(), c.lines.end(), [](const std::string& l) { return l.find("<u>") != std::string::npos; });
		});
		std::size_t gaps = 0;
		for (std::size_t ci = 0; ci < cues.size(); ++ci) {
			const Cue& c = cues[ci];
			std::string body;
			std::string voice = named[ci];
			for (const std::string& l : c.lines) {
				if (const std::string v = voiceOf(l); !v.empty()) voice = v;
				body += (body.empty() ? "" : " ") + l;
			}
			if ((voices.size() > 1 || !o.tier.empty()) && voice != tr.speaker) continue;
			if (highlighted) {
				std::string words;
				for (std::size_t p = 0; (p = body.find("<u>", p)) != std::string::npos;) {
					const auto e = body.find("</u>", p);
					if (e == std::string::npos) break;
					words += (words.empty() ? "" : " ") + body.substr(p + 3, e - p - 3);
					p = e;
				}
				if (words.empty()) {
					++gaps;
					continue;
				}
				body = words;
			}
			body = cueText(body);
			sentences |= body.find(' ') != std::string::npos;
			tr.intervals.push_back({ticksFromSeconds(c.a), ticksFromSeconds(c.b), body, c.no});
		}
		if (highlighted)
			tr.warnings.push_back("words highlighted with <u> (whisper's highlight_words): each underlined word over its cue; " + std::to_string(gaps) +
			                      " cue" + (gaps == 1 ? "" : "s") + " between words left out");
	}
	// Cues overlapping (karaoke-style rolling captions) cannot be one mouth: the later starts where the earlier ends.
	std::stable_sort(tr.intervals.begin(), tr.intervals.end(), [](const Interval& x, const Interval& y) { return x.start < y.start; });
	for (std::size_t k = 1; k < tr.intervals.size(); ++k)
		if (tr.intervals[k].start < tr.intervals[k - 1].end) {
			char b[200];
			std::snprintf(b, sizeof b, "cue at %.3f s overlaps the one before (line %ld): captions that roll or repeat are not one speaker's timing", toSeconds(tr.intervals[k].start),
			              tr.intervals[k - 1].line);
			throw Error(path, tr.intervals[k].line, b);
		}
	if (sentences)
		tr.warnings.push_back("cues hold several words: each cue's phones are spread by espeak-ng's durations (approximate; word-level cues, or talkhead align on the audio, time them)");
	return tr;
}

// ---- CTM ----------------------------------------------------------------------------------------------

namespace {

std::size_t codePointCount(const std::string& s) {
	return std::size_t(std::count_if(s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

struct CtmRow {
	std::string utterance, channel, label;
	double start = 0, duration = 0;
	long line = 0;
};

// A CTM row: "utterance channel start duration label [confidence [type [speaker …]]]" (NeMo adds columns
// and writes NA for a missing confidence). sclite's alternations ("* * <ALT_BEGIN>") come back with
// `alternation` set.
std::optional<CtmRow> ctmRow(const std::string& line, long no, bool* alternation = nullptr) {
	const auto f = splitWhitespace(line);
	if (alternation) *alternation = false;
	if (f.size() < 5 || f.size() > 10) return std::nullopt;
	CtmRow r;
	double d;
	long long ch;
	if (parseDouble(f[0], d) && f[0].find('.') != std::string::npos) return std::nullopt;  // a time, not an id
	if (!parseInt(f[1], ch) && !(f[1].size() == 1 && std::isalpha(static_cast<unsigned char>(f[1][0])))) return std::nullopt;
	if (f[2] == "*" && f[3] == "*" && (f[4] == "<ALT_BEGIN>" || f[4] == "<ALT>" || f[4] == "<ALT_END>")) {
		if (alternation) *alternation = true;
		r.utterance = f[0], r.channel = f[1], r.label = f[4], r.line = no;
		return r;
	}
	if (!parseDouble(f[2], r.start) || !parseDouble(f[3], r.duration)) return std::nullopt;
	if (f.size() >= 6 && !parseDouble(f[5], d) && f[5] != "-" && f[5] != "NA") return std::nullopt;  // confidence
	r.utterance = f[0], r.channel = f[1], r.label = f[4], r.line = no;
	return r;
}

}  // namespace

bool looksLikeCtm(const std::string& text) {
	// Every row shaped like CTM, and either one recording's id on all of them or a word (not a number) in the
	// label column: a .pho line "a 100 50 120" has numbers there, and a phone of its own on each line.
	int rows = 0;
	bool sameUtterance = true, wordLabels = true;
	std::string utterance;
	long no = 0;
	const std::size_t cut = text.size() <= 100000 ? text.size() : text.rfind('\n', 100000);
	for (const std::string& l : split(std::string_view(text).substr(0, cut == std::string::npos ? 0 : cut), '\n')) {
		++no;
		const std::string_view t = trim(l);
		if (t.empty() || t[0] == ';' || t[0] == '#') continue;
		bool alt = false;
		const auto r = ctmRow(std::string(t), no, &alt);
		if (!r) return false;
		if (alt) continue;
		double d;
		wordLabels &= !parseDouble(r->label, d);
		sameUtterance &= rows == 0 || r->utterance == utterance;
		utterance = r->utterance;
		if (++rows >= 50) break;
	}
	return rows > 0 && ((sameUtterance && rows >= 2) || wordLabels);
}

Transcript readCtm(const std::string& text, const std::string& path, const ReadOptions& o) {
	std::vector<CtmRow> rows;
	long no = 0;
	int alternations = 0;
	enum { Outside, First, Other } alt = Outside;
	for (const std::string& l : split(text, '\n')) {
		++no;
		const std::string_view t = trim(l);
		if (t.empty() || t[0] == ';' || t[0] == '#') continue;
		bool isAlt = false;
		const auto r = ctmRow(std::string(t), no, &isAlt);
		if (!r) throw Error(path, no, "expected 'utterance channel start duration label [confidence]', found '" + safeQuote(std::string(t)) + "'");
		if (isAlt) {
			// sclite alternations: the first alternative is read, the others left out.
			if (r->label == "<ALT_BEGIN>") alt = First, ++alternations;
			else if (r->label == "<ALT>") alt = Other;
			else alt = Outside;
			continue;
		}
		if (alt == Other) continue;
		if (!std::isfinite(r->start) || !std::isfinite(r->duration) || r->start < 0 || r->duration < 0)
			throw Error(path, no, "start and duration must be numbers from 0 (seconds)");
		rows.push_back(*r);
	}
	if (rows.empty()) throw Error(path, 0, "no CTM rows");
	// Recordings and channels: each "recording channel" pair is a speaker to choose.
	std::vector<std::string> speakers;
	for (const CtmRow& r : rows) {
		const std::string name = r.utterance + " " + r.channel;
		if (std::find(speakers.begin(), speakers.end(), name) == speakers.end()) speakers.push_back(name);
	}
	Transcript tr;
	tr.format = "ctm";
	tr.speakers = speakers.size() > 1 ? speakers : std::vector<std::string>{};
	ReadOptions pick = o;
	// A channel alone ("A") picks it when there is one recording; "2347:A" and "2347/A" as "2347 A".
	for (char sep : {':', '/', '_'})
		if (const auto p = pick.tier.find(sep); p != std::string::npos) pick.tier[p] = ' ';
	if (!pick.tier.empty() && pick.tier.find(' ') == std::string::npos)
		for (const std::string& s : speakers)
			if (s.substr(s.find(' ') + 1) == pick.tier && rows[0].utterance == s.substr(0, s.find(' '))) pick.tier = s;
	if (speakers.size() > 1 || !o.tier.empty()) tr.speaker = timing::chooseSpeaker(speakers, pick, path, "recording and channel");
	// Phones when the labels are (Kaldi's phone CTMs carry position suffixes: AH1_I), else words.
	int phones = 0, total = 0;
	for (CtmRow& r : rows) {
		r.label = withoutPositionSuffix(r.label);
		if (isPauseLabel(r.label)) continue;
		++total;
		phones += o.knownPhone ? o.knownPhone(r.label) : codePointCount(r.label) <= 3;
	}
	tr.level = total > 0 && phones * 4 >= total * 3 ? LabelLevel::Phone : LabelLevel::Word;
	tr.levelGuessed = true;
	for (const CtmRow& r : rows) {
		if (!tr.speaker.empty() && r.utterance + " " + r.channel != tr.speaker) continue;
		if (r.start + r.duration > kMaxSeconds) throw Error(path, r.line, "a time after 86400 s (a day)");
		// sclite escapes a ';' in a word as "\;".
		std::string label = r.label;
		for (std::size_t p; (p = label.find("\\;")) != std::string::npos;) label.replace(p, 2, ";");
		tr.intervals.push_back({ticksFromSeconds(r.start), ticksFromSeconds(r.start + r.duration), label, r.line});
	}
	if (alternations) tr.warnings.push_back(std::to_string(alternations) + " alternation" + (alternations > 1 ? "s" : "") + " (<ALT_BEGIN>): the first alternative read");
	return tr;
}

std::optional<std::string> timingFileLanguage(const std::string& text) {
	const TimingSample sample(text, "");
	const std::string stated = statedLanguage(sample);
	if (stated.empty()) return std::nullopt;
	const std::string tag = languageTagOf(stated);
	return tag.empty() ? std::nullopt : std::optional<std::string>(tag);
}

}  // namespace talkhead

namespace talkhead {

// Festival's utterance file (EST_File utterance, ascii): the items' features, then each relation's nodes in
// order; the Segment relation's items are the phones, each with its "end" time (start: the one before's end).
Transcript readFestivalUtterance(const std::string& text, const std::string& path) {
	std::map<long, std::pair<std::string, std::optional<double>>> items;  // item number → name, end
	std::vector<std::pair<long, long>> segment;                            // relation order: item, line
	enum { Header, Items, Relation, Other } where = Header;
	long no = 0;
	for (const std::string& raw : split(text, '\n')) {
		++no;
		const std::string l(trim(raw));
		if (l == "Stream_Items") { where = Items; continue; }
		if (startsWith(l, "Relation ")) { where = startsWith(l, "Relation Segment ") ? Relation : Other; continue; }
		if (l == "End_of_Relation" || l == "End_of_Stream_Items") { where = Other; continue; }
		if (where == Items) {
			const auto f = splitWhitespace(l);
			long long n;
			if (f.empty() || !parseInt(f[0], n)) continue;
			std::string name;
			std::optional<double> end;
			for (const std::string& kv : split(l.substr(f[0].size()), ';')) {
				const auto g = splitWhitespace(kv);
				double d;
				if (g.size() >= 2 && g[0] == "name") name = g[1];
				if (g.size() >= 2 && g[0] == "end" && parseDouble(g[1], d)) end = d;
			}
			items[long(n)] = {name, end};
		} else if (where == Relation) {
			const auto f = splitWhitespace(l);
			long long node, item;
			if (f.size() >= 2 && parseInt(f[0], node) && parseInt(f[1], item)) segment.push_back({long(item), no});
		}
	}
	if (segment.empty()) throw Error(path, 0, "a Festival utterance without a Segment relation (no phones with times): save it after synthesis (utt.save)");
	Transcript tr;
	tr.format = "festival";
	tr.level = LabelLevel::Phone;
	double start = 0;
	for (const auto& [item, line] : segment) {
		auto it = items.find(item);
		if (it == items.end() || !it->second.second) throw Error(path, line, "segment item " + std::to_string(item) + " has no 'end' time");
		const double end = *it->second.second;
		if (end < start || end > 86400) throw Error(path, line, "segment '" + safeQuote(it->second.first) + "' ends before the one before it, or after a day");
		tr.intervals.push_back({ticksFromSeconds(start), ticksFromSeconds(end), it->second.first, line});
		start = end;
	}
	return tr;
}

}  // namespace talkhead
