// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "geometry/shape.h"

namespace talkhead {

// A face region: a closed boundary through named points (by index), grown about its centroid and
// feathered inward (see softRegionMask). Regions are listed coarse to fine (composite order).
struct RegionSpec {
	std::string name;
	std::vector<int> boundary;  // point indices, in order around the region
	// Per boundary entry: −1 for the point itself, else the index of a second point; the entry is then the
	// point `fraction` of the way from boundary[i] to towards[i] (scheme syntax A>B@T; a negative fraction
	// lies beyond boundary[i], away from towards[i]). Empty = all −1.
	std::vector<int> towards;
	std::vector<double> fraction;
	double grow = 0;            // relative growth of the curve about its centroid
	double feather = 0.05;      // feather width as a fraction of sqrt(region area)
};

// An eye (for blinks): its two corners, and its upper- and lower-lid points, each list ordered from the
// first corner to the second.
struct EyeSpec {
	std::string name;
	int corner0 = -1, corner1 = -1;
	std::vector<int> upper, lower;
};

// A brow (for raises and frowns): its points from the inner end to the outer end.
struct BrowSpec {
	std::string name;
	std::vector<int> points;
};

// The mouth (for measuring it): the inner lips' facing pairs (upper point, lower point) and the corners.
struct MouthSpec {
	std::vector<std::pair<int, int>> inner;
	int corner0 = -1, corner1 = -1;
	bool empty() const { return inner.empty(); }
};

// A landmark scheme: the names of a corpus's feature points in shape-vector order, their alignment
// weights, and the face regions they bound. Loaded from data files (models/schemes/*.scheme).
struct Scheme {
	std::string name;
	std::vector<std::string> pointNames;
	std::vector<std::string> pointClasses;  // weight class name per point
	Eigen::VectorXd weights;                // alignment weight per point
	std::vector<RegionSpec> regions;
	std::vector<EyeSpec> eyes;  // optional ('eye' lines); none: the face cannot blink
	std::vector<BrowSpec> brows;  // optional ('brow' lines); none: brow events do nothing
	MouthSpec mouth;              // optional ('mouth' line); none: the mouth cannot be measured (coarticulation)

	int pointCount() const { return int(pointNames.size()); }
	int indexOf(const std::string& pointName) const;  // −1 if absent
};

// The boundary of a region on a shape (k × 2 points): one row per boundary entry, in order.
Points regionBoundary(const RegionSpec& region, const Points& shape);

// Parses a scheme file; errors name the file and line.
Scheme parseScheme(const std::string& text, const std::string& fileName);
Scheme loadSchemeFile(const std::string& path);
// Looks up "schemes/<name>.scheme" in the data folders (or takes a path to a .scheme file).
Scheme loadScheme(const std::string& nameOrPath);
// A scheme read from a model file has points, weights and regions but no eye, brow or mouth lines: they
// come from the shipped scheme of the same name when its points are the same (nothing changes otherwise,
// or when the scheme already has any of them).
void completeSchemeParts(Scheme& scheme);
// Names of the schemes shipped in the first data folder that has any.
std::vector<std::string> availableSchemes();

}  // namespace talkhead
