// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstddef>
#include <initializer_list>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

#include "phonetics/labels.h"

namespace talkhead {

// A context-dependent viseme (CDV): one of the keypose classes of phonetics/visemes.tsv — Costa (2015)'s 22
// consonantal and 11 vocalic CDVs and silence. Typed as Emotion is (issue 46): a value of this type is always
// one of the table's, made where a label is read (parse/find) or written in code (of).
class Cdv {
public:
	Cdv();  // silence ("sil")
	// A canonical label written in code as a string literal ("p1", "sil"): as Cdv::of (std::logic_error
	// when it is none). Strings read from files go through parse or find.
	template <std::size_t N>
	Cdv(const char (&canonicalLabel)[N]) : Cdv(of(std::string_view(canonicalLabel, N - 1))) {}

	// A label or its ASCII alias, with or without <>; nullopt when it is none.
	static std::optional<Cdv> find(std::string_view labelOrAscii);
	// The same, or Error("unknown viseme 'x' (known: sil, p1, …, their ASCII aliases, with or without <>)").
	static Cdv parse(std::string_view labelOrAscii);
	// A canonical label written in code; std::logic_error when it is not one.
	static Cdv of(std::string_view canonicalLabel);

	const std::string& label() const;   // canonical: "ʃ1"
	const std::string& ascii() const;   // its ASCII alias: "sh1" (file names, OpenCV's font)
	const VisemeLabel& info() const;    // its row of the table
	bool isSilence() const;
	// Whether this is one of `labels` (canonical labels, each checked as Cdv::of checks it).
	bool in(std::initializer_list<std::string_view> labels) const;

	// How far apart two CDVs' mouths are: the distance of their articulatory targets (inner-lip opening,
	// mouth width, lip height, jaw; phonetics/cdv-mouth-targets.tsv, eye distances from the rest mouth). A
	// face that lacks a CDV shows the nearest one it has (issue 47); silence is the rest mouth (0).
	double mouthDistance(Cdv other) const;

	static std::size_t count();
	static Cdv at(std::size_t index);
	std::size_t index() const { return std::size_t(index_); }

	friend bool operator==(Cdv a, Cdv b) { return a.index_ == b.index_; }
	friend bool operator!=(Cdv a, Cdv b) { return a.index_ != b.index_; }
	// Ordered as their labels (as the strings they were ordered before: maps and reports keep their order).
	friend bool operator<(Cdv a, Cdv b) { return a.label() < b.label(); }

private:
	explicit Cdv(int index) : index_(index) {}
	int index_;
};

// Its label (test messages, logs).
std::ostream& operator<<(std::ostream& out, const Cdv& cdv);

// The known labels, comma-separated, for messages.
std::string cdvList();

}  // namespace talkhead
