// SPDX-License-Identifier: GPL-3.0-or-later
#include "track/compare.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "base/error.h"
#include "base/json.h"
#include "track/from_video.h"

namespace talkhead {

namespace {

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// Linear interpolation of the frames' values at time t (NaN across gaps or outside the frames).
struct Interpolator {
	const LandmarkTrack& track;
	const std::vector<double>& v;
	std::size_t i = 0;
	double at(double t) {
		const auto& f = track.frames;
		while (i + 1 < f.size() && toSeconds(f[i + 1].time) <= t) ++i;
		if (f.empty() || t < toSeconds(f[0].time) - 0.05) return kNoValue;
		if (i + 1 >= f.size()) return t - toSeconds(f[i].time) <= 0.05 && f[i].found ? v[i] : kNoValue;
		const double t0 = toSeconds(f[i].time), t1 = toSeconds(f[i + 1].time);
		if (t1 - t0 > 0.2 + 1e-9) return kNoValue;
		if (t < t0) return f[i].found ? v[i] : kNoValue;
		const double w = (t - t0) / (t1 - t0);
		return (1 - w) * v[i] + w * v[i + 1];  // NaN when either is lost
	}
};

}  // namespace

std::vector<double> resampleSignal(const LandmarkTrack& track, const std::vector<double>& perFrame, double rateHz, double duration) {
	const std::size_t n = std::size_t(std::floor(duration * rateHz + 1e-9));
	std::vector<double> out(n);
	Interpolator ip{track, perFrame};
	for (std::size_t k = 0; k < n; ++k) out[k] = ip.at(double(k) / rateHz);
	return out;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b, int lag) {
	double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
	long n = 0;
	for (long i = 0; i < long(a.size()); ++i) {
		const long j = i + lag;
		if (j < 0 || j >= long(b.size()) || !std::isfinite(a[std::size_t(i)]) || !std::isfinite(b[std::size_t(j)])) continue;
		const double x = a[std::size_t(i)], y = b[std::size_t(j)];
		sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y, ++n;
	}
	if (n < 3) return kNoValue;
	const double va = saa - sa * sa / double(n), vb = sbb - sb * sb / double(n);
	if (va <= 1e-15 || vb <= 1e-15) return kNoValue;
	return (sab - sa * sb / double(n)) / std::sqrt(va * vb);
}

LipSyncReport compareLipSync(const LandmarkTrack& synth, const LandmarkTrack& real, double rateHz, double maxLagMs) {
	LipSyncReport r;
	r.rateHz = rateHz;
	auto lastTime = [](const LandmarkTrack& t) {
		if (t.frames.empty()) return 0.0;
		const double step = t.info.fpsNum > 0 ? double(t.info.fpsDen) / t.info.fpsNum : 0.04;
		return toSeconds(t.frames.back().time) + step;
	};
	r.duration = std::min(lastTime(synth), lastTime(real));
	r.coverageSynth = synth.frames.empty() ? 0 : double(synth.foundCount()) / double(synth.frames.size());
	r.coverageReal = real.frames.empty() ? 0 : double(real.foundCount()) / double(real.frames.size());
	const auto a = resampleSignal(synth, innerLipOpening(synth, false), rateHz, r.duration);
	const auto b = resampleSignal(real, innerLipOpening(real, false), rateHz, r.duration);
	for (std::size_t k = 0; k < a.size(); ++k) r.samples += std::isfinite(a[k]) && std::isfinite(b[k]);
	r.r0 = pearson(a, b, 0);
	r.bestR = r.r0;
	r.bestLagMs = 0;
	const int maxLag = int(std::floor(maxLagMs * rateHz / 1000 + 1e-9));
	for (int lag = -maxLag; lag <= maxLag; ++lag) {
		// b[i] against a[i + lag]: lag > 0 = the synthesized mouth later.
		const double c = pearson(b, a, lag);
		if (std::isfinite(c) && (!std::isfinite(r.bestR) || c > r.bestR + 1e-12)) r.bestR = c, r.bestLagMs = lag * 1000.0 / rateHz;
	}
	// LMD: per-frame normalised mouths, resampled point by point.
	std::vector<std::vector<double>> ma(40), mb(40);
	auto mouthSignals = [&](const LandmarkTrack& t, std::vector<std::vector<double>>& out) {
		std::vector<std::vector<double>> perFrame(40, std::vector<double>(t.frames.size(), kNoValue));
		for (std::size_t f = 0; f < t.frames.size(); ++f) {
			if (!t.frames[f].found) continue;
			const Points m = normalisedMouth(t.frames[f].points);
			for (int k = 0; k < 20; ++k) perFrame[std::size_t(2 * k)][f] = m(k, 0), perFrame[std::size_t(2 * k + 1)][f] = m(k, 1);
		}
		for (int c = 0; c < 40; ++c) out[std::size_t(c)] = resampleSignal(t, perFrame[std::size_t(c)], rateHz, r.duration);
	};
	mouthSignals(synth, ma);
	mouthSignals(real, mb);
	// Mean shapes over the shared samples, and the similarity taking the synthesized mean onto the real one.
	Points meanA = Points::Zero(20, 2), meanB = Points::Zero(20, 2);
	std::vector<std::size_t> shared;
	for (std::size_t k = 0; k < a.size(); ++k) {
		bool ok = true;
		for (int c = 0; c < 40 && ok; ++c) ok = std::isfinite(ma[std::size_t(c)][k]) && std::isfinite(mb[std::size_t(c)][k]);
		if (ok) shared.push_back(k);
	}
	if (shared.empty()) throw Error("no instant where both videos show a face (coverage " + std::to_string(r.coverageSynth) + " and " + std::to_string(r.coverageReal) + ")");
	for (std::size_t k : shared)
		for (int p = 0; p < 20; ++p)
			for (int c = 0; c < 2; ++c) meanA(p, c) += ma[std::size_t(2 * p + c)][k], meanB(p, c) += mb[std::size_t(2 * p + c)][k];
	meanA /= double(shared.size());
	meanB /= double(shared.size());
	const Similarity T = alignSimilarity(meanA, meanB, Eigen::VectorXd::Ones(20));
	double sum = 0;
	for (std::size_t k : shared) {
		Points pa(20, 2), pb(20, 2);
		for (int p = 0; p < 20; ++p)
			for (int c = 0; c < 2; ++c) pa(p, c) = ma[std::size_t(2 * p + c)][k], pb(p, c) = mb[std::size_t(2 * p + c)][k];
		sum += (T.apply(pa) - pb).rowwise().norm().mean();
	}
	r.lmd = sum / double(shared.size());
	return r;
}

std::string LipSyncReport::json() const {
	return JsonObject()
	    .add("duration", duration, "%.4f")
	    .add("rate_hz", rateHz, "%.4f")
	    .add("samples", static_cast<long long>(samples))
	    .add("r_lag0", r0, "%.4f")
	    .add("r_best", bestR, "%.4f")
	    .add("best_lag_ms", bestLagMs, "%.4f")
	    .add("lmd", lmd, "%.4f")
	    .add("coverage_synth", coverageSynth, "%.4f")
	    .add("coverage_real", coverageReal, "%.4f")
	    .str();
}

std::string LipSyncReport::text() const {
	char b[512];
	std::snprintf(b, sizeof b,
	              "lip opening r (lag 0)   %.3f\nlip opening r (best)    %.3f at %+.0f ms (synthesized later when > 0)\nmouth LMD               %.4f eye distances\n"
	              "coverage                %.1f %% synthesized, %.1f %% real\ncompared                %.2f s at %.0f Hz (%zu samples with both faces)\n",
	              r0, bestR, bestLagMs, lmd, 100 * coverageSynth, 100 * coverageReal, duration, rateHz, samples);
	return b;
}

}  // namespace talkhead
