// SPDX-License-Identifier: GPL-3.0-or-later
#include "align/features.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>

namespace talkhead::align {

namespace {

constexpr double kPi = 3.14159265358979323846;

int windowLength(int sampleRate, const FeatureOptions& o) { return std::max(1, int(std::lround(o.windowSeconds * sampleRate))); }
int hopLength(int sampleRate, const FeatureOptions& o) { return std::max(1, int(std::lround(o.hopSeconds * sampleRate))); }

// An in-place iterative radix-2 FFT of one size (a power of two), its bit-reversal swaps and twiddle factors
// computed once: the twiddles by the same recurrence (w^k as k products) that a per-call loop uses, so the
// results are bit for bit those of computing them inline.
class Fft {
public:
	explicit Fft(std::size_t n) : n_(n) {
		for (std::size_t i = 1, j = 0; i < n; ++i) {
			std::size_t bit = n >> 1;
			for (; j & bit; bit >>= 1) j ^= bit;
			j ^= bit;
			if (i < j) swaps_.emplace_back(std::uint32_t(i), std::uint32_t(j));
		}
		for (std::size_t len = 2; len <= n; len <<= 1) {
			const double a = -2 * kPi / double(len);
			const std::complex<double> w(std::cos(a), std::sin(a));
			std::complex<double> wk(1, 0);
			for (std::size_t k = 0; k < len / 2; ++k) {
				twiddles_.push_back(wk);
				wk *= w;
			}
		}
	}
	// Real and imaginary parts in separate arrays of n_ values.
	void operator()(double* re, double* im) const {
		for (const auto& [i, j] : swaps_) std::swap(re[i], re[j]), std::swap(im[i], im[j]);
		const std::complex<double>* tw = twiddles_.data();
		for (std::size_t len = 2; len <= n_; len <<= 1) {
			const std::size_t half = len / 2;
			for (std::size_t i = 0; i < n_; i += len) {
				double *ur = re + i, *ui = im + i, *vr = re + i + half, *vi = im + i + half;
				for (std::size_t k = 0; k < half; ++k) {
					// v·w as std::complex<double> multiplies finite values: (ac − bd, ad + bc).
					const double a = vr[k], b = vi[k], c = tw[k].real(), d = tw[k].imag();
					const double pr = a * c - b * d, pi = a * d + b * c;
					const double xr = ur[k], xi = ui[k];
					ur[k] = xr + pr, ui[k] = xi + pi;
					vr[k] = xr - pr, vi[k] = xi - pi;
				}
			}
			tw += half;
		}
	}

private:
	std::size_t n_;
	std::vector<std::pair<std::uint32_t, std::uint32_t>> swaps_;
	std::vector<std::complex<double>> twiddles_;  // per stage, w^0 … w^(len/2 − 1)
};

double hzToMel(double hz) { return 1127.0 * std::log(1.0 + hz / 700.0); }
double melToHz(double mel) { return 700.0 * (std::exp(mel / 1127.0) - 1.0); }

// Appends regression deltas of columns [from, from + count) as new columns.
void appendDeltas(FeatureMatrix& f, int from, int count) {
	const int oldDims = f.dims, newDims = oldDims + count;
	std::vector<float> out(std::size_t(f.frames) * std::size_t(newDims));
	for (int k = 0; k < f.frames; ++k) {
		std::copy(f.row(k), f.row(k) + oldDims, out.begin() + std::size_t(k) * std::size_t(newDims));
		for (int c = 0; c < count; ++c) {
			double num = 0;
			for (int t = 1; t <= 2; ++t) {
				const int a = std::min(f.frames - 1, k + t), b = std::max(0, k - t);
				num += t * (double(f.row(a)[from + c]) - double(f.row(b)[from + c]));
			}
			out[std::size_t(k) * std::size_t(newDims) + std::size_t(oldDims + c)] = float(num / 10.0);  // 2·(1² + 2²)
		}
	}
	f.data = std::move(out);
	f.dims = newDims;
}

}  // namespace

int frameCountFor(std::size_t samples, int sampleRate, const FeatureOptions& o) {
	const std::size_t win = std::size_t(windowLength(sampleRate, o)), hop = std::size_t(hopLength(sampleRate, o));
	return samples < win ? 0 : int(1 + (samples - win) / hop);
}

FeatureMatrix mfcc(const std::vector<float>& samples, int sampleRate, const FeatureOptions& o) {
	if (sampleRate <= 0) throw std::invalid_argument("mfcc: bad sample rate");
	const int win = windowLength(sampleRate, o), hop = hopLength(sampleRate, o);
	int nfft = 1;
	while (nfft < win) nfft <<= 1;
	const int bins = nfft / 2 + 1;
	// Mel filterbank (triangles in Hz between equally spaced mel points).
	const double high = std::min(o.highHz, 0.95 * sampleRate / 2.0), low = std::min(o.lowHz, high / 2);
	const double mLow = hzToMel(low), mHigh = hzToMel(high);
	std::vector<double> edges(std::size_t(o.melBands) + 2);
	for (std::size_t b = 0; b < edges.size(); ++b) edges[b] = melToHz(mLow + (mHigh - mLow) * double(b) / double(o.melBands + 1));
	// Each filter as its non-zero weights from its first bin (the sum skips zero weights, in bin order).
	std::vector<int> firstBin(std::size_t(o.melBands), 0);
	std::vector<std::vector<double>> filters(std::size_t(o.melBands));
	for (int b = 0; b < o.melBands; ++b) {
		std::vector<double> all(std::size_t(bins), 0.0);
		for (int k = 0; k < bins; ++k) {
			const double hz = double(k) * sampleRate / nfft;
			const double l = edges[std::size_t(b)], c = edges[std::size_t(b) + 1], r = edges[std::size_t(b) + 2];
			double w = 0;
			if (hz > l && hz <= c) w = (hz - l) / (c - l);
			else if (hz > c && hz < r) w = (r - hz) / (r - c);
			all[std::size_t(k)] = w;
		}
		int lo = 0, hi = bins;
		while (lo < bins && !(all[std::size_t(lo)] > 0)) ++lo;
		while (hi > lo && !(all[std::size_t(hi - 1)] > 0)) --hi;
		firstBin[std::size_t(b)] = lo;
		filters[std::size_t(b)].assign(all.begin() + lo, all.begin() + hi);
	}
	std::vector<double> window(static_cast<std::size_t>(win));
	for (int n = 0; n < win; ++n) window[std::size_t(n)] = 0.54 - 0.46 * std::cos(2 * kPi * n / std::max(1, win - 1));
	std::vector<double> dct(std::size_t(o.cepstra) * std::size_t(o.melBands));
	for (int c = 0; c < o.cepstra; ++c)
		for (int b = 0; b < o.melBands; ++b) dct[std::size_t(c) * std::size_t(o.melBands) + std::size_t(b)] = std::cos(kPi * c * (b + 0.5) / o.melBands);
	const double dctScale = std::sqrt(2.0 / o.melBands);
	const Fft fft(static_cast<std::size_t>(nfft));
	FeatureMatrix f;
	f.frames = frameCountFor(samples.size(), sampleRate, o);
	f.dims = o.cepstra;
	f.data.assign(std::size_t(f.frames) * std::size_t(f.dims), 0.f);
	std::vector<double> re(static_cast<std::size_t>(nfft)), im(static_cast<std::size_t>(nfft));
	std::vector<double> mel(std::size_t(o.melBands));
	std::uint32_t seed = 12345;  // deterministic dither (about −90 dBFS)
	const auto dither = [&seed] {
		seed = seed * 1664525u + 1013904223u;
		return (double(seed >> 8) / double(1u << 24) - 0.5) * 6e-5;
	};
	for (int k = 0; k < f.frames; ++k) {
		const std::size_t s0 = std::size_t(k) * std::size_t(hop);
		double prev = s0 > 0 ? samples[s0 - 1] : samples[s0];
		for (int n = 0; n < win; ++n) {
			const double x = double(samples[s0 + std::size_t(n)]) + dither();
			re[std::size_t(n)] = (x - 0.97 * prev) * window[std::size_t(n)];
			prev = x;
		}
		std::fill(re.begin() + win, re.end(), 0.0);
		std::fill(im.begin(), im.end(), 0.0);
		fft(re.data(), im.data());
		for (int b = 0; b < o.melBands; ++b) {
			double e = 0;
			const std::vector<double>& fw = filters[std::size_t(b)];
			const double *r = re.data() + firstBin[std::size_t(b)], *i = im.data() + firstBin[std::size_t(b)];
			for (std::size_t j = 0; j < fw.size(); ++j)
				if (fw[j] > 0) e += fw[j] * (r[j] * r[j] + i[j] * i[j]);
			mel[std::size_t(b)] = std::log(std::max(e / win, 1e-12));
		}
		float* out = f.row(k);
		for (int c = 0; c < o.cepstra; ++c) {
			double s = 0;
			const double* d = dct.data() + std::size_t(c) * std::size_t(o.melBands);
			for (int b = 0; b < o.melBands; ++b) s += mel[std::size_t(b)] * d[b];
			out[c] = float(s * dctScale);
		}
	}
	if (o.deltas) appendDeltas(f, 0, o.cepstra);
	if (o.deltas && o.deltaDeltas) appendDeltas(f, o.cepstra, o.cepstra);
	return f;
}

std::vector<float> frameLevels(const std::vector<float>& samples, int sampleRate, const FeatureOptions& o) {
	const int win = windowLength(sampleRate, o), hop = hopLength(sampleRate, o);
	const int frames = frameCountFor(samples.size(), sampleRate, o);
	std::vector<float> out(static_cast<std::size_t>(frames));
	for (int k = 0; k < frames; ++k) {
		const std::size_t s0 = std::size_t(k) * std::size_t(hop);
		double sum = 0, mean = 0;
		for (int n = 0; n < win; ++n) mean += samples[s0 + std::size_t(n)];
		mean /= win;  // no DC offset
		for (int n = 0; n < win; ++n) {
			const double x = samples[s0 + std::size_t(n)] - mean;
			sum += x * x;
		}
		out[std::size_t(k)] = float(10 * std::log10(std::max(sum / win, 1e-12)));
	}
	return out;
}

void normalise(FeatureMatrix& f, const std::vector<bool>& use) {
	int count = 0;
	for (int k = 0; k < f.frames; ++k) count += use.empty() || (std::size_t(k) < use.size() && use[std::size_t(k)]);
	const bool all = count < 2;
	for (int d = 0; d < f.dims; ++d) {
		double sum = 0, sq = 0;
		int n = 0;
		for (int k = 0; k < f.frames; ++k) {
			if (!all && !use.empty() && !(std::size_t(k) < use.size() && use[std::size_t(k)])) continue;
			const double v = f.row(k)[d];
			sum += v;
			sq += v * v;
			++n;
		}
		if (n == 0) return;
		const double mean = sum / n, sd = std::sqrt(std::max(sq / n - mean * mean, 1e-10));
		for (int k = 0; k < f.frames; ++k) f.row(k)[d] = float((f.row(k)[d] - mean) / sd);
	}
}

float frameDistance(const FeatureMatrix& a, int i, const FeatureMatrix& b, int j) {
	const float* x = a.row(i);
	const float* y = b.row(j);
	float s = 0;
	for (int d = 0; d < a.dims; ++d) {
		const float t = x[d] - y[d];
		s += t * t;
	}
	return std::sqrt(s);
}

namespace {

// The path back from (i, j) to (0, 0) through the step codes (dtw's), in order from the start.
std::vector<std::pair<int, int>> backtrack(const std::vector<std::int8_t>& step, const std::vector<std::size_t>& offset, const std::vector<int>& lo, int i, int j) {
	std::vector<std::pair<int, int>> path;
	while (true) {
		path.emplace_back(i, j);
		if (i == 0 && j == 0) break;
		const int code = step[offset[std::size_t(i)] + std::size_t(j - lo[std::size_t(i)])];
		if (code == 100) {
			--i;
		} else if (code == 101) {
			--j;
		} else if (code > 0) {
			for (int k = 1; k < code; ++k) path.emplace_back(i - k, j);
			i -= code;
			--j;
		} else if (code < 0) {
			for (int k = 1; k < -code; ++k) path.emplace_back(i, j - k);
			--i;
			j += code;
		} else {
			throw std::logic_error("dtw: broken back-pointer");
		}
	}
	std::reverse(path.begin(), path.end());
	return path;
}

// The band: row i covers columns [lo[i], hi[i]] (all of them without a band); its cells are stored row after
// row from offset[i].
struct DtwBand {
	std::vector<int> lo, hi;
	std::vector<std::size_t> offset;
	DtwBand(int n, int m, double width) : lo(std::size_t(n)), hi(std::size_t(n)), offset(std::size_t(n) + 1, 0) {
		for (int i = 0; i < n; ++i) {
			if (width > 0) {
				const double centre = n > 1 ? double(i) * double(m - 1) / double(n - 1) : 0.0;
				lo[std::size_t(i)] = std::max(0, int(std::floor(centre - width)));
				hi[std::size_t(i)] = std::min(m - 1, int(std::ceil(centre + width)));
			} else {
				lo[std::size_t(i)] = 0;
				hi[std::size_t(i)] = m - 1;
			}
			offset[std::size_t(i) + 1] = offset[std::size_t(i)] + std::size_t(hi[std::size_t(i)] - lo[std::size_t(i)] + 1);
		}
	}
};

}  // namespace

DtwResult dtw(const FeatureMatrix& a, const FeatureMatrix& b, const std::vector<bool>& pauseA, const std::vector<bool>& pauseB, const DtwOptions& o) {
	const int n = a.frames, m = b.frames;
	if (n == 0 || m == 0) throw std::invalid_argument("dtw: empty sequence");
	if (a.dims != b.dims) throw std::invalid_argument("dtw: feature dimensions differ");
	const int K = std::max(1, o.maxSlope);
	const auto isPauseA = [&](int i) { return std::size_t(i) < pauseA.size() && pauseA[std::size_t(i)]; };
	const auto isPauseB = [&](int j) { return std::size_t(j) < pauseB.size() && pauseB[std::size_t(j)]; };
	const DtwBand band(n, m, o.band);
	const std::vector<int>&lo = band.lo, &hi = band.hi;
	const std::vector<std::size_t>& offset = band.offset;
	// Step codes: 1..K = (k,1); -1..-K = (1,k) with k ≥ 2 coded as −k; 100 = (1,0); 101 = (0,1); 0 = start.
	std::vector<std::int8_t> step(offset[std::size_t(n)], 0);
	constexpr float kInf = std::numeric_limits<float>::infinity();
	const int ring = K + 1;
	std::vector<std::vector<float>> D(static_cast<std::size_t>(ring)), C(static_cast<std::size_t>(ring));  // accumulated and local cost, last K+1 rows
	const auto at = [&](std::vector<std::vector<float>>& r, int i, int j) -> float {
		if (i < 0 || j < lo[std::size_t(i)] || j > hi[std::size_t(i)]) return kInf;
		return r[std::size_t(i % ring)][std::size_t(j - lo[std::size_t(i)])];
	};
	for (int i = 0; i < n; ++i) {
		auto& Di = D[std::size_t(i % ring)];
		auto& Ci = C[std::size_t(i % ring)];
		const int l = lo[std::size_t(i)], h = hi[std::size_t(i)];
		Di.assign(std::size_t(h - l + 1), kInf);
		Ci.resize(std::size_t(h - l + 1));
		for (int j = l; j <= h; ++j) Ci[std::size_t(j - l)] = frameDistance(a, i, b, j);
		for (int j = l; j <= h; ++j) {
			const float d = Ci[std::size_t(j - l)];
			float best = kInf;
			std::int8_t code = 0;
			if (i == 0 && j == 0) {
				best = 2 * d;
			} else {
				// (k,1): from (i−k, j−1) through a-frames i−k+1 … i at column j.
				float run = 0;
				for (int k = 1; k <= K && i - k >= 0; ++k) {
					const float dk = at(C, i - k + 1, j);
					if (dk == kInf) break;
					run += dk;
					const float prev = at(D, i - k, j - 1);
					const float v = prev + run + dk;  // the first cell (i−k+1) counts twice
					if (v < best) best = v, code = std::int8_t(k);
				}
				// (1,k), k ≥ 2: from (i−1, j−k) through b-frames j−k+1 … j in row i.
				run = d;
				for (int k = 2; k <= K && j - k >= 0; ++k) {
					const float dk = at(C, i, j - k + 1);
					if (dk == kInf) break;
					run += dk;
					const float v = at(D, i - 1, j - k) + run + dk;
					if (v < best) best = v, code = std::int8_t(-k);
				}
				if (isPauseB(j) || isPauseA(i)) {
					const float v = at(D, i - 1, j) + d;
					if (v < best) best = v, code = 100;
				}
				if (isPauseB(j) || (j > 0 && isPauseB(j - 1))) {
					const float v = at(D, i, j - 1) + (isPauseB(j) ? 0.f : d);  // skipping a pause frame is free
					if (v < best) best = v, code = 101;
				}
			}
			Di[std::size_t(j - l)] = best;
			step[offset[std::size_t(i)] + std::size_t(j - l)] = code;
		}
	}
	const float total = at(D, n - 1, m - 1);
	if (!(total < kInf)) throw std::invalid_argument("dtw: no path within the band and slope limits");
	DtwResult r;
	r.cost = double(total) / double(n + m);
	r.path = backtrack(step, offset, lo, n - 1, m - 1);
	return r;
}

PathMap::PathMap(const std::vector<std::pair<int, int>>& path, int m) : first_(std::size_t(std::max(m, 1)), -1), last_(std::size_t(std::max(m, 1)), -1) {
	for (const auto& [i, j] : path) {
		if (j < 0 || j >= m) continue;
		if (first_[std::size_t(j)] < 0) first_[std::size_t(j)] = i;
		last_[std::size_t(j)] = i;
	}
	// Columns the path skipped (none for a connected path) take their neighbours' values.
	for (std::size_t j = 1; j < first_.size(); ++j)
		if (first_[j] < 0) first_[j] = last_[j] = last_[j - 1];
	if (first_[0] < 0) first_[0] = last_[0] = 0;
}

double PathMap::operator()(double position) const {
	const int m = int(first_.size());
	if (position <= 0) return first_[0] + std::max(position, -0.5);
	if (position >= m - 1) return last_[std::size_t(m - 1)] + std::min(position - (m - 1), 0.5);
	const int j = int(std::floor(position));
	const double f = position - j;
	return last_[std::size_t(j)] + f * (first_[std::size_t(j) + 1] - last_[std::size_t(j)]);
}

}  // namespace talkhead::align
