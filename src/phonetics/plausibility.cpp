// SPDX-License-Identifier: GPL-3.0-or-later
// The plausibility gate and the cleaning of labels that are not speech (issue 50, D96).
#include "phonetics/plausibility.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <vector>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/language.h"

namespace talkhead {

namespace {

// Words of a label: white-space separated; a label of CJK characters (no spaces) counts one per character.
int wordsOf(const std::string& label) {
	const auto w = splitWhitespace(label);
	int n = 0;
	for (const std::string& t : w) {
		int cjk = 0;
		for (std::size_t i = 0; i < t.size();) {
			const unsigned char c = static_cast<unsigned char>(t[i]);
			if (c >= 0xE3 && c <= 0xE9 && i + 2 < t.size()) ++cjk, i += 3;  // U+3000–U+9FFF: kana, CJK ideographs
			else ++i;
		}
		n += std::max(1, cjk);
	}
	return std::max(1, n);
}

struct Measure {
	int units = 0;          // phones, words or visemes spoken
	double median = 0;      // median seconds per unit
	double densest = 0;     // most units in any 2 s (by their starts)
	double end = 0;         // the last labelled end, s
	double speech = 0;      // seconds of labelled intervals
};

Measure measure(const Transcript& tr, double scale) {
	Measure m;
	std::vector<double> per, starts;
	for (const Interval& iv : tr.intervals) {
		if (isPauseLabel(iv.label)) continue;
		const double a = toSeconds(iv.start) * scale, b = toSeconds(iv.end) * scale;
		const int n = tr.level == LabelLevel::Word ? wordsOf(iv.label) : 1;
		m.units += n;
		for (int k = 0; k < n; ++k) {
			per.push_back((b - a) / n);
			starts.push_back(a + (b - a) * k / n);
		}
		m.end = std::max(m.end, b);
		m.speech += b - a;
	}
	if (per.empty()) return m;
	std::nth_element(per.begin(), per.begin() + std::ptrdiff_t(per.size() / 2), per.end());
	m.median = per[per.size() / 2];
	std::sort(starts.begin(), starts.end());
	std::size_t j = 0;
	for (std::size_t i = 0; i < starts.size(); ++i) {
		while (starts[i] - starts[j] >= 2.0) ++j;
		m.densest = std::max(m.densest, double(i - j + 1));
	}
	return m;
}

struct Bounds {
	double minMedian, maxMedian, maxIn2s;
	const char* unit;
};
Bounds boundsFor(LabelLevel level) {
	switch (level) {
		case LabelLevel::Phone: return {0.012, 1.0, 50, "phone"};
		case LabelLevel::Word: return {0.020, 5.0, 25, "word"};
		case LabelLevel::Viseme: return {0.012, 2.0, 50, "viseme"};
	}
	return {0.012, 1.0, 50, "phone"};
}

// Empty when plausible; else what is not.
std::string implausible(const Measure& m, const Bounds& b, std::optional<double> duration, const char* durationFrom) {
	char buf[240];
	if (m.median < b.minMedian) {
		std::snprintf(buf, sizeof buf, "the median %s lasts %.3g ms (at least %.0f ms is speech)", b.unit, m.median * 1000, b.minMedian * 1000);
		return buf;
	}
	if (m.median > b.maxMedian) {
		std::snprintf(buf, sizeof buf, "the median %s lasts %.4g s (at most %.0f s is speech)", b.unit, m.median, b.maxMedian);
		return buf;
	}
	// A rate is only a rate over a few units; a single densely packed cluster of visemes at the start of a cue is not.
	if (m.units >= 8 && m.densest > b.maxIn2s) {
		std::snprintf(buf, sizeof buf, "%.0f %ss start within 2 s (at most %.0f is speech)", m.densest, b.unit, b.maxIn2s);
		return buf;
	}
	if (duration && m.end > *duration * 1.1 + 0.5) {
		std::snprintf(buf, sizeof buf, "it ends at %.4g s, past the %.4g s %s states", m.end, *duration, durationFrom);
		return buf;
	}
	return "";
}

}  // namespace

std::string checkTimingPlausibility(const Transcript& tr, std::optional<double> audioSeconds) {
	const Bounds b = boundsFor(tr.level);
	const std::optional<double> duration = audioSeconds ? audioSeconds : tr.statedDuration;
	const char* from = audioSeconds ? "audio" : "file";
	const Measure m = measure(tr, 1.0);
	if (m.units == 0) return "no speech to check";
	const std::string why = implausible(m, b, duration, from);
	char verdict[300];
	if (why.empty()) {
		char within[80] = "";
		if (duration) std::snprintf(within, sizeof within, ", within the %s's %g s", from, *duration);
		std::snprintf(verdict, sizeof verdict, "plausible: %d %ss over %.2f s (median %.0f ms, at most %.0f in any 2 s)%s", m.units, b.unit, m.end, m.median * 1000,
		              m.densest, within);
		return verdict;
	}
	// The unit the times look like: the first scale under which they pass.
	struct Scale {
		double factor;
		std::string name;
	};
	const std::string as = tr.unit == "s" ? "seconds" : tr.unit;
	std::vector<Scale> scales = {{1e-3, tr.unit == "s" ? "milliseconds" : "1000 times too long for " + as},
	                             {1e3, tr.unit == "ms" ? "seconds" : "1000 times too short for " + as + " (seconds where milliseconds were expected?)"},
	                             {1e-7, "100-ns ticks"}};
	for (int rate : {8000, 16000, 20000, 22050, 44100, 48000}) scales.push_back({1.0 / rate, "samples at " + std::to_string(rate) + " Hz"});
	for (const Scale& s : scales) {
		const Measure scaled = measure(tr, s.factor);
		if (!implausible(scaled, b, duration, from).empty()) continue;
		const std::string& name = s.name;
		throw Error(tr.path, 0, "times read as " + as + " are not speech: " + why + "; they look like " + name + " (the median " + b.unit + " then lasts " +
		                            std::to_string(int(std::lround(scaled.median * 1000))) + " ms): export the file in its tool's own unit, or name the format with {{format}}");
	}
	throw Error(tr.path, 0, "times read as " + as + " are not speech: " + why + " — check the file and its format ({{format}})");
}

// ---- Labels that are not speech ------------------------------------------------------------------------

namespace {

bool isUpperStart(const std::string& w) {
	if (w.empty()) return false;
	const unsigned char c = static_cast<unsigned char>(w[0]);
	return std::isupper(c) || c == '(' || c >= 0xC3;  // accented capitals: trusted as names
}

}  // namespace

// "NAME:" at the start of a cue: 1–6 capitalised words (or words in parentheses), the colon right after the
// name, and text after it. Returns the length to drop, 0 when there is none.
std::size_t speakerLabelLength(const std::string& label) {
	std::size_t start = 0;
	if (startsWith(label, ">>")) start = 2;
	const auto colon = label.find(':', start);
	if (colon == std::string::npos || colon > start + 60 || colon + 1 >= label.size() || label[colon + 1] != ' ') return 0;
	const std::string name(trim(std::string_view(label).substr(start, colon - start)));
	if (name.empty()) return 0;
	if (name.find_first_of(".?!,;\"") != std::string::npos) return 0;
	const auto words = splitWhitespace(name);
	if (words.size() > 6) return 0;
	int upper = 0;
	for (const std::string& w : words) {
		if (std::any_of(w.begin(), w.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) return 0;
		upper += isUpperStart(w);
	}
	const std::string after(trim(std::string_view(label).substr(colon + 1)));
	if (splitWhitespace(after).size() < 1) return 0;
	// Capitalised name words, a lower-case particle or two allowed ("Leader of the Opposition").
	if (upper == 0 || upper * 2 < int(words.size())) return 0;
	return colon + 1;
}

namespace {

// Removes [..], (..) and {..} spans of words ("[Applause.]", "(laughs)", "{\an8}"); a span with a digit
// ("(444) 814-9913", a phone number) is speech: only its brackets go. Returns how many spans were removed.
int dropBracketed(std::string& s) {
	int n = 0;
	for (const auto& [open, close] : {std::pair<char, char>{'[', ']'}, {'(', ')'}, {'{', '}'}}) {
		for (std::size_t from = 0, a; (a = s.find(open, from)) != std::string::npos;) {
			const std::size_t b = s.find(close, a + 1);
			if (b == std::string::npos) break;
			const std::string inside = s.substr(a + 1, b - a - 1);
			const bool code = open == '{' && !inside.empty() && inside[0] == '\\';  // {\an8}: an override code
			if (!code && std::any_of(inside.begin(), inside.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
				s.replace(a, b - a + 1, inside);
				from = a + inside.size();
				continue;
			}
			s.replace(a, b - a + 1, " ");
			from = a + 1;
			++n;
		}
	}
	return n;
}

bool toneSyllable(const std::string& w) {
	if (w.size() < 2) return false;
	const char d = w.back();
	if (d < '1' || d > '5') return false;
	return std::all_of(w.begin(), w.end() - 1, [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == ':'; });
}

}  // namespace

void cleanSpeechLabels(Transcript& tr) {
	if (tr.level != LabelLevel::Word) return;
	int events = 0, speakers = 0, tones = 0, syllables = 0, words = 0;
	for (const Interval& iv : tr.intervals)
		for (const std::string& w : splitWhitespace(iv.label)) {
			++words;
			syllables += toneSyllable(w);
		}
	const bool pinyin = words >= 2 && syllables * 2 > words;
	for (Interval& iv : tr.intervals) {
		std::string l = iv.label;
		if (l.empty()) continue;
		if (isPauseLabel(l)) {
			// A whole label in brackets of words ("[Applause.]", "(laughs)"): a sound event, a pause. Pause words
			// (sil, sp, <unk>, {LG}, [SIL]) stay as written.
			const char f = l.front();
			if (f == '(' || (f == '[' && std::any_of(l.begin(), l.end(), [](char c) { return std::islower(static_cast<unsigned char>(c)); }))) {
				++events;
				iv.label = "";
			}
			continue;
		}
		if (const std::size_t p = speakerLabelLength(l)) {
			l = l.substr(p);
			++speakers;
		}
		if (l.find_first_of("[({") != std::string::npos) events += dropBracketed(l);
		if (startsWith(trim(l), "- ")) l = std::string(trim(l)).substr(2);  // a dialogue dash
		if (pinyin) {
			std::string out;
			for (std::string w : splitWhitespace(l)) {
				if (toneSyllable(w)) w.pop_back(), ++tones;
				out += (out.empty() ? "" : " ") + w;
			}
			l = out;
		}
		// What is left of the label: collapsed, and a pause when nothing speakable remains.
		std::string collapsed;
		for (const std::string& w : splitWhitespace(l)) collapsed += (collapsed.empty() ? "" : " ") + w;
		const bool speakable = std::any_of(collapsed.begin(), collapsed.end(), [](char c) {
			return std::isalnum(static_cast<unsigned char>(c)) || (static_cast<unsigned char>(c) & 0x80);
		});
		iv.label = speakable ? collapsed : "";
	}
	if (events) tr.warnings.push_back(std::to_string(events) + " bracketed sound event" + (events > 1 ? "s" : "") + " or note" + (events > 1 ? "s" : "") + " ([Applause], (laughs)) not spoken: pauses");
	if (speakers) tr.warnings.push_back(std::to_string(speakers) + " speaker label" + (speakers > 1 ? "s" : "") + " at the start of a cue (\"NAME:\") not spoken");
	if (tones) tr.warnings.push_back(std::to_string(tones) + " pinyin tone number" + (tones > 1 ? "s" : "") + " dropped (ni3 → ni)");
}

std::string languageTagOf(const std::string& raw) {
	std::string l = toLower(trim(raw));
	std::replace(l.begin(), l.end(), '_', '-');
	if (l.empty()) return "";
	static const std::pair<const char*, const char*> names[] = {
	    {"english", "en"}, {"eng", "en"}, {"french", "fr"}, {"fra", "fr"}, {"fre", "fr"}, {"german", "de"}, {"deu", "de"}, {"ger", "de"},
	    {"spanish", "es"}, {"spa", "es"}, {"italian", "it"}, {"ita", "it"}, {"portuguese", "pt"}, {"por", "pt"}, {"chinese", "zh"},
	    {"zho", "zh"}, {"chi", "zh"}, {"cmn", "zh"}, {"mandarin", "zh"}, {"yue", "yue"}, {"cantonese", "yue"}, {"japanese", "ja"}, {"jpn", "ja"},
	    {"korean", "ko"}, {"kor", "ko"}, {"russian", "ru"}, {"rus", "ru"}, {"arabic", "ar"}, {"ara", "ar"}, {"hindi", "hi"}, {"hin", "hi"},
	    {"dutch", "nl"}, {"nld", "nl"}, {"dut", "nl"}, {"polish", "pl"}, {"pol", "pl"}, {"turkish", "tr"}, {"tur", "tr"}, {"vietnamese", "vi"},
	    {"vie", "vi"}, {"swedish", "sv"}, {"swe", "sv"}, {"danish", "da"}, {"dan", "da"}, {"finnish", "fi"}, {"fin", "fi"}, {"greek", "el"},
	    {"ell", "el"}, {"gre", "el"}, {"czech", "cs"}, {"ces", "cs"}, {"cze", "cs"}, {"ukrainian", "uk"}, {"ukr", "uk"}, {"norwegian", "no"},
	    {"nor", "no"}, {"nob", "nb"}, {"catalan", "ca"}, {"cat", "ca"}, {"hebrew", "he"}, {"heb", "he"}, {"indonesian", "id"}, {"ind", "id"},
	    {"thai", "th"}, {"tha", "th"}, {"romanian", "ro"}, {"ron", "ro"}, {"rum", "ro"}, {"hungarian", "hu"}, {"hun", "hu"}};
	const std::string primary = l.substr(0, l.find('-'));
	std::string code;
	for (const auto& [k, v] : names)
		if (l == k || primary == k) code = v;
	if (code.empty()) {
		if (primary.size() < 2 || primary.size() > 3 || !std::all_of(primary.begin(), primary.end(), [](char c) { return c >= 'a' && c <= 'z'; })) return "";
		code = primary;
	}
	// The tables talkhead has: the region the file names when there is one (en-US), else the table's.
	const std::string region = l.find('-') == std::string::npos ? "" : l.substr(l.find('-'));
	for (const std::string& a : Language::available()) {
		const std::string al = toLower(a);
		if (al == code + region || al == code) return a;
	}
	for (const std::string& a : Language::available())
		if (toLower(a).substr(0, toLower(a).find('-')) == code) return a;
	return code;
}

}  // namespace talkhead
