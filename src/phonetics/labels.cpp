// SPDX-License-Identifier: GPL-3.0-or-later
#include "phonetics/labels.h"

#include <set>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/text.h"
#include "base/tsv.h"

namespace talkhead {

namespace {
std::string dataFile(const std::string& rel) {
	if (auto p = findDataFile(rel)) return *p;
	throw Error("data file '" + rel + "' not found (looked in $TALKHEAD_DATA_DIR, the installed share/talkhead and the source tree)");
}
}  // namespace

std::vector<EmotionLabel> loadEmotionLabels(const std::string& path) {
	TsvTable t = readTsv(path);
	const auto cl = t.column("label"), cv = t.column("valence"), ca = t.column("aliases"), cs = t.column("specification"), cen = t.column("term_en"),
	           cpt = t.column("term_pt");
	std::vector<EmotionLabel> out;
	std::set<std::string> seen;
	for (const auto& r : t.rows) {
		EmotionLabel e;
		e.label = r.fields[cl];
		const std::string& v = r.fields[cv];
		if (v != "+" && v != "-" && v != "0") throw Error(path, r.line, "valence must be +, - or 0");
		e.valence = v[0];
		if (r.fields[ca] != "-")
			for (const auto& a : split(r.fields[ca], ',')) e.aliases.push_back(toLower(trim(a)));
		e.specification = r.fields[cs];
		if (r.fields[cen] != "-") e.termEn = r.fields[cen];
		if (r.fields[cpt] != "-") e.termPt = r.fields[cpt];
		for (const auto& name : [&] { auto n = e.aliases; n.push_back(toLower(e.label)); return n; }())
			if (!seen.insert(name).second) throw Error(path, r.line, "label or alias '" + name + "' is used twice");
		out.push_back(std::move(e));
	}
	if (out.empty()) throw Error(path, 0, "no emotions");
	return out;
}

std::vector<VisemeLabel> loadVisemeLabels(const std::string& path) {
	TsvTable t = readTsv(path);
	const auto cl = t.column("label"), ck = t.column("kind"), cg = t.column("group"), ca = t.column("ascii"), cc = t.column("contexts"),
	           cn = t.column("note");
	std::vector<VisemeLabel> out;
	std::set<std::string> seen;
	for (const auto& r : t.rows) {
		VisemeLabel v;
		v.label = r.fields[cl];
		v.kind = r.fields[ck];
		if (v.kind != "consonant" && v.kind != "vowel" && v.kind != "silence") throw Error(path, r.line, "kind must be consonant, vowel or silence");
		if (r.fields[cg] != "-") v.group = splitWhitespace(r.fields[cg]);
		v.ascii = r.fields[ca];
		if (r.fields[cc] != "-") v.contexts = splitWhitespace(r.fields[cc]);
		v.note = r.fields[cn];
		if (!seen.insert(v.label).second || (v.ascii != v.label && !seen.insert(v.ascii).second))
			throw Error(path, r.line, "label or ASCII alias used twice");
		out.push_back(std::move(v));
	}
	if (out.empty()) throw Error(path, 0, "no visemes");
	return out;
}

const std::vector<EmotionLabel>& emotionLabels() {
	static const std::vector<EmotionLabel> v = loadEmotionLabels(dataFile("phonetics/emotions.tsv"));
	return v;
}

std::string emotionList() {
	std::string s;
	for (const auto& e : emotionLabels()) s += (s.empty() ? "" : ", ") + e.label;
	return s;
}

const std::vector<VisemeLabel>& visemeLabels() {
	static const std::vector<VisemeLabel> v = loadVisemeLabels(dataFile("phonetics/visemes.tsv"));
	return v;
}

std::optional<std::string> canonicalEmotion(const std::string& name) {
	const std::string n = toLower(trim(name));
	for (const auto& e : emotionLabels()) {
		if (toLower(e.label) == n) return e.label;
		for (const auto& a : e.aliases)
			if (a == n) return e.label;
	}
	return std::nullopt;
}

std::optional<std::string> canonicalViseme(const std::string& name) {
	std::string n(trim(name));
	if (n.size() >= 2 && n.front() == '<' && n.back() == '>') n = n.substr(1, n.size() - 2);
	for (const auto& v : visemeLabels())
		if (v.label == n || v.ascii == n) return v.label;
	return std::nullopt;
}

}  // namespace talkhead
