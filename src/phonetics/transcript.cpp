// SPDX-License-Identifier: GPL-3.0-or-later
// Timed-transcript readers: Praat TextGrid (long and short text, UTF-8/UTF-16), MBROLA .pho, HTK .lab
// and MLF, GRID .align, speech-marks JSON lines (Polly), plain TSV, Rhubarb mouth cues (TSV and JSON).
#include "phonetics/transcript.h"
#include "phonetics/timing_formats.h"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <set>
#include <sstream>

#include "base/error.h"
#include "base/json.h"
#include "base/text.h"

namespace talkhead {

const std::vector<std::string>& transcriptFormats() {
	static const std::vector<std::string> f = [] {
		std::vector<std::string> v = {"textgrid", "pho", "htk", "grid", "timit", "xlabel", "marks", "tsv", "rhubarb-tsv", "rhubarb-json", "srt", "vtt", "ctm", "festival", "smil"};
		for (const std::string& j : jsonTimingFormats()) v.push_back(j);
		return v;
	}();
	return f;
}

namespace {

constexpr std::int64_t kTicksPerMs = kTicksPerSecond / 1000;
constexpr std::int64_t kTicksPerGridUnit = kTicksPerSecond / 25000;  // 1/1000 of a 25 fps frame = 40 µs

struct Line {
	long no;
	std::string text;  // trimmed, CR removed
};
std::vector<Line> lines(const std::string& text) {
	std::vector<Line> out;
	long n = 0;
	for (std::string l : split(text, '\n')) {
		++n;
		if (!l.empty() && l.back() == '\r') l.pop_back();
		out.push_back({n, std::string(trim(l))});
	}
	return out;
}

// One limit for every reader (issue 15 item 4): a transcript time is finite, ≥ 0 and at most a day, and is
// checked before it becomes ticks (1e20 s would overflow the 64-bit tick count).
constexpr double kMaxTranscriptSeconds = 86400;
Ticks boundedSeconds(double v, const std::string& path, long line, const std::string& what) {
	if (!std::isfinite(v)) throw Error(path, line, what + " is not a number");
	if (v < 0) throw Error(path, line, what + " is negative (" + std::to_string(v) + " s)");
	if (v > kMaxTranscriptSeconds) throw Error(path, line, what + " is absurd (" + std::to_string(v) + " s; at most 86400 s, a day)");
	return ticksFromSeconds(v);
}

Ticks seconds(const std::string& path, long line, const std::string& s, const char* what) {
	double v;
	if (!parseDouble(s, v)) throw Error(path, line, std::string("expected ") + what + " in seconds, found '" + s + "'");
	if (v < 0) throw Error(path, line, std::string(what) + " is negative (" + s + ")");
	if (v > 86400) throw Error(path, line, std::string(what) + " is absurd (" + s + " s)");
	return ticksFromSeconds(v);
}

Ticks integerUnits(const std::string& path, long line, const std::string& s, double ticksPerUnit, const char* what) {
	long long v;
	if (!parseInt(s, v)) throw Error(path, line, std::string("expected ") + what + " as an integer, found '" + s + "'");
	if (v < 0) throw Error(path, line, std::string(what) + " is negative (" + s + ")");
	if (double(v) * ticksPerUnit / double(kTicksPerSecond) > 86400) throw Error(path, line, std::string(what) + " is absurd (" + s + ")");
	return Ticks(std::llround(double(v) * ticksPerUnit));
}

// ---- Praat TextGrid ------------------------------------------------------------------------------
// Long and short text forms carry the same sequence of values (numbers, quoted strings, <exists>);
// the long form adds "key =" names and "[n]:" headings, which the tokenizer skips.
struct Token {
	enum Kind { Number, String, Flag } kind;
	std::string text;
	long line;
};

std::vector<Token> textGridTokens(const std::string& t, const std::string& path) {
	std::vector<Token> out;
	long line = 1;
	std::size_t i = 0;
	while (i < t.size()) {
		const char c = t[i];
		if (c == '\n') {
			++line;
			++i;
		} else if (c == '"') {
			std::string s;
			const long startLine = line;
			++i;
			for (;;) {
				if (i >= t.size()) throw Error(path, startLine, "unterminated string");
				if (t[i] == '"') {
					if (i + 1 < t.size() && t[i + 1] == '"') {  // "" is an escaped quote
						s += '"';
						i += 2;
						continue;
					}
					++i;
					break;
				}
				if (t[i] == '\n') ++line;
				s += t[i++];
			}
			out.push_back({Token::String, s, startLine});
		} else if (c == '[') {  // "item [1]:" headings
			while (i < t.size() && t[i] != ']' && t[i] != '\n') ++i;
			if (i < t.size() && t[i] == ']') ++i;
		} else if (c == '!') {  // comment to end of line
			while (i < t.size() && t[i] != '\n') ++i;
		} else if (c == '<') {
			std::size_t e = t.find('>', i), nl = t.find('\n', i);
			if (e == std::string::npos || (nl != std::string::npos && nl < e)) throw Error(path, line, "unterminated <flag>");
			out.push_back({Token::Flag, t.substr(i, e - i + 1), line});
			i = e + 1;
		} else if (c == '-' || c == '+' || c == '.' || std::isdigit((unsigned char)c)) {
			std::size_t j = i + 1;
			while (j < t.size() && (std::isalnum((unsigned char)t[j]) || t[j] == '.' || t[j] == '-' || t[j] == '+')) ++j;
			out.push_back({Token::Number, t.substr(i, j - i), line});
			i = j;
		} else if (std::isalpha((unsigned char)c)) {  // keys: skip the word
			while (i < t.size() && (std::isalnum((unsigned char)t[i]) || t[i] == '_' || t[i] == '?')) ++i;
		} else {
			++i;
		}
	}
	return out;
}

// A token as quoted in an error message (base/text.h quoted).
std::string shown(const std::string& s) { return safeQuote(s, 40); }

class TokenReader {
public:
	TokenReader(std::vector<Token> t, std::string path) : t_(std::move(t)), path_(std::move(path)) {}
	const Token& next(Token::Kind k, const char* what) {
		if (i_ >= t_.size()) throw Error(path_, t_.empty() ? 0 : t_.back().line, std::string("unexpected end of file: expected ") + what);
		const Token& tok = t_[i_++];
		if (tok.kind != k) throw Error(path_, tok.line, std::string("expected ") + what + ", found '" + shown(tok.text) + "'");
		return tok;
	}
	double number(const char* what) {
		const Token& tok = next(Token::Number, what);
		double v;
		if (!parseDouble(tok.text, v)) throw Error(path_, tok.line, std::string("expected ") + what + ", found '" + shown(tok.text) + "'");
		return v;
	}
	long long count(const char* what) {
		const Token& tok = next(Token::Number, what);
		long long v;
		if (!parseInt(tok.text, v) || v < 0 || v > 10'000'000) throw Error(path_, tok.line, std::string("bad ") + what + " '" + shown(tok.text) + "'");
		return v;
	}
	bool peekFlag() const { return i_ < t_.size() && t_[i_].kind == Token::Flag; }
	long line() const { return i_ < t_.size() ? t_[i_].line : (t_.empty() ? 0 : t_.back().line); }

private:
	std::vector<Token> t_;
	std::string path_;
	std::size_t i_ = 0;
};

// ---- TextGrid tiers: which holds the phones, which the words ------------------------------------------
// Names are matched by token, case-insensitively: MFA's "michael - phones", WebMAUS "MAU" (its "ORT-MAU" and
// "KAN-MAU" are words), EMU "Phoneme"/"Phonetic", praatIO "phone"/"phons"/"word".
enum class TierKind { Phones, Words, Other };

std::vector<std::string> nameTokens(const std::string& name) {
	std::vector<std::string> out(1);
	for (char c : toLower(name)) {
		if (std::isalnum((unsigned char)c) || (unsigned char)c >= 0x80) out.back() += c;
		else if (!out.back().empty()) out.emplace_back();
	}
	if (out.back().empty()) out.pop_back();
	return out;
}

TierKind tierNameKind(const std::string& name) {
	static const char* const words[] = {"word", "words", "wort", "woerter", "wörter", "mot", "mots", "palavra", "palavras", "palabra",
	                                    "palabras", "parola", "parole", "ort", "kan", "trn", "orthography", "orthographic", "text",
	                                    "utterance", "utterances", "sentence", "sentences", "phrase", "phrases"};
	static const char* const phones[] = {"phone", "phones", "phoneme", "phonemes", "phonetic", "phonetics", "phon", "phons", "fon",
	                                     "fone", "fones", "fonema", "fonemas", "segment", "segments", "mau"};
	const auto tokens = nameTokens(name);
	for (const auto& t : tokens)
		for (const char* w : words)
			if (t == w) return TierKind::Words;
	for (const auto& t : tokens)
		for (const char* p : phones)
			if (t == p) return TierKind::Phones;
	const std::string n = toLower(name);  // "MichaelPhones", "speaker_phonemes"
	for (const char* p : {"phones", "phonemes", "phone"})
		if (endsWith(n, p)) return TierKind::Phones;
	return TierKind::Other;
}

std::size_t codePoints(std::string_view s) {
	std::size_t n = 0;
	for (char c : s) n += ((unsigned char)c & 0xC0) != 0x80;
	return n;
}

// What a tier's distinct non-pause labels look like.
struct TierLook {
	std::size_t labels = 0, spaced = 0, multiline = 0, known = 0, wordLike = 0;
	std::vector<std::string> sample;  // a few labels, for messages
	enum Kind { Empty, Phones, Words, Unsure };
	// Words: half the labels hold spaces (utterances), or most are unknown as phones and 3+ characters long;
	// phones: three quarters are known phones; otherwise unsure.
	Kind kind() const {
		if (labels == 0) return Empty;
		if (spaced * 2 >= labels) return Words;
		if (known * 4 >= labels * 3) return Phones;
		if (wordLike * 2 > labels) return Words;
		return Unsure;
	}
	bool mostlyMultiline() const { return multiline * 2 > labels; }
};

TierLook lookAt(const std::vector<Interval>& intervals, const ReadOptions& o) {
	TierLook k;
	std::set<std::string> seen;
	for (const auto& iv : intervals) {
		const std::string l(trim(iv.label));
		if (isPauseLabel(l) || !seen.insert(l).second) continue;
		++k.labels;
		const bool spaced = l.find_first_of(" \t\n\r") != std::string::npos;
		k.spaced += spaced;
		k.multiline += l.find('\n') != std::string::npos;
		const bool known = !spaced && (o.knownPhone ? o.knownPhone(l) : codePoints(l) <= 3);
		k.known += known;
		k.wordLike += !known && (spaced || codePoints(l) >= 3);
		if (k.sample.size() < 4) k.sample.push_back(l);
	}
	return k;
}

}  // namespace

std::vector<TextGridTier> readTextGridTiers(const std::string& bytes, const std::string& path) {
	const std::string text = decodeText(bytes);
	TokenReader r(textGridTokens(text, path), path);
	if (r.next(Token::String, "\"ooTextFile\"").text != "ooTextFile") throw Error(path, 1, "not a Praat text file (expected File type = \"ooTextFile\")");
	if (r.next(Token::String, "\"TextGrid\"").text != "TextGrid") throw Error(path, 2, "not a TextGrid (Object class is not \"TextGrid\")");
	const double gridMin = r.number("xmin"), gridMax = r.number("xmax");
	if (!r.peekFlag()) throw Error(path, r.line(), "expected <exists> (a TextGrid with tiers)");
	const std::string flag = r.next(Token::Flag, "<exists>").text;
	const long long tiers = flag == "<exists>" ? r.count("number of tiers") : 0;
	std::vector<TextGridTier> all;
	for (long long k = 0; k < tiers; ++k) {
		TextGridTier tier;
		tier.line = r.line();
		tier.cls = r.next(Token::String, "tier class").text;
		tier.name = r.next(Token::String, "tier name").text;
		const double tmin = r.number("tier xmin"), tmax = r.number("tier xmax");
		const long long n = r.count("interval count");
		if (tier.cls == "IntervalTier") {
			for (long long j = 0; j < n; ++j) {
				const long line = r.line();
				const double a = r.number("interval xmin"), b = r.number("interval xmax");
				const std::string label = r.next(Token::String, "interval text").text;
				if (b < a) throw Error(path, line, "interval ends (" + std::to_string(b) + ") before it starts (" + std::to_string(a) + ")");
				if (a < tmin - 1e-9 || b > tmax + 1e-9 || b > gridMax + 1e-9 || a < gridMin - 1e-9)
					throw Error(path, line, "interval [" + std::to_string(a) + ", " + std::to_string(b) + "] lies outside its tier [" +
					                            std::to_string(tmin) + ", " + std::to_string(tmax) + "]");
				if (a < 0) throw Error(path, line, "negative time");
				tier.intervals.push_back({boundedSeconds(a, path, line, "interval xmin"), boundedSeconds(b, path, line, "interval xmax"), std::string(trim(label)), line});
			}
		} else if (tier.cls == "TextTier") {
			for (long long j = 0; j < n; ++j) {
				const long line = r.line();
				const double t = r.number("point time");
				const std::string mark = r.next(Token::String, "point mark").text;
				if (t < 0) throw Error(path, line, "negative time");
				const Ticks at = boundedSeconds(t, path, line, "point time");
				tier.intervals.push_back({at, at, std::string(trim(mark)), line});
			}
		} else {
			throw Error(path, tier.line, "unknown tier class '" + shown(tier.cls) + "'");
		}
		all.push_back(std::move(tier));
	}
	return all;
}

namespace {

// MFA's spn ("spoken noise": a word its dictionary or model could not align) and <unk> cover speech, yet read
// as pauses they close the mouth (issue 29 item 1). Where the phones are spn, the words tier's words are
// spoken instead (phonemised): the whole tier when spn is more than a fifth of the speech, else said in a
// warning; where the words are <unk> too there is nothing to say it with: an error when that is most of
// the speech, else a warning.
bool isSpokenNoise(const std::string& label) {
	const std::string l = toLower(std::string(trim(label)));
	return l == "spn" || l == "<unk>" || l == "<spn>" || l == "<noise>";
}

void spokenNoise(Transcript& tr, const std::vector<TextGridTier>& all, const TextGridTier* chosen, const std::string& path) {
	double noise = 0, speech = 0;
	for (const Interval& iv : tr.intervals) {
		const double d = toSeconds(iv.end - iv.start);
		if (isSpokenNoise(iv.label)) noise += d, speech += d;
		else if (!isPauseLabel(iv.label)) speech += d;
	}
	if (noise <= 0) return;
	// The words under the noise, from a words tier beside a phones tier.
	// The words tier of the same speaker (MFA names them "SPEAKER - words" beside "SPEAKER - phones"), or the
	// only one.
	const TextGridTier* words = nullptr;
	if (tr.level == LabelLevel::Phone) {
		const auto speaker = [](const std::string& n) { return n.find(" - ") == std::string::npos ? std::string() : n.substr(0, n.find(" - ")); };
		int count = 0;
		const TextGridTier* same = nullptr;
		for (const auto& t : all)
			if (&t != chosen && t.cls == "IntervalTier" && tierNameKind(t.name) == TierKind::Words) {
				++count;
				words = &t;
				if (speaker(t.name) == speaker(chosen->name)) same = &t;
			}
		if (same) words = same;
		else if (count != 1) words = nullptr;
	}
	double wordsUnder = 0;
	if (words)
		for (const Interval& iv : tr.intervals)
			if (isSpokenNoise(iv.label))
				for (const Interval& w : words->intervals)
					if (!isPauseLabel(w.label) && w.start < iv.end && w.end > iv.start) wordsUnder += toSeconds(std::min(w.end, iv.end) - std::max(w.start, iv.start));
	char b[400];
	const char* what = tr.level == LabelLevel::Phone ? "phones" : "words";
	if (words && wordsUnder > 0 && noise > 0.2 * speech && noise - wordsUnder <= 0.5 * speech) {
		std::snprintf(b, sizeof b, "tier '%s' is spoken noise (spn, <unk>) for %.1f of its %.1f s of speech: the words of tier '%s' are read instead (phonemised by espeak-ng)%s",
		              tr.tier.c_str(), noise, speech, words->name.c_str(),
		              wordsUnder < 0.9 * noise ? "; where they are <unk> too, the mouth rests" : "");
		tr.warnings.push_back(b);
		tr.intervals = words->intervals;
		tr.tier = words->name;
		tr.level = LabelLevel::Word;
		tr.levelGuessed = false;
		tr.tierNote = "words, for the spoken noise of the phones";
		return;
	}
	if (noise - wordsUnder > 0.5 * speech)
		throw Error(path, chosen->line, "tier '" + tr.tier + "' has no " + what + " to show: " + std::to_string(int(std::lround(100 * noise / speech))) +
		                                    " % of its speech is spoken noise (spn) or <unk>" + (words ? (wordsUnder > 0 ? ", and most of the words under it are <unk>" : ", and so are the words under it") : "") +
		                                    " — the aligner could not align it (its dictionary or model does not fit this speech); give the audio and its text instead (talkhead render {{audio}} A {{text}} T aligns them)");
	std::snprintf(b, sizeof b, "tier '%s': %.1f s of its %.1f s of speech are spoken noise (spn, <unk>), read as pauses: the mouth rests there%s", tr.tier.c_str(), noise, speech,
	              words && wordsUnder > 0 ? " (the words tier has words there: {{tier}} to read it instead)" : "");
	tr.warnings.push_back(b);
}

// The tier to read when none is named: the phone tier (named like phones; else labels that are known
// phones), else the word tier, else the first with labels; `note` names other tiers as good.
const TextGridTier* guessTier(const std::vector<TextGridTier>& all, const ReadOptions& o, const std::string& names, const std::string& path, std::string& note) {
	using Tier = TextGridTier;
	const Tier* chosen = nullptr;
	// The phone tier (named like phones; else labels that are known phones), else the word tier (named
	// like words, or labels that are utterances or words unknown as phones; a tier whose labels mostly
	// hold several lines — praatIO's word + part of speech — after the others), else the first with labels.
	// --level words skips phone tiers; --level phones takes unsure tiers before word tiers.
	auto rank = [&](const Tier& t) -> int {
		if (t.cls != "IntervalTier") return -1;
		const TierKind nk = tierNameKind(t.name);
		const TierLook lk = lookAt(t.intervals, o);
		const auto k = lk.kind();
		if (k == TierLook::Empty) return -1;
		const bool phoneish = nk == TierKind::Phones || (nk == TierKind::Other && k == TierLook::Phones);
		const bool wordish = !phoneish && (nk == TierKind::Words || k == TierLook::Words);
		const int words = nk == TierKind::Words && k == TierLook::Words ? 0 : k == TierLook::Phones ? 2 : 1;
		int r = nk == TierKind::Phones ? (k == TierLook::Phones ? 0 : 1)
		        : phoneish             ? 2
		        : wordish              ? 3 + (lk.mostlyMultiline() ? 3 : 0) + words
		                               : 9;
		if (o.level == LabelLevel::Word && phoneish) return -1;
		if (o.level == LabelLevel::Phone && wordish) r += 10;
		return r;
	};
	int best = -1;
	std::vector<int> ranks;
	for (const auto& t : all) {
		ranks.push_back(rank(t));
		if (ranks.back() >= 0 && (best < 0 || ranks.back() < best)) best = ranks.back();
	}
	std::string others;  // other tiers as good (several speakers' phone tiers, EMU's Phoneme and Phonetic)
	for (std::size_t k = 0; k < all.size(); ++k)
		if (ranks[k] == best && best >= 0) {
			if (!chosen) chosen = &all[k];
			else if (best < 9) others += (others.empty() ? "'" : ", '") + all[k].name + "' (tier " + std::to_string(k + 1) + ")";
		}
	if (!chosen && o.level == LabelLevel::Word)
		throw Error(path, 0, "no tier holds words (tiers: " + (names.empty() ? "none" : names) + "); {{tier}} NAME reads one as words");
	for (const auto& t : all)  // no labels anywhere: the first interval tier with intervals (all pauses)
		if (!chosen && t.cls == "IntervalTier" && !t.intervals.empty()) chosen = &t;
	if (!chosen && !names.empty() && std::any_of(all.begin(), all.end(), [](const Tier& t) { return t.cls == "IntervalTier"; }))
		throw Error(path, 0, "no tier holds an interval (tiers: " + names + ")");
	if (!chosen) throw Error(path, 0, "no interval tier (tiers: " + (names.empty() ? "none" : names) + ")");
	if (!others.empty()) note = "also " + others + ": choose with {{tier}}";
	return chosen;
}

Transcript readTextGrid(const std::string& text, const std::string& path, const ReadOptions& o) {
	using Tier = TextGridTier;
	const std::vector<Tier> all = readTextGridTiers(text, path);
	const Tier* chosen = nullptr;
	std::string names, note;
	for (const auto& t : all) names += (names.empty() ? "" : ", ") + ("'" + t.name + "' (" + (t.cls == "IntervalTier" ? "intervals" : "points") + ")");
	if (!o.tier.empty()) {
		// By name, then by name ignoring case, then by number.
		for (const auto& t : all)
			if (!chosen && t.name == o.tier) chosen = &t;
		for (const auto& t : all)
			if (!chosen && toLower(t.name) == toLower(o.tier)) chosen = &t;
		long long idx;
		if (!chosen && parseInt(o.tier, idx) && idx >= 1 && std::size_t(idx) <= all.size()) chosen = &all[std::size_t(idx - 1)];
		if (!chosen) throw Error(path, 0, "no tier named '" + o.tier + "' (tiers: " + (names.empty() ? "none" : names) + ")");
		if (chosen->cls != "IntervalTier") throw Error(path, chosen->line, "tier '" + o.tier + "' is a point tier; phones need an interval tier");
		note = "{{tier}}";
	} else {
		chosen = guessTier(all, o, names, path, note);
	}
	// The level: --level; else utterances are words; a tier named like phones is phones, one named like words
	// is words (unless its labels look like phones: then ask); else as its labels look, phones when unsure.
	Transcript tr;
	tr.format = "textgrid";
	tr.intervals = chosen->intervals;
	tr.tier = chosen->name;
	const TierKind nk = tierNameKind(chosen->name);
	const TierLook lk = lookAt(chosen->intervals, o);
	const auto k = lk.kind();
	std::string sample;
	for (const auto& s : lk.sample) sample += (sample.empty() ? "'" : " '") + shown(s) + "'";
	if (o.level) tr.level = *o.level;
	else if (k == TierLook::Words && lk.spaced * 2 >= lk.labels) tr.level = LabelLevel::Word;
	else if (nk == TierKind::Phones) tr.level = LabelLevel::Phone, tr.levelGuessed = k == TierLook::Words;
	else if (nk == TierKind::Words && k == TierLook::Phones)
		throw Error(path, chosen->line, "tier '" + chosen->name + "' holds words, not phones, by its name, but its labels (" + sample +
		                                    ") look like phones; use {{level}} words, or {{level}} phones");
	else if (nk == TierKind::Words || k == TierLook::Words) tr.level = LabelLevel::Word;
	else tr.level = LabelLevel::Phone, tr.levelGuessed = k == TierLook::Unsure;
	const std::string level = tr.level == LabelLevel::Word ? "words" : "phones";
	tr.tierNote = note.empty() ? level : level + "; " + note;
	spokenNoise(tr, all, chosen, path);
	return tr;
}

// ---- MBROLA .pho -----------------------------------------------------------------------------------
Transcript readPho(const std::string& text, const std::string& path) {
	Transcript tr;
	tr.format = "pho";
	Ticks t{0};
	for (const Line& l : lines(text)) {
		std::string s = l.text.substr(0, l.text.find(';'));
		auto f = splitWhitespace(s);
		if (f.empty()) continue;
		if (f.size() < 2 || f.size() % 2 != 0)
			throw Error(path, l.no, "expected 'phone duration_ms [position pitch]…', found '" + l.text + "'");
		double ms;
		if (!parseDouble(f[1], ms) || ms < 0 || ms > 600000) throw Error(path, l.no, "bad duration '" + f[1] + "' (milliseconds)");
		const Ticks d(std::llround(ms * double(kTicksPerMs)));
		if (toSeconds(t + d) > kMaxTranscriptSeconds) throw Error(path, l.no, "the phones add up to more than 86400 s (a day)");
		tr.intervals.push_back({t, t + d, f[0] == "_" ? "" : f[0], l.no});
		t += d;
	}
	return tr;
}

// ---- xlabel (ESPS waves+, festvox/EHMM .lab) ---------------------------------------------------------
// A header ("separator ;", "nfields 1", …) ending in a line "#", then "end_time color label" lines: end times
// in seconds, each label lasting from the previous end (0 for the first); text after the separator is
// other fields (EHMM's "; score …").
Transcript readXlabel(const std::string& text, const std::string& path) {
	Transcript tr;
	tr.format = "xlabel";
	const std::vector<Line> ls = lines(text);
	std::size_t i = 0;
	char sep = ';';
	for (; i < ls.size() && ls[i].text != "#"; ++i) {
		const auto f = splitWhitespace(ls[i].text);
		if (f.size() == 2 && (f[0] == "separator" || f[0] == "seperator") && f[1].size() == 1) sep = f[1][0];
	}
	if (i == ls.size()) throw Error(path, 0, "xlabel file without the line '#' that ends its header");
	Ticks prev{0};
	for (++i; i < ls.size(); ++i) {
		const Line& l = ls[i];
		const auto f = splitWhitespace(l.text.substr(0, l.text.find(sep)));
		if (f.empty()) continue;
		long long color;
		// "end color label", "end color" (no label: a pause) or "end label".
		const bool hasColor = f.size() >= 2 && parseInt(f[1], color);
		if (f.size() < 2) throw Error(path, l.no, "expected 'end_time color label' (xlabel: end times in seconds), found '" + shown(l.text) + "'");
		const Ticks end = seconds(path, l.no, f[0], "end time");
		if (end < prev)
			throw Error(path, l.no, "end time " + f[0] + " is before the previous one (xlabel lines hold end times, in order)");
		std::string label;
		for (std::size_t k = hasColor ? 2 : 1; k < f.size(); ++k) label += (label.empty() ? "" : " ") + f[k];
		tr.intervals.push_back({prev, end, label, l.no});
		prev = end;
	}
	return tr;
}

// The centre phone of an HTS full-context label "p1^p2-p3+p4=p5@…/A:…" (p3), or nullopt for a plain label.
std::optional<std::string> fullContextCentre(const std::string& label) {
	const std::size_t caret = label.find('^');
	if (caret == std::string::npos) return std::nullopt;
	const std::size_t minus = label.find('-', caret + 1);
	if (minus == std::string::npos) return std::nullopt;
	const std::size_t plus = label.find('+', minus + 1);
	if (plus == std::string::npos || plus == minus + 1) return std::nullopt;
	const std::size_t eq = label.find('=', plus + 1);
	if (eq == std::string::npos) return std::nullopt;
	return label.substr(minus + 1, plus - minus - 1);
}

// ---- HTK .lab / MLF and GRID .align -----------------------------------------------------------------
// "start end label [score …]" with integer times; HTK in 100 ns units, GRID in 40 µs units.
std::vector<Interval> readStartEndLabel(const std::vector<Line>& ls, const std::string& path, double ticksPerUnit) {
	std::vector<Interval> out;
	for (const Line& l : ls) {
		if (l.text.empty() || (l.text[0] == '#' && !fullContextCentre(l.text))) continue;
		auto f = splitWhitespace(l.text);
		if (f.size() < 3) {
			// Say what is missing (HTS full-context labels before alignment have no times), the label abbreviated.
			long long v;
			const bool timed = !f.empty() && parseInt(f[0], v);
			const std::string label = shown(fullContextCentre(f.back()) ? f.back().substr(0, f.back().find('/')) + "…" : f.back());
			if (!timed)
				throw Error(path, l.no, "no times: the line holds only the label '" + label + "'" +
				                            (fullContextCentre(f.back()) ? " (an HTS full-context label, centre phone '" + *fullContextCentre(f.back()) + "')" : "") +
				                            "; every line needs 'start end label'");
			throw Error(path, l.no, f.size() == 1 ? "only a time (" + label + "): expected 'start end label'"
			                                      : "no label, or no end time: expected 'start end label', found '" + shown(l.text) + "'");
		}
		Ticks a = integerUnits(path, l.no, f[0], ticksPerUnit, "start"), b = integerUnits(path, l.no, f[1], ticksPerUnit, "end");
		if (b < a) throw Error(path, l.no, "interval ends before it starts");
		// HTS full-context label: the phone is the centre one (p1^p2-p3+p4=p5@…).
		out.push_back({a, b, fullContextCentre(f[2]).value_or(f[2]), l.no});
	}
	return out;
}

Transcript readHtk(const std::string& text, const std::string& path, const ReadOptions& o) {
	Transcript tr;
	tr.format = "htk";
	std::vector<Line> ls = lines(text);
	const double ticksPer100ns = double(kTicksPerSecond) / 1e7;
	if (!ls.empty() && ls.front().text == "#!MLF!#") {
		// Master label file: "name" lines, label lines, "." ends each utterance.
		struct Utt {
			std::string name;
			long line;
			std::vector<Line> body;
		};
		std::vector<Utt> utts;
		Utt* cur = nullptr;
		for (std::size_t i = 1; i < ls.size(); ++i) {
			const Line& l = ls[i];
			if (l.text.empty()) continue;
			if (!cur) {
				if (l.text.front() != '"') throw Error(path, l.no, "expected a quoted utterance name in the MLF");
				utts.push_back({l.text.substr(1, l.text.size() - 2), l.no, {}});
				cur = &utts.back();
			} else if (l.text == ".") {
				cur = nullptr;
			} else {
				cur->body.push_back(l);
			}
		}
		if (utts.empty()) throw Error(path, 0, "the MLF holds no utterance");
		const Utt* pick = &utts.front();
		if (!o.utterance.empty()) {
			pick = nullptr;
			// A number is a 1-based index; a name matches exactly, or as the unique utterance whose name ends
			// with it (a path suffix such as "*/a0001.lab" or "a0001"); anything else is an error listing them.
			std::string names;
			for (const auto& u : utts) names += (names.empty() ? "" : ", ") + u.name;
			long long idx;
			if (parseInt(o.utterance, idx)) {
				if (idx < 1 || std::size_t(idx) > utts.size())
					throw Error(path, 0, "no utterance " + o.utterance + ": the MLF holds " + std::to_string(utts.size()) + " (" + names + ")");
				pick = &utts[std::size_t(idx - 1)];
			} else {
				auto stem = [](std::string n) {  // "*/a0001.lab" → a0001
					if (auto slash = n.find_last_of('/'); slash != std::string::npos) n = n.substr(slash + 1);
					if (auto dot = n.rfind('.'); dot != std::string::npos && dot > 0) n = n.substr(0, dot);
					return n;
				};
				std::vector<const Utt*> hits;
				for (const auto& u : utts)
					if (u.name == o.utterance) hits = {&u};
				if (hits.empty())
					for (const auto& u : utts)
						if (endsWith(u.name, o.utterance) || stem(u.name) == o.utterance) hits.push_back(&u);
				if (hits.size() > 1) throw Error(path, 0, "utterance '" + o.utterance + "' is ambiguous in the MLF (utterances: " + names + "); give the full name or its number");
				if (hits.empty()) throw Error(path, 0, "no utterance '" + o.utterance + "' in the MLF (utterances: " + names + ")");
				pick = hits.front();
			}
		}
		tr.intervals = readStartEndLabel(pick->body, path, ticksPer100ns);
	} else {
		tr.intervals = readStartEndLabel(ls, path, ticksPer100ns);
	}
	return tr;
}

Transcript readGrid(const std::string& text, const std::string& path) {
	Transcript tr;
	tr.format = "grid";
	tr.level = LabelLevel::Word;
	tr.intervals = readStartEndLabel(lines(text), path, double(kTicksPerGridUnit));
	return tr;
}

// ---- TIMIT .phn: start end phone, times in samples (16 kHz unless --sample-rate) ------------------------
Transcript readTimit(const std::string& text, const std::string& path, int sampleRate) {
	if (sampleRate < 1000 || sampleRate > 192000) throw Error(path, 0, "sample rate " + std::to_string(sampleRate) + " Hz is out of range (1000–192000)");
	Transcript tr;
	tr.format = "timit";
	tr.level = LabelLevel::Phone;
	tr.intervals = readStartEndLabel(lines(text), path, double(kTicksPerSecond) / sampleRate);
	return tr;
}

// ---- plain TSV: start end label in seconds -----------------------------------------------------------
Transcript readTimingTsv(const std::string& text, const std::string& path, const std::string& timingText) {
	Transcript tr;
	tr.format = "tsv";
	bool first = true;
	for (const Line& l : lines(text)) {
		if (l.text.empty() || l.text[0] == '#') continue;
		auto f = split(l.text, '\t');
		if (f.size() == 1) f = splitWhitespace(l.text);
		double dummy;
		if (first && f.size() >= 2 && !parseDouble(f[0], dummy)) {  // a header line
			first = false;
			continue;
		}
		first = false;
		if (f.size() < 2 || f.size() > 3) throw Error(path, l.no, "expected 'start<TAB>end<TAB>label' in seconds, found '" + l.text + "'");
		Ticks a = seconds(path, l.no, f[0], "start"), b = seconds(path, l.no, f[1], "end");
		if (b < a) throw Error(path, l.no, "interval ends before it starts");
		tr.intervals.push_back({a, b, f.size() == 3 ? std::string(trim(f[2])) : "", l.no});
	}
	// aeneas's TSV sync map: fragment ids (f000001), not text (issue 29 item 2): no label here is a sound.
	const bool ids = !tr.intervals.empty() && std::all_of(tr.intervals.begin(), tr.intervals.end(), [](const Interval& i) {
		return i.label.size() >= 2 && i.label[0] == 'f' && std::all_of(i.label.begin() + 1, i.label.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
	});
	if (ids && !timingText.empty()) return withFragmentText(tr, path, timingText);
	if (ids)
		throw Error(path, tr.intervals.front().line, "the labels are aeneas fragment ids ('" + tr.intervals.front().label +
		                                                "'), not text: write the sync map as aeneas JSON, SRT or VTT, which carry the text; or give the text they refer to ({{timing-text}} FILE)");
	return tr;
}

// ---- Rhubarb mouth cues ---------------------------------------------------------------------------
// TSV: "time<TAB>shape", each shape holding until the next cue; the last cue (normally X) ends the file.
Transcript readRhubarbTsv(const std::string& text, const std::string& path) {
	Transcript tr;
	tr.format = "rhubarb-tsv";
	tr.level = LabelLevel::Viseme;
	tr.visemeScheme = "rhubarb";
	std::vector<std::pair<Ticks, Line>> cues;
	for (const Line& l : lines(text)) {
		if (l.text.empty()) continue;
		auto f = splitWhitespace(l.text);
		if (f.size() != 2) throw Error(path, l.no, "expected 'time<TAB>mouth shape', found '" + l.text + "'");
		cues.emplace_back(seconds(path, l.no, f[0], "time"), Line{l.no, f[1]});
		// Each cue holds until the next, so a cue before its predecessor would make a reversed interval.
		if (cues.size() > 1 && cues.back().first < cues[cues.size() - 2].first)
			throw Error(path, l.no, "cue at " + f[0] + " s comes before the previous one (line " + std::to_string(cues[cues.size() - 2].second.no) +
			                            "): Rhubarb cues are in time order");
	}
	for (std::size_t i = 0; i + 1 < cues.size(); ++i)
		tr.intervals.push_back({cues[i].first, cues[i + 1].first, cues[i].second.text, cues[i].second.no});
	if (cues.size() == 1) tr.intervals.push_back({cues[0].first, cues[0].first + Ticks(kTicksPerSecond / 10), cues[0].second.text, cues[0].second.no});
	return tr;
}

double jsonNumber(const JsonValue& o, const char* key, const std::string& path, long line) {
	const JsonValue* v = o.find(key);
	if (!v || v->kind != JsonValue::Kind::Number) throw Error(path, line, std::string("expected a number \"") + key + "\"");
	return v->number;
}

Transcript readRhubarbJson(const std::string& text, const std::string& path) {
	Transcript tr;
	tr.format = "rhubarb-json";
	tr.level = LabelLevel::Viseme;
	tr.visemeScheme = "rhubarb";
	JsonValue doc = parseJson(text, path);
	const JsonValue* cues = doc.find("mouthCues");
	if (!cues || cues->kind != JsonValue::Kind::Array) throw Error(path, 0, "no \"mouthCues\" array");
	long k = 0;
	for (const JsonValue& c : cues->array) {
		++k;
		const JsonValue* v = c.find("value");
		if (!v || v->kind != JsonValue::Kind::String) throw Error(path, 0, "mouth cue " + std::to_string(k) + " has no \"value\"");
		const double a = jsonNumber(c, "start", path, 0), b = jsonNumber(c, "end", path, 0);
		if (a < 0 || b < a) throw Error(path, 0, "mouth cue " + std::to_string(k) + " has bad times");
		tr.intervals.push_back({boundedSeconds(a, path, 0, "mouth cue " + std::to_string(k) + " start"),
		                        boundedSeconds(b, path, 0, "mouth cue " + std::to_string(k) + " end"), v->string, k});
	}
	return tr;
}

// ---- speech marks (JSON lines, Amazon Polly) ----------------------------------------------------------
// Viseme marks when there are any (viseme level), else word marks (word level). A mark lasts until the
// next mark of its type; the last one until the end of the last sentence mark's text is unknown, so it
// gets 150 ms (docs/decisions.md).
Transcript readMarks(const std::string& text, const std::string& path) {
	Transcript tr;
	tr.format = "marks";
	struct Mark {
		Ticks t;
		std::string type, value;
		long line;
	};
	std::vector<Mark> marks;
	// JSON lines (what Polly returns), or one JSON array of the same objects (what some SDKs save).
	std::vector<std::pair<JsonValue, long>> objects;
	if (startsWith(trim(text), "[")) {
		JsonValue all = parseJson(text, path, 1);
		long k = 0;
		for (auto& m : all.array) objects.push_back({std::move(m), ++k});
	} else {
		for (const Line& l : lines(text))
			if (!l.text.empty()) objects.push_back({parseJson(l.text, path, l.no), l.no});
	}
	for (const auto& [m, no] : objects) {
		const Line l{no, std::string()};
		if (m.kind != JsonValue::Kind::Object) throw Error(path, l.no, "expected a JSON object per line");
		const double ms = jsonNumber(m, "time", path, l.no);
		if (ms < 0) throw Error(path, l.no, "negative time");
		const JsonValue* type = m.find("type");
		const JsonValue* value = m.find("value");
		if (!type || type->kind != JsonValue::Kind::String) throw Error(path, l.no, "expected \"type\"");
		if (!value || value->kind != JsonValue::Kind::String) throw Error(path, l.no, "expected a string \"value\"");
		marks.push_back({boundedSeconds(ms / 1000.0, path, l.no, "mark time"), type->string, value->string, l.no});
	}
	bool hasViseme = false;
	for (const auto& m : marks) hasViseme |= m.type == "viseme";
	const std::string want = hasViseme ? "viseme" : "word";
	tr.level = hasViseme ? LabelLevel::Viseme : LabelLevel::Word;
	tr.visemeScheme = hasViseme ? "polly" : "";
	std::vector<Mark> sel;
	for (const auto& m : marks)
		if (m.type == want) sel.push_back(m);
	std::stable_sort(sel.begin(), sel.end(), [](const Mark& a, const Mark& b) { return a.t < b.t; });
	for (std::size_t i = 0; i < sel.size(); ++i) {
		const Ticks end = i + 1 < sel.size() ? sel[i + 1].t : sel[i].t + Ticks(150 * kTicksPerMs);
		// Polly reports SSML it met as "words" (<break time="300ms"/>, <mark name="x"/>): a pause, not speech.
		const std::string_view v = trim(sel[i].value);
		const bool tag = !v.empty() && v.front() == '<' && v.back() == '>';
		tr.intervals.push_back({sel[i].t, end, tag ? std::string() : sel[i].value, sel[i].line});
	}
	return tr;
}

bool allIntegers(const std::vector<std::string>& f, std::size_t n) {
	long long v;
	for (std::size_t i = 0; i < n && i < f.size(); ++i)
		if (!parseInt(f[i], v)) return false;
	return f.size() >= n;
}

}  // namespace

bool isPauseLabel(std::string_view label) {
	const std::string l = toLower(trim(label));
	// h#: TIMIT's and EMU/MRPA's (H#) silence.
	if (l.empty() || l == "_" || l == "#" || l == "sil" || l == "sp" || l == "spn" || l == "pau" || l == "h#") return true;
	// Noise and non-speech tags: <unk> <noise> <sil> <p:> (MFA, Kaldi, WebMAUS), {LG} {NS} (Buckeye, MFA).
	return l.size() >= 3 && ((l.front() == '<' && l.back() == '>') || (l.front() == '{' && l.back() == '}'));
}

std::optional<std::string> detectTranscriptFormat(const std::string& raw) {
	const std::string text = decodeText(raw);
	std::string_view t = trim(text);
	if (t.empty()) return std::nullopt;
	if (t.find("ooTextFile") != std::string_view::npos && t.find("TextGrid") != std::string_view::npos) return "textgrid";
	if (startsWith(t, "#!MLF!#")) return "htk";
	if (t.front() == '{' || t.front() == '[') {
		if (t.find("\"mouthCues\"") != std::string_view::npos) return "rhubarb-json";
		if (t.find("\"time\"") != std::string_view::npos && t.find("\"type\"") != std::string_view::npos && t.find("\"value\"") != std::string_view::npos) return "marks";
		return "json";  // one of the JSON timing formats (timing_formats.h), told apart by their members
	}
	if (startsWith(t, "<?xml") || startsWith(t, "<smil") || t.find("<smil") < 200) return "smil";
	if (startsWith(t, "EST_File utterance")) return "festival";
	if (looksLikeSubtitles(text)) return startsWith(t, "WEBVTT") ? "vtt" : "srt";
	if (looksLikeCtm(text)) return "ctm";
	// xlabel (festvox/EHMM .lab): header lines, a line "#", then "end_time [color] label" lines.
	{
		const std::vector<Line> ls = lines(text);
		double d;
		for (std::size_t i = 1; i < ls.size() && i < 40; ++i) {
			const auto f = splitWhitespace(ls[i - 1].text);
			if (!f.empty() && parseDouble(f[0], d)) break;  // data before any "#": not xlabel
			if (ls[i].text != "#") continue;
			for (std::size_t j = i + 1; j < ls.size(); ++j)
				if (!ls[j].text.empty()) {
					const auto g = splitWhitespace(ls[j].text);
					if (g.size() >= 2 && parseDouble(g[0], d)) return "xlabel";
					break;
				}
			break;
		}
	}
	// Line formats: look at the first data line (and the largest time for HTK vs GRID).
	std::vector<std::string> first;
	long long maxEnd = 0;
	bool intsOnly = true, semicolon = false;
	for (const Line& l : lines(text)) {
		if (l.text.empty()) continue;
		if (l.text[0] == ';') {
			semicolon = true;
			continue;
		}
		if (l.text[0] == '#') continue;
		auto f = splitWhitespace(l.text);
		if (first.empty()) first = f;
		long long v;
		if (f.size() >= 3 && allIntegers(f, 2)) {
			if (parseInt(f[1], v)) maxEnd = std::max(maxEnd, v);
		} else if (f.size() >= 3 || !allIntegers(f, f.size() - 1)) {
			intsOnly = false;  // (a lone label, or times without a label, is a broken line the reader names)
		}
	}
	if (first.empty()) return semicolon ? std::optional<std::string>("pho") : std::nullopt;
	if (fullContextCentre(first.back())) return "htk";  // HTS full-context labels, timed or not (the reader says)
	double d;
	if (first.size() == 2 && parseDouble(first[0], d) && first[1].size() == 1 && std::string("ABCDEFGHX").find(first[1]) != std::string::npos)
		return "rhubarb-tsv";
	if (first.size() >= 2 && !parseDouble(first[0], d) && parseDouble(first[1], d)) return "pho";
	// Integer times: the unit is the format's (GRID 1/25000 s, TIMIT samples, HTK 100 ns) and is never
	// guessed from magnitudes alone. TIMIT starts with h#, GRID with sil; HTK times are 100-ns units
	// (a second is 10⁷). Anything else: nullopt, and the error asks for --format.
	if (first.size() >= 3 && allIntegers(first, 2) && intsOnly) {
		if (first[2] == "h#") return "timit";
		if (maxEnd >= 1'000'000) return "htk";
		if (first[2] == "sil") return "grid";
		return std::nullopt;
	}
	if (first.size() >= 2 && parseDouble(first[0], d)) return "tsv";
	if (first.size() >= 2 && !parseDouble(first[0], d)) return "tsv";  // a header line
	return std::nullopt;
}

namespace {
std::string joinedFormats() {
	std::string k;
	for (const std::string& f : transcriptFormats()) k += (k.empty() ? "" : ", ") + f;
	return k;
}
}  // namespace

Transcript parseTranscript(const std::string& bytes, const std::string& path, const ReadOptions& o) {
	const std::string text = decodeText(bytes);
	if (trim(text).empty()) throw Error(path, 0, "empty transcript");
	if (const auto z = text.find('\0'); z != std::string::npos)
		throw Error(path, 0, "NUL bytes (the first at byte " + std::to_string(z) + "): not a text transcript (UTF-8 and UTF-16 are read)");
	std::string format = o.format;
	if (format.empty()) {
		auto f = detectTranscriptFormat(text);
		if (endsWith(toLower(path), ".phn") && (!f || *f == "grid" || *f == "htk" || *f == "timit")) f = "timit";
		if (!f && endsWith(toLower(path), ".align")) f = "grid";
		if (!f && endsWith(toLower(path), ".lab")) f = "htk";
		if (!f)
			throw Error(path, 0, "cannot tell the transcript format (integer times have no unit of their own); name it with {{format}}: timit (16-kHz samples, {{sample-rate}}), grid (1/25000 s), htk (100 ns), or " +
			                         joinedFormats());
		format = *f;
		// Integer "start end word" files are HTK or GRID; the extension settles it where it can.
		if ((format == "htk" || format == "grid") && !startsWith(trim(text), "#!MLF!#")) {
			if (endsWith(toLower(path), ".align")) format = "grid";
			else if (endsWith(toLower(path), ".lab") || endsWith(toLower(path), ".mlf")) format = "htk";
		}
	}
	Transcript tr;
	if (format == "textgrid") tr = readTextGrid(text, path, o);
	else if (format == "pho") tr = readPho(text, path);
	else if (format == "xlabel") tr = readXlabel(text, path);
	else if (format == "htk") tr = readHtk(text, path, o);
	else if (format == "grid") tr = readGrid(text, path);
	else if (format == "timit") tr = readTimit(text, path, o.sampleRate);
	else if (format == "marks") tr = readMarks(text, path);
	else if (format == "tsv") tr = readTimingTsv(text, path, o.timingText);
	else if (format == "rhubarb-tsv") tr = readRhubarbTsv(text, path);
	else if (format == "rhubarb-json") tr = readRhubarbJson(text, path);
	else if (format == "srt" || format == "vtt") tr = readSubtitles(text, path);
	else if (format == "ctm") tr = readCtm(text, path, o);
	else if (format == "json") tr = readJsonTiming(text, path, "", o);
	else if (std::find(jsonTimingFormats().begin(), jsonTimingFormats().end(), format) != jsonTimingFormats().end()) tr = readJsonTiming(text, path, format, o);
	else if (format == "festival") tr = readFestivalUtterance(text, path);
	else if (format == "smil") tr = readSmil(text, path, o.timingText);
	else throw Error("unknown transcript format '" + format + "' (known: " + joinedFormats() + ")");
	tr.path = path;
	// --level: phones or words for a transcript of either (a TextGrid has chosen its tier by it); visemes stay.
	if (o.level && *o.level != tr.level) {
		if (tr.level == LabelLevel::Viseme) throw Error(path, 0, "the transcript holds visemes (" + format + "); {{level}} does not apply");
		tr.level = *o.level;
	}

	// Validation: sort, reject overlaps, drop zero-length intervals, fill gaps with pauses (withPauses).
	std::stable_sort(tr.intervals.begin(), tr.intervals.end(), [](const Interval& a, const Interval& b) { return a.start < b.start; });
	std::vector<Interval> clean;
	for (const Interval& iv : tr.intervals) {
		if (iv.end < iv.start) throw Error(path, iv.line, "interval '" + iv.label + "' ends before it starts");  // every reader's guard
		if (iv.end == iv.start) continue;
		if (!clean.empty() && iv.start < clean.back().end) {
			const Interval& prev = clean.back();
			char buf[160];
			std::snprintf(buf, sizeof buf, "interval '%s' [%.6g, %.6g] overlaps '%s' [%.6g, %.6g] (line %ld) by %.6g s", iv.label.c_str(),
			              toSeconds(iv.start), toSeconds(iv.end), prev.label.c_str(), toSeconds(prev.start), toSeconds(prev.end), prev.line,
			              toSeconds(prev.end - iv.start));
			throw Error(path, iv.line, buf);
		}
		clean.push_back(iv);
	}
	if (clean.empty()) throw Error(path, 0, "the transcript has no interval of non-zero length");
	tr.intervals = withPauses(clean);
	return tr;
}

std::vector<Interval> withPauses(const std::vector<Interval>& sorted, std::optional<Ticks> from, std::optional<Ticks> to) {
	std::vector<Interval> out;
	out.reserve(sorted.size() * 2 + 1);
	Ticks at = from ? *from : sorted.empty() ? Ticks(0) : sorted.front().start;
	for (const Interval& i : sorted) {
		if (i.start > at) out.push_back({at, i.start, "", i.line});  // a gap: a pause
		if (i.end > std::max(at, i.start)) {
			out.push_back(i);
			out.back().start = std::max(at, i.start);
		}
		at = std::max(at, i.end);
	}
	if (to && at < *to) out.push_back({at, *to, "", 0});
	return out;
}

Transcript readTranscript(const std::string& path, const ReadOptions& o) {
	if (path == "-") {
		std::string data((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
		return parseTranscript(data, "-", o);
	}
	return parseTranscript(readTextFile(path), path, o);
}

std::vector<Interval> textGridWords(const std::string& path, const std::string& readTier) {
	for (auto& t : readTextGridTiers(readTextFile(path), path)) {
		if (t.cls != "IntervalTier" || t.name == readTier) continue;
		if (toLower(t.name).find("word") != std::string::npos) return std::move(t.intervals);
	}
	return {};
}

}  // namespace talkhead
