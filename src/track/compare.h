// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Objective lip-sync measures of a synthesized face against a real speaker (issue 10 §4).
#include <string>
#include <vector>

#include "track/landmarks.h"

namespace talkhead {

// A landmark signal resampled to a fixed rate: NaN where the face was lost (gaps of more than 0.2 s).
std::vector<double> resampleSignal(const LandmarkTrack& track, const std::vector<double>& perFrame, double rateHz, double duration);

// Pearson correlation over the samples where both are finite (NaN when fewer than 3 or a constant signal).
// lagSamples > 0 compares a[i] with b[i + lag].
double pearson(const std::vector<double>& a, const std::vector<double>& b, int lagSamples = 0);

struct LipSyncReport {
	double duration = 0;        // seconds compared (the shorter video)
	double rateHz = 100;
	std::size_t samples = 0;    // samples where both faces were found
	double r0 = 0;              // Pearson r of the inner-lip opening at lag 0
	double bestR = 0;           // the best r within ±maxLag
	double bestLagMs = 0;       // its lag: > 0 when the synthesized mouth moves later than the real one
	double lmd = 0;             // mean mouth-landmark distance after aligning the mouths, in eye distances
	double coverageSynth = 0;   // fraction of frames with a face
	double coverageReal = 0;
	std::string json() const;
	std::string text() const;
};

// Inner-lip opening (normalised by the eye distance) of both tracks at rateHz, correlated at lag 0 and at the
// best lag within ±maxLagMs; LMD over the 20 mouth points, each frame's mouth centred, derotated by the eye
// line and scaled by the eye distance, the synthesized mouth's mean shape similarity-aligned to the real one.
LipSyncReport compareLipSync(const LandmarkTrack& synth, const LandmarkTrack& real, double rateHz = 100, double maxLagMs = 120);

}  // namespace talkhead
