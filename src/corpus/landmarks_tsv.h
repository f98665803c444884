// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "base/ticks.h"
#include "geometry/shape.h"

namespace talkhead {

// Feature points per frame as TSV, the one dialect talkhead writes (issue 46) — `corpus landmarks`'
// landmarks.tsv and a render's --landmarks-out alike:
//   frame  time  status  confidence  <point>_x  <point>_y  …
// time in seconds (6 decimals); status detected, tracked or lost (a tracker's) or drawn (a render's);
// confidence 0–1 (3 decimals; a render's is 1); points in pixels (3 decimals), named as the scheme names
// them, empty fields when lost. Two older dialects are still read: a tracker's `x0 y0 …` columns (the 68
// iBUG points in order) and a render's `<point>_x <point>_y` without status and confidence.
struct LandmarkRow {
	std::int64_t frame = 0;
	Ticks time{0};
	std::string status = "drawn";
	double confidence = 1;
	Points points;  // one row per point; empty when lost
};

std::string landmarksTsvHeader(const std::vector<std::string>& pointNames);
// Appends one row (`pointCount` pairs of fields: empty ones when the row has no points).
void appendLandmarksTsvRow(std::string& out, const LandmarkRow& row, std::size_t pointCount);

struct LandmarksTable {
	std::vector<std::string> pointNames;  // as the header names them; the older tracker dialect's are the iBUG
	                                      // indices "0" … "67"
	bool iBugIndices = false;             // the header numbered its points (x0 y0 …), iBUG order
	std::vector<LandmarkRow> rows;
};
// Reads any of the three dialects: whole, finite numbers in range, a known status, as many fields as the
// header has. Throws Error naming `path` and the line.
LandmarksTable parseLandmarksTsv(const std::string& text, const std::string& path);

}  // namespace talkhead
