// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The signal-processing parts of forced alignment (align.h): MFCC features, an energy voice-activity
// measure and dynamic time warping. Public so that tests can check them against known answers.
#include <cstdint>
#include <utility>
#include <vector>

namespace talkhead::align {

struct FeatureOptions {
	double windowSeconds = 0.025;  // Hamming window
	double hopSeconds = 0.010;
	int melBands = 26;
	int cepstra = 13;              // c0 … c12 (c0 = log energy in the mel bands)
	double lowHz = 60, highHz = 7600;  // highHz is capped below each signal's Nyquist frequency
	bool deltas = true;            // append Δ (regression over ±2 frames)
	bool deltaDeltas = false;      // append ΔΔ
};

// A frames × dims matrix of features, row-major.
struct FeatureMatrix {
	int frames = 0, dims = 0;
	std::vector<float> data;
	float* row(int k) { return data.data() + std::size_t(k) * std::size_t(dims); }
	const float* row(int k) const { return data.data() + std::size_t(k) * std::size_t(dims); }
};

// Frame k covers samples [k·hop, k·hop + window) (centre at k·hop + window/2); a signal shorter than one
// window gives no frames.
int frameCountFor(std::size_t samples, int sampleRate, const FeatureOptions& options = {});

// MFCCs of mono samples in [−1, 1]: pre-emphasis 0.97, Hamming window, power spectrum (radix-2 FFT),
// triangular mel filters, log, DCT-II; then deltas as options say. A tiny deterministic dither keeps
// digital silence finite. The mel filters are placed in Hz, so signals at different sample rates give
// comparable features.
FeatureMatrix mfcc(const std::vector<float>& samples, int sampleRate, const FeatureOptions& options = {});

// Each frame's level in dB relative to full scale (mean square over the window; −120 for digital silence).
std::vector<float> frameLevels(const std::vector<float>& samples, int sampleRate, const FeatureOptions& options = {});

// Cepstral mean and variance normalisation of every dimension with statistics taken over the frames
// where use[k] is true (all frames when use is empty or selects fewer than 2).
void normalise(FeatureMatrix& features, const std::vector<bool>& use = {});

// Euclidean distance between frame i of a and frame j of b (same dims).
float frameDistance(const FeatureMatrix& a, int i, const FeatureMatrix& b, int j);

struct DtwOptions {
	// Local slope limit: one frame of either sequence may match at most this many consecutive frames of
	// the other (steps (k,1) and (1,k), k ≤ maxSlope), except where pauses allow free runs.
	int maxSlope = 3;
	// Sakoe–Chiba radius in frames around the straight line from (0,0) to (n−1,m−1); 0 = no band.
	int band = 0;
};

struct DtwResult {
	std::vector<std::pair<int, int>> path;  // (i, j) cells from (0,0) to (n−1, m−1), both non-decreasing
	double cost = 0;                         // total weighted local cost / (n + m)
};

// Aligns sequence a (n frames, e.g. the speech to align) with b (m frames, e.g. the reference).
// Symmetric step weights (every path weighs n + m): a step (k,1) or (1,k) costs 2·d at its first cell
// and d at each further cell. Where pauseB[j] (b's frame j is a pause) the path may also move
// (1,0) into (i,j) at cost d, (0,1) into j at no cost and (0,1) out of it at cost d, so a pause of any
// length in a lines up with a pause of b and a pause of b that a lacks costs nothing; pauseA[i] likewise
// lets a's pauses run (1,0) without the slope limit. Either vector may be empty (no pauses). Throws std::invalid_argument for empty input
// or when the band cannot hold a path.
DtwResult dtw(const FeatureMatrix& a, const FeatureMatrix& b, const std::vector<bool>& pauseA, const std::vector<bool>& pauseB,
              const DtwOptions& options = {});

// Maps positions in b (fractional frame index; frame centres are integers) to fractional frame indices
// in a through a DTW path: between b's frames j and j+1 it runs linearly from the last frame of a matched
// to j to the first frame of a matched to j+1, so a boundary of b falls between the a-frames on either
// side of it. Monotone in position; clamped to the path's ends.
class PathMap {
public:
	PathMap(const std::vector<std::pair<int, int>>& path, int m);
	double operator()(double position) const;

private:
	std::vector<int> first_, last_;  // per frame of b: the first and last frame of a matched to it
};

}  // namespace talkhead::align
