// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

namespace talkhead {

// One of the emotions of phonetics/emotions.tsv (neutral + the 22 OCC types), canonical by construction
// (issue 30): made by parsing a label or alias where text comes in (Emotion::find, Emotion::parse, whose
// error lists the known labels), or from a label written in the code (Emotion::of, Emotion::in), which must
// be canonical: a misspelt one ("happy_for") throws std::logic_error when it is reached, so the test that
// reaches it fails instead of the emotion silently never matching.
class Emotion {
public:
	Emotion() = default;  // neutral

	// A label or alias, any case; nullopt when it is none.
	static std::optional<Emotion> find(std::string_view nameOrAlias);
	// The same, or Error("unknown emotion 'x' (known: neutral, joy, …; aliases such as sadness, disgust)").
	static Emotion parse(std::string_view nameOrAlias);
	// A canonical label written in code; std::logic_error when it is not one (aliases neither).
	static Emotion of(std::string_view canonicalLabel);

	const std::string& label() const;  // canonical: "happy-for"
	char valence() const;              // '+', '-' or '0'
	bool isNeutral() const { return index_ == 0; }
	// Whether this is one of `labels` (canonical labels, each checked as Emotion::of checks it).
	bool in(std::initializer_list<std::string_view> labels) const;

	// All of them, in the table's order (neutral first).
	static std::size_t count();
	static Emotion at(std::size_t index);
	std::size_t index() const { return std::size_t(index_); }

	// The neutral emotion's label, the table's first (the one place it is spelt is phonetics/emotions.tsv),
	// for code that compares labels as strings (corpus rows, model samples).
	static const std::string& neutralLabel() { return Emotion().label(); }

	friend bool operator==(Emotion a, Emotion b) { return a.index_ == b.index_; }
	friend bool operator!=(Emotion a, Emotion b) { return a.index_ != b.index_; }
	friend bool operator<(Emotion a, Emotion b) { return a.index_ < b.index_; }

private:
	explicit Emotion(int index) : index_(index) {}
	int index_ = 0;
};

}  // namespace talkhead
