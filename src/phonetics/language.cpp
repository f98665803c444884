// SPDX-License-Identifier: GPL-3.0-or-later
#include "phonetics/language.h"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <mutex>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/text.h"
#include "base/tsv.h"
#include "phonetics/espeak.h"
#include "phonetics/labels.h"

namespace talkhead {

namespace {

std::string folded(const std::string& s) { return toLower(s); }

std::string spaced(const std::vector<std::string>& v) {
	std::string out;
	for (const auto& x : v) out += (out.empty() ? "" : " ") + x;
	return out;
}

// "SAMPA/X-SAMPA" → "sampa" (the notation field's value).
std::string optionName(Notation n) {
	switch (n) {
		case Notation::Ipa: return "ipa";
		case Notation::Arpabet: return "arpabet";
		case Notation::Xsampa: return "sampa";
		case Notation::Espeak: return "espeak";
		case Notation::Praat: return "praat";
		case Notation::Br1: return "br1";
		default: return "auto";
	}
}

// Removes stress and length marks (ˈ ˌ ː ˑ and ASCII ':'), and ARPAbet stress digits at the end.
// Any letter (ASCII, or any non-ASCII code point: IPA symbols, accented letters) in a label.
bool hasLetter(const std::string& s) {
	return std::any_of(s.begin(), s.end(), [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || (static_cast<unsigned char>(c) & 0x80); });
}

std::string stripMarks(const std::string& in) {
	// Praat's stress and length trigraphs first (\'1 \'2 \:f), before the apostrophe goes.
	std::string s = in;
	for (const char* t : {"\\'1", "\\'2", "\\:f", "\\.f"})
		for (std::size_t p; (p = s.find(t)) != std::string::npos;) s.erase(p, 3);
	std::string out;
	for (std::size_t i = 0; i < s.size();) {
		if (s.compare(i, 2, "\xCB\x88") == 0 || s.compare(i, 2, "\xCB\x8C") == 0 || s.compare(i, 2, "\xCB\x90") == 0 ||
		    s.compare(i, 2, "\xCB\x91") == 0) {
			i += 2;
			continue;
		}
		if (s[i] == ':' || s[i] == '\'' || s[i] == ',') {
			++i;
			continue;
		}
		out += s[i++];
	}
	// ARPAbet stress digits (AY1, ah0): ASCII letters followed by digits.
	std::size_t letters = 0;
	while (letters < out.size() && std::isalpha((unsigned char)out[letters])) ++letters;
	// One stress digit (0, 1, 2) after at most four letters: "f000001" (an aeneas fragment id) is no phone with
	// stress, and never becomes 'f' (issue 29 item 2).
	if (letters > 0 && letters <= 4 && out.size() == letters + 1 && out[letters] >= '0' && out[letters] <= '2') out.resize(letters);
	return out;
}

// X-SAMPA and br1 spell length with ':' and stress with '"' and '%': removed; digits and case stay
// (they carry meaning: s2, r2, 3, E/e).
std::string stripLength(const std::string& in) {
	std::string out;
	for (char c : in)
		if (c != ':' && c != '"' && c != '%' && c != '\'') out += c;
	return out;
}

// The code points of UTF-8 `s`, each as its bytes.
std::vector<std::string> codePointsOf(const std::string& s) {
	std::vector<std::string> out;
	for (char c : s) {
		if (out.empty() || ((unsigned char)c & 0xC0) != 0x80) out.emplace_back();
		out.back() += c;
	}
	return out;
}

unsigned codePointValue(const std::string& c) {
	const unsigned char b = c[0];
	if (b < 0x80 || c.size() < 2) return b;
	unsigned v = c.size() == 2 ? (b & 0x1F) : c.size() == 3 ? (b & 0x0F) : (b & 0x07);
	for (std::size_t i = 1; i < c.size(); ++i) v = (v << 6) | ((unsigned char)c[i] & 0x3F);
	return v;
}

// Without modifier letters (U+02B0–02FF: ʰ ʲ ʷ ˞ ˈ ˌ ː …) and, unless keepTilde says otherwise for U+0303,
// combining diacritics (U+0300–036F, tie bars included: t͡ʃ → tʃ).
std::string withoutDiacritics(const std::string& s, bool keepTilde) {
	std::string out;
	for (const auto& c : codePointsOf(s)) {
		const unsigned v = codePointValue(c);
		if (v >= 0x02B0 && v <= 0x02FF) continue;
		if (v >= 0x0300 && v <= 0x036F && !(keepTilde && v == 0x0303)) continue;
		out += c;
	}
	return out;
}

// Precomposed letters that are a plain letter with a hook (implosives ɓ ɗ ʄ ɠ ʛ, Vietnamese đ as espeak-ng's
// ɗ; ƥ ƭ ƈ ƙ): the plain letter.
std::string withoutHooks(const std::string& s) {
	static const std::pair<const char*, const char*> hooks[] = {{"ɓ", "b"}, {"ɗ", "d"}, {"ʄ", "ɟ"}, {"ɠ", "g"}, {"ʛ", "ɢ"},
	                                                            {"ƥ", "p"}, {"ƭ", "t"}, {"ƈ", "k"}, {"ƙ", "k"}};
	std::string out;
	for (const auto& c : codePointsOf(s)) {
		std::string r = c;
		for (const auto& [from, to] : hooks)
			if (c == from) r = to;
		out += r;
	}
	return out;
}

// Levenshtein distance over code points, or limit + 1 when it exceeds limit.
std::size_t editDistance(const std::vector<std::string>& a, const std::vector<std::string>& b, std::size_t limit) {
	if ((a.size() > b.size() ? a.size() - b.size() : b.size() - a.size()) > limit) return limit + 1;
	std::vector<std::size_t> row(b.size() + 1), next(b.size() + 1);
	for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
	for (std::size_t i = 1; i <= a.size(); ++i) {
		next[0] = i;
		std::size_t best = next[0];
		for (std::size_t j = 1; j <= b.size(); ++j) {
			next[j] = std::min({row[j] + 1, next[j - 1] + 1, row[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
			best = std::min(best, next[j]);
		}
		if (best > limit) return limit + 1;
		std::swap(row, next);
	}
	return std::min(row[b.size()], limit + 1);
}

// A label as an error message quotes it: one line, at most 40 characters (whole code points).
std::string quotedLabel(const std::string& label) { return safeQuote(trim(label), 80); }

std::string dataDirFor(const std::string& tag) {
	if (auto p = findDataFile("phonetics/" + tag + "/inventory.tsv")) return std::filesystem::path(*p).parent_path().string();
	return "";
}

}  // namespace

Language::Language(const std::string& tag, const std::string& dir) : tag_(tag) {
	TsvTable inv = readTsv(dir + "/inventory.tsv");
	const auto cp = inv.column("phone"), ck = inv.column("kind"), cg = inv.column("group"), cv = inv.column("vclass"), cc = inv.column("cdv");
	for (const auto& r : inv.rows) {
		PhoneInfo p;
		p.phone = r.fields[cp];
		p.kind = r.fields[ck];
		if (p.kind != "vowel" && p.kind != "consonant" && p.kind != "liquid" && p.kind != "glide" && p.kind != "pause")
			throw Error(inv.path, r.line, "kind must be vowel, consonant, liquid, glide or pause");
		p.group = r.fields[cg] == "-" ? "" : r.fields[cg];
		const std::string& vc = r.fields[cv];
		if (vc != "-") {
			if (vc != "i" && vc != "a" && vc != "u") throw Error(inv.path, r.line, "vclass must be i, a, u or -");
			p.vclass = vc[0];
		}
		if (r.fields[cc] != "-") {
			p.cdv = Cdv::find(r.fields[cc]);
			if (!p.cdv) throw Error(inv.path, r.line, "unknown CDV '" + r.fields[cc] + "'");
		}
		if (!p.cdv && p.group.empty()) throw Error(inv.path, r.line, "a phone needs a CDV or a consonant group");
		if (inventory_.count(p.phone)) throw Error(inv.path, r.line, "phone '" + p.phone + "' listed twice");
		order_.push_back(p.phone);
		inventory_[p.phone] = p;
	}
	// Pauses ("", "sil", "sp", "_", …) normalise to "_": every table must have it (found by the language
	// fuzz target: a table without it made every pause an internal error).
	if (!inventory_.count("_")) throw Error(inv.path, 0, "no pause: the inventory needs the phone '_' (kind pause, CDV sil)");
	TsvTable sym = readTsv(dir + "/symbols.tsv");
	const auto cs = sym.column("symbol"), cph = sym.column("phones"), cn = sym.column("notation");
	for (const auto& r : sym.rows) {
		auto phones = splitWhitespace(r.fields[cph]);
		if (phones.empty()) throw Error(sym.path, r.line, "no phones");
		for (const auto& p : phones)
			if (!inventory_.count(p)) throw Error(sym.path, r.line, "phone '" + p + "' is not in the inventory");
		const std::string& nn = r.fields[cn];
		const auto n = nn == "pause" ? std::optional<Notation>(Notation::Ipa) : parseNotation(nn);
		if (!n || *n == Notation::Auto) throw Error(sym.path, r.line, "unknown notation '" + nn + "' (ipa, arpabet, xsampa, sampa, espeak, praat, br1, pause)");
		if (byNotation_[*n].count(r.fields[cs])) throw Error(sym.path, r.line, "symbol '" + r.fields[cs] + "' listed twice for " + notationName(*n));
		byNotation_[*n][r.fields[cs]] = phones;
		byNotationFolded_[*n].emplace(folded(r.fields[cs]), phones);
		// Without a notation, the first row of a spelling wins (file order: ARPAbet before X-SAMPA in en-US).
		symbols_.emplace(r.fields[cs], phones);
		symbolsFolded_.emplace(folded(r.fields[cs]), phones);
	}
	for (const auto& p : order_) {
		symbols_.emplace(p, std::vector<std::string>{p});
		byNotation_[Notation::Ipa].emplace(p, std::vector<std::string>{p});
	}
}

namespace {
std::mutex& languagesMutex() {
	static std::mutex m;
	return m;
}
// Languages loaded so far: the tables by tag, and the languages mapped through the generic table
// (Language::generic) by lower-case tag.
std::map<std::string, std::unique_ptr<Language>>& languageCache() {
	static std::map<std::string, std::unique_ptr<Language>> cache;
	return cache;
}
std::map<std::string, std::unique_ptr<Language>>& genericCache() {
	static std::map<std::string, std::unique_ptr<Language>> cache;
	return cache;
}
}  // namespace

const Language& Language::get(const std::string& tag) {
	std::lock_guard<std::mutex> lock(languagesMutex());
	std::string canon;
	for (const auto& a : available())
		if (toLower(a) == toLower(tag)) canon = a;
	// A region the tables do not split (fr-FR, de-AT, es-MX) reads as its language's table.
	if (canon.empty() && tag.find('-') != std::string::npos)
		for (const auto& a : available())
			if (toLower(a) == toLower(tag.substr(0, tag.find('-')))) canon = a;
	if (canon.empty()) {
		if (auto it = genericCache().find(toLower(tag)); it != genericCache().end()) return *it->second;
		std::string known;
		for (const auto& a : available()) known += (known.empty() ? "" : ", ") + a;
		throw Error("no viseme table for language '" + tag + "' (languages: " + known + "; {{generic-visemes}} maps IPA through a generic table)");
	}
	auto& slot = languageCache()[canon];
	if (!slot) slot = std::make_unique<Language>(canon, dataDirFor(canon));
	return *slot;
}

const Language& Language::generic(const std::string& tag) {
	std::lock_guard<std::mutex> lock(languagesMutex());
	auto& slot = genericCache()[toLower(tag)];
	if (!slot) {
		const std::string dir = dataDirFor("generic");
		if (dir.empty()) throw Error("data file 'phonetics/generic/inventory.tsv' not found");
		slot = std::make_unique<Language>(tag, dir);
	}
	return *slot;
}

std::vector<std::string> Language::available() {
	std::vector<std::string> out;
	for (const char* t : {"pt-BR", "en-US", "de", "es", "fr", "it"})
		if (!dataDirFor(t).empty()) out.emplace_back(t);
	return out;
}

std::optional<std::vector<std::string>> Language::normalize(const std::string& label, Notation notation) const {
	const std::string l(trim(label));
	if (isPauseLabel(l)) return std::vector<std::string>{"_"};  // also '#', which cannot be a table row (comment)
	if (notation == Notation::Auto) {
		if (auto it = symbols_.find(l); it != symbols_.end()) return it->second;
		const std::string s = stripMarks(l);
		if (auto it = symbols_.find(s); it != symbols_.end()) return it->second;
		if (auto it = symbolsFolded_.find(folded(s)); it != symbolsFolded_.end()) return it->second;
		return std::nullopt;
	}
	// The notation's own spellings, then IPA (and pauses), exactly; case-insensitive notations also folded.
	const bool caseless = notation == Notation::Arpabet || notation == Notation::Espeak || notation == Notation::Praat;
	const std::string s = notation == Notation::Xsampa || notation == Notation::Br1 ? stripLength(l) : stripMarks(l);
	for (Notation n : {notation, Notation::Ipa}) {
		auto t = byNotation_.find(n);
		if (t == byNotation_.end()) continue;
		if (auto it = t->second.find(l); it != t->second.end()) return it->second;
		if (auto it = t->second.find(s); it != t->second.end()) return it->second;
		if (caseless && n == notation) {
			const auto& f = byNotationFolded_.at(n);
			if (auto it = f.find(folded(s)); it != f.end()) return it->second;
		}
	}
	return std::nullopt;
}

std::vector<Notation> Language::notations() const {
	std::vector<Notation> out;
	for (const auto& [n, table] : byNotation_) out.push_back(n);
	return out;
}

std::optional<Notation> parseNotation(const std::string& name) {
	const std::string n = toLower(name);
	if (n == "auto") return Notation::Auto;
	if (n == "ipa") return Notation::Ipa;
	if (n == "arpabet") return Notation::Arpabet;
	if (n == "xsampa" || n == "x-sampa" || n == "sampa") return Notation::Xsampa;
	if (n == "espeak") return Notation::Espeak;
	if (n == "praat") return Notation::Praat;
	if (n == "br1" || n == "mbrola-br1") return Notation::Br1;
	return std::nullopt;
}

std::string notationName(Notation n) {
	switch (n) {
		case Notation::Auto: return "auto";
		case Notation::Ipa: return "IPA";
		case Notation::Arpabet: return "ARPAbet";
		case Notation::Xsampa: return "SAMPA/X-SAMPA";
		case Notation::Espeak: return "espeak-ng mnemonics";
		case Notation::Praat: return "Praat trigraphs";
		case Notation::Br1: return "MBROLA br1";
	}
	return "?";
}

Notation detectNotation(const Transcript& tr, const Language& lang, std::string* evidence) {
	std::vector<std::string> labels;
	for (const auto& iv : tr.intervals) {
		const std::string l(trim(iv.label));
		if (!l.empty() && std::find(labels.begin(), labels.end(), l) == labels.end()) labels.push_back(l);
	}
	std::vector<Notation> cands;
	for (Notation n : lang.notations())
		if (tr.format != "pho" || n == Notation::Xsampa || n == Notation::Br1) cands.push_back(n);
	// How many distinct labels each notation knows; the most wins.
	std::map<Notation, std::size_t> known;
	std::size_t best = 0;
	for (Notation n : cands) {
		for (const auto& l : labels) known[n] += lang.normalize(l, n) ? 1 : 0;
		best = std::max(best, known[n]);
	}
	if (best == 0) return Notation::Auto;
	std::vector<Notation> top;
	for (Notation n : cands)
		if (known[n] == best) top.push_back(n);
	// Several equally good: fine when they read every label alike (then the first: IPA, ARPAbet, …). Every
	// notation falls back to the IPA spellings, so IPA never has labels of its own; it wins a tie when the
	// labels show IPA's own characters (anything outside ASCII), which no other notation uses.
	const bool nonAscii = std::any_of(labels.begin(), labels.end(), [](const std::string& l) {
		return std::any_of(l.begin(), l.end(), [](char c) { return (unsigned char)c >= 0x80; });
	});
	if (top.size() > 1 && top[0] == Notation::Ipa && nonAscii) top.resize(1);
	for (std::size_t k = 1; k < top.size(); ++k)
		for (const auto& l : labels) {
			const auto a = lang.normalize(l, top[0]), b = lang.normalize(l, top[k]);
			if (a && b && *a != *b)
				throw Error(tr.path, 0, "the phone labels can be read as " + notationName(top[0]) + " or " + notationName(top[k]) + ", which differ ('" + l +
				                            "' is [" + spaced(*a) + "] or [" + spaced(*b) + "]) in " + lang.tag() + "; is that the language ({{lang}})? if so, say which with {{notation}} " + optionName(top[0]) +
				                            " or {{notation}} " + optionName(top[k]));
		}
	if (evidence) {
		// Labels that only the chosen notation knows (up to 5).
		std::string e;
		int count = 0;
		for (const auto& l : labels) {
			bool unique = true;
			for (Notation n : cands)
				if (n != top[0] && n != Notation::Ipa && lang.normalize(l, n) == lang.normalize(l, top[0])) unique = false;
			if (top[0] != Notation::Ipa && lang.normalize(l, Notation::Ipa) == lang.normalize(l, top[0])) unique = false;
			if (unique && count++ < 5) e += (e.empty() ? "'" : " '") + l + "'";
		}
		*evidence = e;
	}
	return top[0];
}

std::optional<std::vector<std::string>> Language::nearest(const std::string& label, Notation notation, std::string* near) const {
	const std::string l(trim(label));
	const std::vector<std::string> cps = codePointsOf(l);
	if (cps.empty() || cps.size() > 16) return std::nullopt;  // a word or a sentence is near no phone
	// The same label without stress and length marks, modifier letters, then diacritics.
	for (const std::string& s : {stripMarks(l), withoutDiacritics(stripMarks(l), true), withoutDiacritics(stripMarks(l), false),
	                             withoutHooks(withoutDiacritics(stripMarks(l), false))})
		if (!s.empty() && s != l)
			if (auto p = normalize(s, notation); p && *p != std::vector<std::string>{"_"}) return p;
	// A spelling one edit away (two for 5+ characters); all the nearest must agree. Never a pause.
	if (cps.size() < 2) return std::nullopt;
	const std::size_t limit = cps.size() >= 5 ? 2 : 1;
	const bool caseless = notation == Notation::Auto || notation == Notation::Arpabet || notation == Notation::Espeak || notation == Notation::Praat;
	const auto key = codePointsOf(caseless ? folded(l) : l);
	std::size_t best = limit + 1;
	std::vector<std::pair<std::string, const std::vector<std::string>*>> found;
	auto consider = [&](const std::map<std::string, std::vector<std::string>>& table) {
		for (const auto& [spelling, phones] : table) {
			if (phones == std::vector<std::string>{"_"}) continue;
			const std::size_t d = editDistance(key, codePointsOf(caseless ? folded(spelling) : spelling), std::min(best, limit));
			if (d > limit || d > best) continue;
			if (d < best) found.clear(), best = d;
			found.emplace_back(spelling, &phones);
		}
	};
	if (notation == Notation::Auto) consider(symbols_);
	else
		for (Notation n : notation == Notation::Ipa ? std::vector<Notation>{Notation::Ipa} : std::vector<Notation>{notation, Notation::Ipa})
			if (auto t = byNotation_.find(n); t != byNotation_.end()) consider(t->second);
	if (found.empty()) return std::nullopt;
	for (const auto& f : found)
		if (*f.second != *found.front().second) {
			if (near) {
				std::string list;
				for (std::size_t k = 0; k < found.size() && k < 6; ++k) list += (list.empty() ? "'" : ", '") + found[k].first + "' [" + spaced(*found[k].second) + "]";
				*near = list + (found.size() > 6 ? ", …" : "");
			}
			return std::nullopt;
		}
	return *found.front().second;
}

const PhoneInfo& Language::info(const std::string& phone) const {
	auto it = inventory_.find(phone);
	if (it == inventory_.end()) throw std::logic_error("Language::info: unknown phone " + phone);
	return it->second;
}

std::string Language::inventoryList() const {
	std::string s;
	for (const auto& p : order_) s += (s.empty() ? "" : " ") + p;
	return s;
}

namespace {

// (group key, context) → CDV, from phonetics/visemes.tsv.
const std::map<std::pair<std::string, std::string>, Cdv>& contextTable() {
	static const auto table = [] {
		std::map<std::pair<std::string, std::string>, Cdv> t;
		for (const auto& v : visemeLabels())
			if (v.kind == "consonant" && !v.group.empty())
				for (const auto& c : v.contexts) t[{v.group.front(), c}] = Cdv::of(v.label);
		return t;
	}();
	return table;
}

Cdv firstCdvOfGroup(const std::string& group) {
	for (const auto& v : visemeLabels())
		if (v.kind == "consonant" && !v.group.empty() && v.group.front() == group) return Cdv::of(v.label);
	return Cdv();
}

const std::map<std::pair<std::string, std::string>, Cdv>& visemeInput() {
	static const auto table = [] {
		std::map<std::pair<std::string, std::string>, Cdv> t;
		auto path = findDataFile("phonetics/viseme-input.tsv");
		if (!path) throw Error("data file 'phonetics/viseme-input.tsv' not found");
		TsvTable tab = readTsv(*path);
		const auto cs = tab.column("scheme"), cy = tab.column("symbol"), cc = tab.column("cdv");
		for (const auto& r : tab.rows) {
			auto c = Cdv::find(r.fields[cc]);
			if (!c) throw Error(tab.path, r.line, "unknown CDV '" + r.fields[cc] + "'");
			t[{r.fields[cs], r.fields[cy]}] = *c;
		}
		return t;
	}();
	return table;
}

}  // namespace

void assignCdvs(std::vector<PhoneSegment>& ph, const Language& lang) {
	const std::size_t n = ph.size();
	auto info = [&](std::size_t i) -> const PhoneInfo& { return lang.info(ph[i].phone); };
	auto vowelish = [&](std::size_t i) { return info(i).vclass != 0 && (info(i).kind == "vowel" || info(i).kind == "glide"); };
	for (std::size_t i = 0; i < n; ++i) {
		const PhoneInfo& p = info(i);
		if (p.kind == "pause") {
			ph[i].cdv = Cdv();
			continue;
		}
		if (p.cdv) {
			ph[i].cdv = *p.cdv;
			// <i2>: [i] between two [t d n] or two [ʃ ʒ] consonants (visemes.tsv: tit ʃiʃ).
			if (*p.cdv == Cdv::of("i1") && i > 0 && i + 1 < n) {
				const std::string& gl = info(i - 1).group;
				const std::string& gr = info(i + 1).group;
				if (gl == gr && (gl == "t" || gl == "ʃ")) ph[i].cdv = Cdv::of("i2");
			}
			continue;
		}
		// Consonant: V1 from the phone directly to the left, V2 from the first vowel to the right within
		// two phones, stepping over liquids and glides of a cluster.
		char v1 = 0, v2 = 0;
		if (i > 0 && vowelish(i - 1)) v1 = info(i - 1).vclass;
		for (std::size_t j = i + 1; j < n && j <= i + 2; ++j) {
			if (info(j).kind == "vowel") {
				v2 = info(j).vclass;
				break;
			}
			if (info(j).kind != "liquid" && info(j).kind != "glide") break;
		}
		if (!v2) {
			// Coda or before a pause: the lips keep the nucleus's shape (nearest vowel to the left).
			for (std::size_t j = i; j-- > 0 && j + 3 > i;)
				if (vowelish(j)) {
					v2 = info(j).vclass;
					break;
				}
			if (!v2) v2 = 'a';
		}
		std::string context;
		if (v1) {
			const char* reduced = v2 == 'i' ? "ɪ" : v2 == 'u' ? "ʊ" : "ɐ";
			context = std::string(1, v1) + p.group + reduced;
		} else {
			context = p.group + std::string(1, v2);
		}
		auto it = contextTable().find({p.group, context});
		ph[i].cdv = it != contextTable().end() ? it->second : firstCdvOfGroup(p.group);
	}
}

std::vector<PhoneSegment> phoneSegments(const Transcript& tr, const Language& lang, UnknownPhone unknown, Notation notation, Notation* used) {
	std::vector<PhoneSegment> out;
	if (tr.level == LabelLevel::Viseme) {
		for (const auto& iv : tr.intervals) {
			Cdv cdv;  // silence
			if (!iv.label.empty()) {
				auto it = visemeInput().find({tr.visemeScheme, iv.label});
				if (it == visemeInput().end()) {
					std::string known;
					for (const auto& [k, v] : visemeInput())
						if (k.first == tr.visemeScheme) known += (known.empty() ? "" : " ") + k.second;
					if (unknown == UnknownPhone::Error)
						throw Error(tr.path, iv.line, "unknown " + tr.visemeScheme + " viseme '" + iv.label + "' (known: " + known + ")");
				} else {
					cdv = it->second;
				}
			}
			out.push_back({iv.start, iv.end, iv.label, iv.label.empty() ? "_" : iv.label, cdv, iv.line});
		}
		return out;
	}
	std::vector<Interval> phoneIntervals;
	if (tr.level == LabelLevel::Word) {
		phoneIntervals = expandWords(tr, lang.tag());
		notation = Notation::Espeak;  // espeak-ng's phoneme event names (IPA, with espeak-ng's own spellings: ɔø, ??, y-)
	} else {
		phoneIntervals = tr.intervals;
		if (notation == Notation::Auto) notation = detectNotation(tr, lang);
	}
	if (used) *used = notation;
	std::map<std::string, std::optional<std::vector<std::string>>> nearestOf;  // each unknown label searched once
	for (const auto& iv : phoneIntervals) {
		auto phones = lang.normalize(iv.label, notation);
		if (!phones) {
			std::string near;
			if (unknown == UnknownPhone::Nearest) {
				auto it = nearestOf.find(iv.label);
				if (it == nearestOf.end()) it = nearestOf.emplace(iv.label, lang.nearest(iv.label, notation, &near)).first;
				phones = it->second;
			}
			if (!phones && unknown == UnknownPhone::Silence) phones = std::vector<std::string>{"_"};
			if (!phones) {
				// Words where phones were expected (an utterance, or a tier whose level was a guess): say --level words.
				const std::string shown = quotedLabel(iv.label), in = tr.tier.empty() ? "" : " in tier '" + tr.tier + "'";
				const bool spacedLabel = trim(iv.label).find_first_of(" \t\n\r") != std::string_view::npos;
				if (tr.level == LabelLevel::Phone && (spacedLabel || (tr.levelGuessed && codePointsOf(std::string(trim(iv.label))).size() >= 3)))
					throw Error(tr.path, iv.line, (tr.tier.empty() ? std::string("the labels hold") : "tier '" + tr.tier + "' holds") +
					                                  " words, not phones; use {{level}} words ('" + shown + "' is no " + lang.tag() + " phone)");
				// What the error suggests never makes a wrong result (issue 29 item 4): silence only for a label
				// with no letter in it (a marker: "#", "<…>", "+"), never for one that may be a sound.
				const bool marker = !hasLetter(iv.label);
				if (unknown == UnknownPhone::Nearest)
					throw Error(tr.path, iv.line, "unknown " + lang.tag() + " phone '" + shown + "'" + in + ": no known spelling is near it" +
					                                  (near.empty() ? "" : " (as near: " + near + ")") +
					                                  (marker ? "; use {{unknown}} silence if it marks no speech, or correct the label"
					                                          : "; correct the label, or check {{lang}} and {{notation}}"));
				throw Error(tr.path, iv.line, "unknown " + lang.tag() + " phone '" + shown + "'" + in + " (known: " + lang.inventoryList() +
				                                  (marker ? "; or use {{unknown}}=nearest|silence)" : "; check {{lang}} and {{notation}}, or use {{unknown}} nearest)"));
			}
		}
		// Split the interval equally among the phones it spells (diphthongs, affricates).
		const std::int64_t total = (iv.end - iv.start).count(), k = std::int64_t(phones->size());
		for (std::int64_t j = 0; j < k; ++j) {
			const Ticks a = iv.start + Ticks(total * j / k), b = iv.start + Ticks(total * (j + 1) / k);
			out.push_back({a, b, iv.label, (*phones)[std::size_t(j)], Cdv(), iv.line});
		}
	}
	assignCdvs(out, lang);
	return out;
}

std::optional<PauseStyle> parsePauseStyle(const std::string& name) {
	if (name == "natural") return PauseStyle::Natural;
	if (name == "thesis") return PauseStyle::Thesis;
	if (name == "still") return PauseStyle::Still;
	return std::nullopt;
}

bool bilabial(const std::string& cdv) { return cdv == "p1" || cdv == "p2"; }

std::vector<Keypose> keyposes(const std::vector<PhoneSegment>& ph, Ticks frame, PauseStyle pauses, bool keepBilabials) {
	std::vector<Keypose> out;
	auto shuts = [&](const Keypose& k) { return keepBilabials && bilabial(k.cdv.label()); };
	// Appends k unless it is less than a frame after the previous keypose (then the one whose phones
	// last longer stays — with keepBilabials a /p b m/ first; a pause's extra keyposes never displace a phone's).
	auto add = [&](const Keypose& k, bool canReplace) {
		if (!out.empty() && k.time - out.back().time < frame) {
			const Keypose& prev = out.back();
			const Ticks prevLen = ph[prev.last].end - ph[prev.first].start, len = ph[k.last].end - ph[k.first].start;
			if (canReplace && shuts(k) != shuts(prev)) {
				if (shuts(k)) out.back() = k;
			} else if (canReplace && len > prevLen) out.back() = k;
		} else {
			out.push_back(k);
		}
	};
	auto phoneAt = [&](long q) { return q < 0 || q >= long(ph.size()) || ph[std::size_t(q)].phone.empty() ? std::string("_") : ph[std::size_t(q)].phone; };
	std::size_t i = 0;
	while (i < ph.size()) {
		// A run of phones with the same CDV makes one keypose at the run's midpoint.
		std::size_t j = i;
		while (j + 1 < ph.size() && ph[j + 1].cdv == ph[i].cdv) ++j;
		Keypose k{Ticks((ph[i].start.count() + ph[j].end.count()) / 2), ph[i].cdv, i, j};
		k.context = {phoneAt(long(i) - 2), phoneAt(long(i) - 1), phoneAt(long(i)), phoneAt(long(j) + 1), phoneAt(long(j) + 2)};
		auto at = [&](Ticks t, Cdv cdv, bool breath = false) {
			Keypose x = k;
			x.time = t, x.cdv = cdv, x.breath = breath;
			return x;
		};
		const Ticks a = ph[i].start, b = ph[j].end, len = b - a;
		const bool leading = i == 0, trailing = j + 1 == ph.size();
		if (pauses == PauseStyle::Still && ph[i].phone == "_" && leading && !trailing) {
			// D70: before the first words the lips hold one pose (the real speakers', with a model), still.
			Keypose h = at(a, k.cdv);
			h.hold = true;
			add(h, false);
			if (b - kStillLead - a >= frame) h.time = b - kStillLead, add(h, false);
		} else if (pauses != PauseStyle::Thesis && ph[i].phone == "_" && len > kPauseShort && !(leading && trailing)) {
			// D34: rest soon after speech stops, held; before the next speech an in-breath, or rest.
			if (!leading) add(at(a + kRestAfter, k.cdv), false);
			if (!trailing) {
				const Ticks restFrom = leading ? a : a + kRestAfter;
				if (pauses == PauseStyle::Still && b - restFrom >= kBreathPause) {
					// The breath rises slowly: over up to twice Natural's rise, as far as the pause allows.
					add(at(std::max(restFrom, b - kBreathLead - 2 * kBreathRise), k.cdv), false);
					add(at(b - kBreathLead, Cdv::of(kBreathCdv), true), false);
				} else if (pauses == PauseStyle::Still) {
					add(at(b - kStillLead, k.cdv), false);
				} else if (b - restFrom >= kBreathPause) {
					add(at(b - kBreathPause, k.cdv), false);
					add(at(b - kBreathLead, Cdv::of(kBreathCdv), true), false);
				} else {
					add(at(b - kRestBefore, k.cdv), false);
				}
			}
		} else {
			add(k, true);
		}
		i = j + 1;
	}
	return out;
}

}  // namespace talkhead
