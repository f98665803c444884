// SPDX-License-Identifier: GPL-3.0-or-later
#include "phonetics/emotion.h"

#include <cstdio>
#include <stdexcept>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/labels.h"

namespace talkhead {

namespace {

// The table, checked once: neutral first (Emotion's default).
const std::vector<EmotionLabel>& table() {
	const auto& t = emotionLabels();
	if (t.empty() || t.front().label != "neutral") throw Error("phonetics/emotions.tsv: the first emotion must be neutral");
	return t;
}

std::optional<int> exactEmotion(std::string_view label) {
	const auto& t = table();
	for (std::size_t i = 0; i < t.size(); ++i)
		if (t[i].label == label) return int(i);
	return std::nullopt;
}

}  // namespace

std::optional<Emotion> Emotion::find(std::string_view nameOrAlias) {
	const std::string n = toLower(trim(nameOrAlias));
	const auto& t = table();
	for (std::size_t i = 0; i < t.size(); ++i) {
		if (t[i].label == n) return Emotion(int(i));
		for (const auto& a : t[i].aliases)
			if (a == n) return Emotion(int(i));
	}
	return std::nullopt;
}

Emotion Emotion::parse(std::string_view nameOrAlias) {
	if (auto e = find(nameOrAlias)) return *e;
	throw Error("unknown emotion '" + safeQuote(nameOrAlias) + "' (known: " + emotionList() + "; aliases such as sadness, disgust)");
}

Emotion Emotion::of(std::string_view canonicalLabel) {
	if (auto i = exactEmotion(canonicalLabel)) return Emotion(*i);
	throw std::logic_error("'" + std::string(canonicalLabel) + "' is not a canonical emotion label of phonetics/emotions.tsv");
}

const std::string& Emotion::label() const { return table()[std::size_t(index_)].label; }

char Emotion::valence() const { return table()[std::size_t(index_)].valence; }

bool Emotion::in(std::initializer_list<std::string_view> labels) const {
	bool found = false;
	for (std::string_view l : labels) found |= of(l) == *this;  // every label checked, not only up to a match
	return found;
}

std::size_t Emotion::count() { return table().size(); }

Emotion Emotion::at(std::size_t index) {
	if (index >= count()) throw std::out_of_range("Emotion::at");
	return Emotion(int(index));
}

namespace {

std::string intensityText(double intensity) {
	char b[32];
	std::snprintf(b, sizeof b, "%g", intensity);
	return b;
}

}  // namespace

Expression::Expression(Emotion emotion, double intensity) : emotion_(emotion), intensity_(intensity) {
	if (!(intensity >= 0 && intensity <= kMaxIntensity))
		throw FieldError("intensity", "intensity '" + intensityText(intensity) + "' is not a number from 0 to 1.5");
}

Expression Expression::parse(std::string_view text) {
	double intensity = 1;
	if (const auto colon = text.rfind(':'); colon != std::string_view::npos) {
		const std::string_view value = text.substr(colon + 1);
		if (!parseDouble(value, intensity) || !(intensity >= 0 && intensity <= kMaxIntensity))
			throw FieldError("intensity", "intensity '" + safeQuote(value) + "' is not a number from 0 to 1.5");
		text = text.substr(0, colon);
	}
	const std::optional<Emotion> e = Emotion::find(text);
	if (!e) {
		try {
			Emotion::parse(text);
		} catch (const Error& error) {
			throw FieldError("emotion", error.what());
		}
	}
	return Expression(*e, intensity);
}

std::string Expression::str() const { return intensity_ == 1 ? emotion_.label() : emotion_.label() + ":" + intensityText(intensity_); }

}  // namespace talkhead
