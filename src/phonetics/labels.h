// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace talkhead {

// The canonical emotion labels (phonetics/emotions.tsv): neutral + the 22 OCC emotions, with aliases.
struct EmotionLabel {
	std::string label;
	char valence = '0';  // '+', '-', '0'
	std::vector<std::string> aliases;
	std::string specification;
	std::string termEn, termPt;  // what a perceptual test's participant votes for (Table 6.1); empty for neutral
};

// The canonical keypose classes (phonetics/visemes.tsv): 22 consonantal and 11 vocalic context-
// dependent visemes of Costa (2015) and silence.
struct VisemeLabel {
	std::string label;  // e.g. "p1", "ʃ1", "ɛ", "sil"
	std::string kind;   // consonant | vowel | silence
	std::vector<std::string> group;  // the homorganic group's phones (IPA)
	std::string ascii;  // unique ASCII alias ("sh1", "E", …), used in file names
	std::vector<std::string> contexts;
	std::string note;
};

const std::vector<EmotionLabel>& emotionLabels();  // loaded once from the data folder
const std::vector<VisemeLabel>& visemeLabels();
std::vector<EmotionLabel> loadEmotionLabels(const std::string& path);
std::vector<VisemeLabel> loadVisemeLabels(const std::string& path);

// The canonical emotion labels, comma-separated (for messages).
std::string emotionList();
// Canonical label for a label or alias (case-insensitive), or nullopt.
std::optional<std::string> canonicalEmotion(const std::string& nameOrAlias);
// Canonical viseme label for a label or its ASCII alias, or nullopt.
std::optional<std::string> canonicalViseme(const std::string& nameOrAscii);

}  // namespace talkhead
