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

// An emotion at an intensity (D43): 0 = the neutral keyposes, 1 = the corpus's emotion, up to 1.5
// (extrapolated). Checked where it is made, once: a value of this type is always in range. Every front end
// (a flag, a manifest column, a request, a control track) makes one through the constructor or parse().
class Expression {
public:
	static constexpr double kMaxIntensity = 1.5;

	Expression() = default;  // neutral, at 1
	// FieldError("intensity", …) for an intensity outside 0–1.5 (or not a number).
	explicit Expression(Emotion emotion, double intensity = 1);
	// "LABEL" or "LABEL:I", a label or alias in any case: FieldError("emotion", …) for an unknown label,
	// FieldError("intensity", …) for an intensity that is not a number from 0 to 1.5.
	static Expression parse(std::string_view text);

	Emotion emotion() const { return emotion_; }
	double intensity() const { return intensity_; }
	bool extrapolated() const { return intensity_ > 1; }  // beyond the corpus's emotion
	std::string str() const;  // "joy" at 1, else "joy:0.5"

	friend bool operator==(const Expression& a, const Expression& b) { return a.emotion_ == b.emotion_ && a.intensity_ == b.intensity_; }
	friend bool operator!=(const Expression& a, const Expression& b) { return !(a == b); }

private:
	Emotion emotion_;
	double intensity_ = 1;
};

}  // namespace talkhead
