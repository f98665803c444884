// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "base/progress.h"
#include "synth_face.h"

namespace talkhead {

// The synthetic expressive viseme corpus: one image per (expression × viseme), in CH-Unicamp format.
struct SynthCorpusOptions {
	int width = 1280, height = 720;
	std::uint64_t seed = 1;
	std::vector<std::string> emotions;  // canonical labels; empty = all 23
	std::vector<std::string> visemes;   // canonical labels; empty = all 34
	unsigned threads = 0;
	int pngCompression = 3;  // 0–9
};

// Articulation per viseme label and AU profile per emotion label, from the data tables
// (corpus-tools/data/viseme-articulation.tsv, expression-aus.tsv).
std::map<std::string, Articulation> loadArticulations(const std::string& path);
std::map<std::string, ActionUnits> loadActionUnits(const std::string& path);
const std::map<std::string, Articulation>& articulations();
const std::map<std::string, ActionUnits>& actionUnits();

// A smile widens every viseme and so on: the expression's AUs and the viseme's articulation combined.
struct SynthItem {
	std::string emotion, viseme;
	Articulation articulation;
	ActionUnits actionUnits;
	HeadPose pose;
	std::string fileName;                // "<emotion>_<viseme ascii>.png"
	std::array<std::string, 5> context;  // 2 left, centre, 2 right (Praat-style "_" = pause)
	std::string word;
};

// The items of the corpus in CSV order (emotions outer, visemes inner), with their per-image jitter.
// The jitter depends only on (seed, emotion, viseme), never on the order or the thread that draws it.
std::vector<SynthItem> synthCorpusItems(const SynthCorpusOptions& options);
// The closed-eyes image (D50): the neutral face at rest with its eyes shut (AU43 at 1), an unlabelled row
// (emotion "-", CDV "closed-eyes", neutral_closed.png) that the CSV names with "# closed-eyes:". The corpus
// has it whenever it has neutral.
SynthItem closedEyesItem(const SynthCorpusOptions& options);

// Writes DIR/<files>.png and DIR/corpus.csv (written last, through a temporary name), with the
// closed-eyes image when the emotions include neutral.
void writeSynthCorpus(const std::string& dir, const SynthCorpusOptions& options, ProgressSink& progress);

}  // namespace talkhead
