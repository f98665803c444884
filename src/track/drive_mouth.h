// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The mouth from a driving video (issue 17 §2, render --drive-mouth; decision D55): each frame of the
// driver's tracked mouth is labelled with one of the model actor's mouth classes (its CDVs), and the
// actor's exemplar of that class nearest the driver's shape becomes a keypose.
#include <string>
#include <vector>

#include "model/face_model.h"
#include "phonetics/language.h"
#include "track/from_video.h"
#include "track/landmarks.h"

namespace talkhead {

// A nearest-target classifier on four articulatory measures of the mouth (MouthMeasures: inner-lip
// opening, corner distance, outer lip height, subnasale–chin; eye distances): each class's target is its
// displacement from rest, the driver's measures are taken from its own rest (the most neutral frame) and
// scaled per measure to the targets' range (z-scores by the speaker's 2–98 % spread), so speakers of any
// mouth size and framing compare with one actor. Trained on labelled frames of the project: the
// synthetic corpus's CDV shapes (phonetics/cdv-mouth-targets.tsv) for the ch-unicamp-56 scheme, the
// model's own samples (a real-face corpus) for ibug-68.
struct MouthClassifier {
	std::vector<std::string> classes;    // CDVs
	std::vector<MouthMeasures> targets;  // per class: displacement from rest
	MouthMeasures rest, spread, scale;   // the driver's (calibrate)
	std::int64_t restFrame = -1;         // calibrate(track): the driver's most neutral frame
	// The model actor's classes (its CDVs of `emotion`, else neutral). Throws Error for schemes without
	// mouth measures (neither ibug-68 nor ch-unicamp-56).
	static MouthClassifier forModel(const FaceModel& model, const std::string& emotion);
	// From explicit targets (e.g. the synthetic corpus's, loadCdvMouthTargets).
	static MouthClassifier fromTargets(const std::vector<CdvMouthTarget>& targets);
	// The driver's rest and spread, from its track.
	void calibrate(const LandmarkTrack& driver);
	void calibrate(const MouthMeasures& rest, const std::vector<MouthMeasures>& frames);
	// The nearest class (index) of one frame's measures.
	std::size_t classify(const MouthMeasures& m) const;
};

struct DrivenMouth {
	std::vector<Keypose> keys;         // one per run of frames of one class, at the run's middle
	std::vector<std::string> perFrame; // each driver frame's class ("" where the face was lost)
	std::size_t exemplarChoices = 0;   // keyposes whose class had several exemplars (chosen by MHD)
};

// Keyposes for the model from a driver's track: measures from the unsmoothed points, smoothed centred
// (σ 40 ms), classified per frame; a keypose at the middle of each run of one class, with the actor's
// exemplar of the class nearest (modified Hausdorff distance of the mouth points) to the driver's mouth
// moved onto the actor's rest mouth, when the model has several. Throws Error when no frame has a face.
DrivenMouth driveMouth(const LandmarkTrack& driver, const FaceModel& model, const std::string& emotion);

// The modified Hausdorff distance (Dubuisson & Jain 1994) between two point sets.
double modifiedHausdorff(const Points& a, const Points& b);

}  // namespace talkhead
