// SPDX-License-Identifier: GPL-3.0-or-later
#include "phonetics/cdv.h"

#include <array>
#include <cmath>
#include <ostream>
#include <vector>
#include <stdexcept>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/tsv.h"
#include "base/text.h"

namespace talkhead {

namespace {

std::optional<int> exactCdv(std::string_view label) {
	const auto& t = visemeLabels();
	for (std::size_t i = 0; i < t.size(); ++i)
		if (t[i].label == label) return int(i);
	return std::nullopt;
}

int silence() {
	static const int i = [] {
		const auto& t = visemeLabels();
		for (std::size_t k = 0; k < t.size(); ++k)
			if (t[k].kind == "silence") return int(k);
		throw Error("phonetics/visemes.tsv: no silence viseme");
	}();
	return i;
}

}  // namespace

Cdv::Cdv() : index_(silence()) {}

std::optional<Cdv> Cdv::find(std::string_view name) {
	std::string_view n = trim(name);
	if (n.size() >= 2 && n.front() == '<' && n.back() == '>') n = n.substr(1, n.size() - 2);
	const auto& t = visemeLabels();
	for (std::size_t i = 0; i < t.size(); ++i)
		if (t[i].label == n || t[i].ascii == n) return Cdv(int(i));
	return std::nullopt;
}

Cdv Cdv::parse(std::string_view name) {
	if (auto c = find(name)) return *c;
	throw Error("unknown viseme '" + safeQuote(name) + "' (known: " + cdvList() + ", their ASCII aliases, with or without <>)");
}

Cdv Cdv::of(std::string_view canonicalLabel) {
	if (auto i = exactCdv(canonicalLabel)) return Cdv(*i);
	throw std::logic_error("'" + std::string(canonicalLabel) + "' is not a canonical viseme label of phonetics/visemes.tsv");
}

const VisemeLabel& Cdv::info() const { return visemeLabels()[std::size_t(index_)]; }
const std::string& Cdv::label() const { return info().label; }
const std::string& Cdv::ascii() const { return info().ascii; }
bool Cdv::isSilence() const { return index_ == silence(); }

bool Cdv::in(std::initializer_list<std::string_view> labels) const {
	bool found = false;
	for (std::string_view l : labels) found |= of(l) == *this;  // every label checked, not only up to a match
	return found;
}

std::size_t Cdv::count() { return visemeLabels().size(); }

Cdv Cdv::at(std::size_t index) {
	if (index >= count()) throw std::out_of_range("Cdv::at");
	return Cdv(int(index));
}

double Cdv::mouthDistance(Cdv other) const {
	// Each CDV's target (the rest mouth, zeros, for a CDV the file leaves out), read once.
	static const std::vector<std::array<double, 4>> targets = [] {
		std::vector<std::array<double, 4>> t(count(), {0, 0, 0, 0});
		const auto path = findDataFile("phonetics/cdv-mouth-targets.tsv");
		if (!path) throw Error("phonetics/cdv-mouth-targets.tsv: not found in the data folders (set TALKHEAD_DATA_DIR)");
		const TsvTable tab = readTsv(*path);
		const std::size_t cc = tab.column("cdv"), cols[4] = {tab.column("opening"), tab.column("width"), tab.column("height"), tab.column("jaw")};
		for (const auto& row : tab.rows) {
			const auto c = find(row.fields[cc]);
			if (!c) throw Error(tab.path, row.line, "unknown CDV '" + row.fields[cc] + "'");
			for (int k = 0; k < 4; ++k) t[c->index()][std::size_t(k)] = tab.number(row, cols[k], -1, 1);
		}
		return t;
	}();
	double d = 0;
	for (std::size_t k = 0; k < 4; ++k) d += std::pow(targets[index()][k] - targets[other.index()][k], 2);
	return std::sqrt(d);
}

std::ostream& operator<<(std::ostream& out, const Cdv& cdv) { return out << cdv.label(); }

std::string cdvList() {
	std::string s;
	for (const auto& v : visemeLabels()) s += (s.empty() ? "" : ", ") + v.label;
	return s;
}

}  // namespace talkhead
