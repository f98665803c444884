// SPDX-License-Identifier: GPL-3.0-or-later
// Timed-transcript readers: Praat TextGrid (long and short text, UTF-8/UTF-16), MBROLA .pho, HTK .lab
// and MLF, GRID .align, speech-marks JSON lines (Polly), plain TSV, Rhubarb mouth cues (TSV and JSON).
#include "phonetics/transcript.h"
#include "phonetics/timing_formats.h"
#include "phonetics/plausibility.h"
#include "phonetics/timing_readers.h"

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
		std::vector<std::string> v;
		for (const TimingFormat& t : timingFormats())
			if (t.read) v.push_back(t.name);
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
	if (const JsonValue* m = doc.find("metadata"); m && m->kind == JsonValue::Kind::Object)
		if (const JsonValue* d = m->find("duration"); d && d->kind == JsonValue::Kind::Number) tr.statedDuration = d->number;
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
	// [SIL] [NOISE] (Charsiu, wav2vec2 aligners).
	return l.size() >= 3 && ((l.front() == '<' && l.back() == '>') || (l.front() == '{' && l.back() == '}') || (l.front() == '[' && l.back() == ']'));
}

namespace {

// The first `n` bytes of a text, cut after its last whole line: a signature never sees a line cut in two.
std::string headLines(const std::string& text, std::size_t n) {
	if (text.size() <= n) return text;
	const auto nl = text.rfind('\n', n);
	return nl == std::string::npos ? std::string() : text.substr(0, nl + 1);
}

// The line formats' shape: the first data line's fields, the largest second field of integer lines, whether
// every data line is "integer integer label", and whether there are ';' comment lines.
struct LineShape {
	std::vector<std::string> first;
	long long maxEnd = 0;
	bool intsOnly = true, semicolon = false;
	int dataLines = 0;
};
LineShape lineShape(const std::string& text) {
	LineShape sh;
	for (const Line& l : lines(headLines(text, 256 * 1024))) {
		if (l.text.empty()) continue;
		if (l.text[0] == ';') {
			sh.semicolon = true;
			continue;
		}
		if (l.text[0] == '#') continue;
		auto f = splitWhitespace(l.text);
		++sh.dataLines;
		if (sh.first.empty()) sh.first = f;
		long long v;
		if (f.size() >= 3 && allIntegers(f, 2)) {
			if (parseInt(f[1], v)) sh.maxEnd = std::max(sh.maxEnd, v);
		} else if (f.size() >= 3 || !allIntegers(f, f.size() - 1)) {
			sh.intsOnly = false;  // (a lone label, or times without a label, is a broken line the reader names)
		}
		if (sh.dataLines >= 400) break;
	}
	return sh;
}

bool integerLines(const LineShape& sh) { return sh.first.size() >= 3 && allIntegers(sh.first, 2) && sh.intsOnly && !fullContextCentre(sh.first.back()); }

bool isXlabel(const std::string& text) {
	// xlabel (festvox/EHMM .lab): header lines, a line "#", then "end_time [color] label" lines.
	const std::vector<Line> ls = lines(headLines(text, 8000));
	double d;
	for (std::size_t i = 1; i < ls.size() && i < 40; ++i) {
		const auto f = splitWhitespace(ls[i - 1].text);
		if (!f.empty() && parseDouble(f[0], d)) return false;  // data before any "#": not xlabel
		if (ls[i].text != "#") continue;
		for (std::size_t j = i + 1; j < ls.size(); ++j)
			if (!ls[j].text.empty()) {
				const auto g = splitWhitespace(ls[j].text);
				return g.size() >= 2 && parseDouble(g[0], d);
			}
		return false;
	}
	return false;
}

// Every data line "phone duration [position pitch]…" (numbers after the phone, an even count of them).
bool isPho(const std::string& text) {
	int data = 0;
	bool comment = false;
	for (const Line& l : lines(headLines(text, 256 * 1024))) {
		if (!l.text.empty() && l.text[0] == ';') {
			comment = true;
			continue;
		}
		const auto f = splitWhitespace(l.text.substr(0, l.text.find(';')));
		if (f.empty()) continue;
		double d;
		if (f.size() < 2 || f.size() % 2 != 0 || parseDouble(f[0], d)) return false;
		for (std::size_t i = 1; i < f.size(); ++i)
			if (!parseDouble(f[i], d)) return false;
		if (++data >= 400) break;
	}
	return data > 0 || comment;
}

// "start end label" (tab- or space-separated, seconds) on the first data line, or a header naming start and end.
bool isTimingTsv(const std::string& text) {
	for (const Line& l : lines(headLines(text, 8000))) {
		if (l.text.empty() || l.text[0] == '#') continue;
		auto f = split(l.text, '\t');
		if (f.size() == 1) f = splitWhitespace(l.text);
		double a, b;
		if (f.size() >= 2 && f.size() <= 3 && parseDouble(f[0], a) && parseDouble(f[1], b)) return true;
		const std::string low = toLower(l.text);
		return f.size() >= 2 && low.find("start") != std::string::npos && low.find("end") != std::string::npos;
	}
	return false;
}

bool isRhubarbTsv(const std::string& text) {
	int n = 0;
	for (const Line& l : lines(headLines(text, 20000))) {
		if (l.text.empty()) continue;
		const auto f = splitWhitespace(l.text);
		double d;
		if (f.size() != 2 || !parseDouble(f[0], d) || f[1].size() != 1 || std::string("ABCDEFGHX").find(f[1]) == std::string::npos) return false;
		++n;
	}
	return n > 0;
}

// Amazon Polly's speech marks: JSON objects (lines, or one array) each with a numeric "time", a "type" of
// Polly's four and a "value".
bool isMarks(const TimingSample& s) {
	auto mark = [](const JsonValue& m) {
		const JsonValue* type = m.kind == JsonValue::Kind::Object ? m.find("type") : nullptr;
		const JsonValue* t = m.kind == JsonValue::Kind::Object ? m.find("time") : nullptr;
		if (!type || type->kind != JsonValue::Kind::String || !t || t->kind != JsonValue::Kind::Number || !m.find("value")) return false;
		return type->string == "word" || type->string == "sentence" || type->string == "viseme" || type->string == "ssml";
	};
	if (const JsonValue* j = s.json()) {
		if (j->kind == JsonValue::Kind::Object) return mark(*j);
		return j->kind == JsonValue::Kind::Array && !j->array.empty() && std::all_of(j->array.begin(), j->array.end(), mark);
	}
	const auto& st = s.jsonStream();
	return !st.empty() && std::all_of(st.begin(), st.end(), [&](const auto& p) { return mark(p.second); });
}

}  // namespace

void registerClassicTimingFormats(std::vector<TimingFormat>& v) {
	v.push_back({"textgrid", "Praat TextGrid (long or short text; MFA, Charsiu, WebMAUS, praatio)", {".textgrid"}, "phones or words (the tier)",
	             "tiers (the phone tier, else the word tier; {{tier}} picks one); spoken noise", 3,
	             [](const TimingSample& s) {
		             const std::string_view t = s.trimmed().substr(0, 400);
		             return t.find("ooTextFile") != std::string_view::npos && t.find("TextGrid") != std::string_view::npos;
	             },
	             [](const TimingSample& s, const ReadOptions& o) { return readTextGrid(s.text(), s.path(), o); }, ""});
	v.push_back({"htk", "HTK label file or MLF; HTS full-context labels", {".lab", ".mlf"}, "phones", "times in 100 ns; MLF utterances ({{utterance}})", 2,
	             [](const TimingSample& s) {
		             if (startsWith(s.trimmed(), "#!MLF!#")) return true;
		             const LineShape sh = lineShape(s.text());
		             if (!sh.first.empty() && fullContextCentre(sh.first.back())) return true;
		             if (!integerLines(sh) || s.extension() == ".align" || s.extension() == ".phn" || s.extension() == ".wrd") return false;
		             return s.extension() == ".lab" || s.extension() == ".mlf" || (sh.maxEnd >= 1'000'000 && sh.first[2] != "h#");
	             },
	             [](const TimingSample& s, const ReadOptions& o) { return readHtk(s.text(), s.path(), o); }, ""});
	v.push_back({"grid", "GRID corpus .align", {".align"}, "words", "times in 1/25000 s; English", 2,
	             [](const TimingSample& s) {
		             const LineShape sh = lineShape(s.text());
		             if (!integerLines(sh) || s.extension() == ".lab" || s.extension() == ".mlf" || s.extension() == ".phn") return false;
		             return s.extension() == ".align" || (sh.first[2] == "sil" && sh.maxEnd < 1'000'000);
	             },
	             [](const TimingSample& s, const ReadOptions&) { return readGrid(s.text(), s.path()); }, ""});
	v.push_back({"timit", "TIMIT .phn", {".phn"}, "phones", "times in samples at {{sample-rate}} (16 kHz)", 2,
	             [](const TimingSample& s) {
		             const LineShape sh = lineShape(s.text());
		             return integerLines(sh) && (s.extension() == ".phn" || sh.first[2] == "h#");
	             },
	             [](const TimingSample& s, const ReadOptions& o) { return readTimit(s.text(), s.path(), o.sampleRate); }, ""});
	v.push_back({"xlabel", "ESPS xlabel (festvox, EHMM .lab)", {".lab"}, "phones", "end times in s", 2,
	             [](const TimingSample& s) { return isXlabel(s.text()); },
	             [](const TimingSample& s, const ReadOptions&) { return readXlabel(s.text(), s.path()); }, ""});
	v.push_back({"pho", "MBROLA .pho (espeak-ng, MaryTTS)", {".pho"}, "phones", "durations in ms", 2, [](const TimingSample& s) { return !s.looksLikeJson() && isPho(s.text()); },
	             [](const TimingSample& s, const ReadOptions&) { return readPho(s.text(), s.path()); }, ""});
	v.push_back({"marks", "Amazon Polly speech marks (JSON lines)", {".marks", ".json", ".jsonl"}, "visemes or words", "times in ms", 3, isMarks,
	             [](const TimingSample& s, const ReadOptions&) { return readMarks(s.text(), s.path()); }, ""});
	v.push_back({"tsv", "start, end, label (TSV or spaces, seconds; aeneas TSV with {{timing-text}})", {".tsv", ".txt"}, "phones or words", "times in s", 1,
	             [](const TimingSample& s) { return !s.looksLikeJson() && !s.looksLikeXml() && isTimingTsv(s.text()); },
	             [](const TimingSample& s, const ReadOptions& o) { return readTimingTsv(s.text(), s.path(), o.timingText); }, ""});
	v.push_back({"rhubarb-tsv", "Rhubarb Lip Sync TSV", {".tsv", ".txt"}, "visemes (Rhubarb's A–H, X)", "times in s", 2, [](const TimingSample& s) { return isRhubarbTsv(s.text()); },
	             [](const TimingSample& s, const ReadOptions&) { return readRhubarbTsv(s.text(), s.path()); }, ""});
	// Integer times whose unit no extension or label settles: named and refused (the unit is never guessed).
	v.push_back({"integer-times", "start, end, label lines with integer times (HTK, GRID or TIMIT without its extension)", {}, "", "", 2,
	             [](const TimingSample& s) {
		             if (!integerLines(lineShape(s.text()))) return false;
		             for (const char* unitFormat : {"htk", "grid", "timit"})
			             if (findTimingFormat(unitFormat)->signature(s)) return false;
		             return true;
	             },
	             nullptr,
	             "integer times have no unit of their own; name it with {{format}}: timit (16-kHz samples, {{sample-rate}}), grid (1/25000 s) or htk (100 ns)"});
	v.push_back({"rhubarb-json", "Rhubarb Lip Sync JSON", {".json"}, "visemes (Rhubarb's A–H, X)", "times in s; metadata.duration", 3,
	             [](const TimingSample& s) { return s.json() && timing::array(*s.json(), "mouthCues"); },
	             [](const TimingSample& s, const ReadOptions&) { return readRhubarbJson(s.text(), s.path()); }, ""});
}

std::optional<std::string> detectTranscriptFormat(const std::string& raw) {
	const TimingSample s(decodeText(raw), "");
	return detectTimingFormat(s);
}


Transcript parseTranscript(const std::string& bytes, const std::string& path, const ReadOptions& o) {
	const std::string text = decodeText(bytes);
	if (trim(text).empty()) throw Error(path, 0, "empty transcript");
	if (const auto z = text.find('\0'); z != std::string::npos)
		throw Error(path, 0, "NUL bytes (the first at byte " + std::to_string(z) + "): not a text transcript (UTF-8 and UTF-16 are read)");
	const TimingSample sample(text, path);
	Transcript tr = readTimingSample(sample, o);
	const std::string& format = tr.format;
	tr.path = path;
	// --level: phones or words for a transcript of either (a TextGrid has chosen its tier by it); visemes stay.
	if (o.level && *o.level != tr.level) {
		if (tr.level == LabelLevel::Viseme) throw Error(path, 0, "the transcript holds visemes (" + format + "); {{level}} does not apply");
		tr.level = *o.level;
	}

	// Labels that are not speech (sound events, speaker labels, tone numbers) never reach the phonemiser.
	cleanSpeechLabels(tr);
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
	// The plausibility gate (issue 50): units, rates, the stated duration; an Error naming what is wrong.
	tr.verdict = checkTimingPlausibility(tr);
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
