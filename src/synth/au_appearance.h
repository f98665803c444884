// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Issue 31, route 2: what an action unit does to the skin's appearance (furrows, wrinkles, raised cheeks),
// learned as expression ratio images (Liu, Shan & Zhang 2001; decision D61) from a corpus that has the
// emotions, and applied to any face recorded neutral through its own shape frame.
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geometry/scheme.h"
#include "geometry/shape.h"
#include "image/image.h"
#include "synth/action_units.h"

namespace talkhead {

// The anatomical anchors every scheme has (from its eyes and brows): the four eye corners, the brows'
// inner and outer ends, and the chin (the point farthest down the face along the eyes' frame). They tie an
// AU's appearance map to a face of any scheme.
constexpr int kAppearanceAnchors = 9;
Points appearanceAnchors(const Scheme& scheme, const Points& shape);

// Per action unit, the log of the luminance ratio expression / neutral on a grid in a canonical face frame
// (the learning corpus's neutral face), with that face's anchors in grid pixels. Luminance only: a ratio
// changes shading, never the hue, so the reference face's skin tone cannot tint another face.
struct AuAppearance {
	int width = 0, height = 0;
	Points anchors;                        // kAppearanceAnchors × 2, grid pixels
	std::vector<std::string> names;        // AUs, in order
	std::vector<std::vector<float>> logRatio;  // per AU, width × height, row-major
	std::string source;                    // what it was learned from
	int find(const std::string& au) const;
};

// Learning (talkhead corpus au-appearance): every image of an emotion with a profile, and its own CDV's
// neutral image, warped to the corpus's neutral rest shape (piecewise affine over its mesh); their log
// luminance ratio per pixel fitted by ridge least squares as Σ profile_a × logRatio_a over all (emotion,
// CDV) pairs, then smoothed a little (σ 1.5 grid pixels). `images(i)` reads entry i's image.
struct AppearanceSample {
	std::string emotion, cdv;
	Points points;
};
AuAppearance learnAuAppearance(const Scheme& scheme, const std::vector<AppearanceSample>& samples, const std::function<Image8(std::size_t)>& images,
                               const std::map<std::string, AuProfile>& profiles, int gridWidth = 256);

// A binary file (magic "THAUAPP1"); reading checks every size and says what is wrong, naming the file.
// `only`: read just these AUs' maps (the others are skipped, their sizes still checked).
void saveAuAppearance(const AuAppearance& a, const std::string& path);
AuAppearance loadAuAppearance(const std::string& path, const std::vector<std::string>* only = nullptr);
// The installed maps (models/au-appearance.bin, learned from the default face's corpus at build time) of
// these AUs (those it has), each read from the file once per process; nullopt when none is installed.
std::optional<AuAppearance> installedAuAppearance(const std::vector<std::string>& aus);

// The maps resampled into one face's frame: the box [x0, x0 + width) × [y0, y0 + height) of an image
// whose face has the shape `shape` (an affine fit of the anchors, least squares).
//
// Given the face's own image (`face`, the frame the box is in), a face other than the one the maps were
// learned from keeps its own skin (issue 47, D85): the learned furrows and wrinkles are the learning face's
// drawn lines, at its scale, and pasted as they are they show on another face as pale and dark bands. Each
// map is split at 0.08 eye distances into its broad shading and its lines (their local strength L: the
// mean |line| / 0.05, at most 1). Kept: the shading where it darkens (a furrow's shadow), its brightening
// only away from the lines (× (1 − L)), and the lines' dark folds, narrowed (−line² / 0.06, at most −0.3);
// the pale ridges between them go. Where the lines were, the face's own fine detail (its log luminance
// less its blur at 0.04 eye distances) is deepened, ×(1 + 1.5 L), by at most ±0.04 (an eye's edge is a detail of
// 0.3: deepened, it looked drawn). The learning face itself (its anchors fit
// the map's within 5 % of its eye distance; the default face 1.3 %, franck 22 %, a GRID s1 face 21 %) keeps
// the map as learned.
struct MappedAuAppearance {
	int x0 = 0, y0 = 0, width = 0, height = 0;
	std::vector<std::string> names;
	std::vector<std::vector<float>> logRatio;
	bool ownSkin = false;  // D85: the lines became the face's own detail deepened
	int find(const std::string& au) const;
};
// Only the AUs in `only` when it is given (a render maps those its emotions use).
MappedAuAppearance mapAuAppearance(const AuAppearance& a, const Scheme& scheme, const Points& shape, int x0, int y0, int width, int height,
                                   const std::vector<std::string>* only = nullptr, const Image8* face = nullptr);

// The luminance gain per pixel of the box for these AU weights: exp(Σ weight × logRatio), 1 where none
// applies. Empty when no weight names a mapped AU (nothing to change).
std::vector<float> appearanceGain(const MappedAuAppearance& m, const std::vector<std::pair<std::string, double>>& weights);

}  // namespace talkhead
