// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "geometry/shape.h"
#include "phonetics/cdv.h"
#include "phonetics/emotion.h"

namespace talkhead {

// One annotated training image: (image, emotion, CDV, phone context, points).
struct CorpusEntry {
	std::string imagePath;              // resolved path
	// A labelled row's emotion and CDV, typed from the reader up (issue 46). An unlabelled row ("-" in the
	// emotion column: an IMM face, the closed-eye sample, an image with its .pts) has neither; its CDV
	// column as written (an image stem, D11) is its `name`.
	std::optional<Emotion> emotion;
	std::optional<Cdv> cdv;
	std::string name;
	std::array<std::string, 5> context; // 2nd left, 1st left, centre, 1st right, 2nd right phone
	std::string word;
	Points points;                      // #points × 2, pixels, in the scheme's order
	std::string source;                 // "file:line" the entry came from, for error messages

	bool labelled() const { return emotion.has_value(); }
	// The labels as a corpus CSV and a model's samples write them: canonical, or "-" and the name.
	std::string emotionLabel() const { return emotion ? emotion->label() : "-"; }
	std::string cdvLabel() const { return cdv ? cdv->label() : name; }
	// Sets the labels from a corpus row's emotion and CDV columns ("-": unlabelled, the CDV column its
	// name); throws Error for an unknown emotion or viseme.
	void setLabels(const std::string& emotionColumn, const std::string& cdvColumn);
};

struct Corpus {
	std::string path;
	std::string schemeName;  // inferred from the format and point count (ch-unicamp-56, imm-73, ibug-68)
	std::vector<CorpusEntry> entries;
	std::string baseface;    // image chosen as the baseface ("# baseface: IMAGE" in a CSV), resolved; "" = the builder's choice
	// An image of the face with its eyes shut ("# closed-eyes: IMAGE", an unlabelled row): blinks take the
	// closed lid's skin from it (D50). "" = none.
	std::string closedEyes;
};

// CH-Unicamp CSV (Costa 2015 §3.2, spec §1.3): no header; image, emotion, 5 context phones, CDV, word,
// then `pointCount` points written "(x;y)". Images resolve relative to the CSV's folder. pointCount 0: from
// the first row (56 → ch-unicamp-56, 68 → ibug-68, 73 → imm-73). Lines starting with '#' are comments;
// "# baseface: IMAGE" names the training image to use as the model's baseface; "# closed-eyes: IMAGE" an
// unlabelled row (emotion "-") showing the face with its eyes shut. Labels come out canonical
// (D36): emotion and CDV through the phonetics tables (aliases, "<p1>"), an unknown one is an error naming
// the row; emotion "-" marks an unlabelled row, whose CDV is kept as written.
Corpus readChUnicampCsv(const std::string& path, int pointCount = 0);
// One row of a CH-Unicamp CSV, as readChUnicampCsv reads it back (issue 46: the one writer, for corpus
// synth and corpus from-video): `imagePath` as given (relative to the CSV), a field holding ',' or '"'
// quoted, an empty one written "-", each point "(x;y)" with 3 decimals. No newline.
std::string chUnicampCsvRow(const CorpusEntry& entry);

// AAM-API .asf shape file (IMM): relative 0–1 coordinates, host image name at the end. The image's
// size is needed to turn them into pixels; it is read from the image header.
CorpusEntry readAsf(const std::string& path);

// iBUG .pts: "version: 1", "n_points: N", "{", N lines "x y", "}". Coordinates are 1-based pixels in
// the iBUG convention; they are converted to 0-based pixel centres.
CorpusEntry readPts(const std::string& path);

// A CSV file, or a folder searched recursively for .asf / .pts files (the image beside the shape file or
// one folder up). Entries are sorted by image path, so the order does not depend on the file system.
Corpus loadCorpus(const std::string& path);

}  // namespace talkhead
