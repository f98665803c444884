// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/scheme.h"
#include "geometry/shape.h"

namespace talkhead {

// Facial action units as shape templates (issue 13 §4; decision D48). A template is, for every point of a
// scheme, its displacement from the neutral face at full intensity, in units of the inter-ocular distance
// (between the two eyes' centres, each the midpoint of its corners), x along the eye line toward the
// image-right eye, y perpendicular to it, down the face. Learned from a corpus that has the emotions
// (learnAuTemplates) and stored as data: models/au-templates/<scheme>.tsv.
struct AuTemplates {
	std::string scheme;
	std::vector<std::string> names;  // "AU1", "AU2", … in file order
	std::vector<Points> offsets;     // per AU: point count × 2
	int find(const std::string& au) const;  // −1 if absent
};

// An emotion's action units and their intensities (0–1), e.g. {{"AU6", 0.9}, {"AU12", 1.0}}.
using AuProfile = std::vector<std::pair<std::string, double>>;

// "AU12", "au12", "12" → "AU12"; nullopt unless it is one of knownActionUnits().
std::optional<std::string> canonicalActionUnit(const std::string& name);
// The action units talkhead knows (the columns of corpus-tools/data/expression-aus.tsv, plus AU45 blink).
const std::vector<std::string>& knownActionUnits();

// The emotion profiles of corpus-tools/data/expression-aus.tsv (every column named AU…), keyed by
// canonical emotion; throws Error naming the file and line.
std::map<std::string, AuProfile> loadAuProfiles(const std::string& path);
const std::map<std::string, AuProfile>& defaultAuProfiles();

// Reads / writes a template file: '#' comments, a header "au point dx dy", one row per (AU, point) with
// every point of the scheme for each AU. Throws Error naming the file and line.
AuTemplates parseAuTemplates(const std::string& text, const std::string& path, const Scheme& scheme);
std::string formatAuTemplates(const AuTemplates& t, const Scheme& scheme, const std::string& comment);
// The shipped templates of a scheme (models/au-templates/<name>.tsv), if there are any.
std::optional<AuTemplates> findAuTemplates(const Scheme& scheme);

// The eye frame of a shape: origin between the eyes' centres, unit x toward the image-right eye, unit y
// perpendicular (down the face), scale = the inter-ocular distance. Needs the scheme's two eyes.
struct EyeFrame {
	Eigen::RowVector2d origin, x, y;
	double iod = 0;
};
EyeFrame eyeFrame(const Scheme& scheme, const Points& shape);

// Adds Σ weight × template to `shape` in `frame` (side −1: only the image-left half of the face, the
// subject's right; +1 the image-right half; 0 both; points within 5 % of the inter-ocular distance of the
// midline take half on one side).
struct AuWeight {
	int au = -1;  // index into the templates
	double weight = 0;
	int side = 0;
};
void applyActionUnits(Points& shape, const AuTemplates& t, const std::vector<AuWeight>& weights, const EyeFrame& frame);
// The offsets an emotion profile gives, at `intensity`, for AUs the templates have.
std::vector<AuWeight> profileWeights(const AuTemplates& t, const AuProfile& profile, double intensity);

// Learning (talkhead corpus au-templates): every (emotion, CDV) shape of an emotion with a profile is
// aligned to the neutral shape of the same CDV (similarity on the scheme's heaviest, rigid points),
// its displacement expressed in the neutral shape's eye frame; then one ridge least-squares fit over all
// of them: displacement ≈ Σ_a profile_a × template_a. AUs no profile uses are left out.
struct LabelledShape {
	std::string emotion, cdv;
	Points points;
};
struct AuFit {
	AuTemplates templates;
	std::size_t pairs = 0;          // (emotion, CDV) shapes used
	double rmsData = 0, rmsResidual = 0;  // of the displacements and of the fit's residual (IOD units)
	std::vector<std::string> unused;      // AUs no profile sets
};
AuFit learnAuTemplates(const Scheme& scheme, const std::vector<LabelledShape>& shapes, const std::map<std::string, AuProfile>& profiles);

}  // namespace talkhead
