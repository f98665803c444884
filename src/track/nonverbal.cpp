// SPDX-License-Identifier: GPL-3.0-or-later
#include "track/nonverbal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "base/error.h"
#include "geometry/scheme.h"
#include "geometry/shape.h"
#include "track/from_video.h"
#include "geometry/eigen_products.h"

namespace talkhead {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The modulator's blink (synth/modulator.cpp): half shut 37.5 ms after its start (smoothstep over 75 ms),
// shut from 75 ms to 100 ms.
constexpr double kBlinkHalfClosed = 0.0375, kBlinkShutOffset = 0.0875;
// Nose-tip depth in front of the outer eye corners, per outer-eye-corner distance (anthropometry: the
// exocanthia ~90 mm apart, the pronasale ~35–40 mm in front of them): a yaw of ψ moves the tip across the
// eye line's midpoint by about 0.42 tan ψ eye distances.
constexpr double kNoseDepth = 0.42;

// The rigid points of the iBUG layout (issue 17: outer eye corners, nose tip, nostrils) and their weights.
Eigen::VectorXd rigidWeights() {
	Eigen::VectorXd w = Eigen::VectorXd::Zero(kIbugPoints);
	for (int i : {36, 45}) w(i) = 1.0;   // outer eye corners
	for (int i : {39, 42}) w(i) = 1.0;   // inner eye corners
	w(27) = 0.5;                         // top of the nose bridge
	w(30) = 1.0;                         // nose tip
	for (int i : {31, 33, 35}) w(i) = 0.5;  // nostril wings, subnasale
	return w;
}

double smoothstep(double u) {
	u = std::clamp(u, 0.0, 1.0);
	return u * u * (3 - 2 * u);
}

// Fills the entries where ok[i] is false by zero-tangent Hermite interpolation between the valid values on
// either side (held at the ends).
void bridge(std::vector<double>& v, const std::vector<bool>& ok) {
	const std::size_t n = v.size();
	std::size_t i = 0;
	while (i < n) {
		if (ok[i]) {
			++i;
			continue;
		}
		std::size_t j = i;
		while (j < n && !ok[j]) ++j;
		const bool before = i > 0, after = j < n;
		for (std::size_t k = i; k < j; ++k) {
			if (before && after) v[k] = v[i - 1] + (v[j] - v[i - 1]) * smoothstep(double(k - (i - 1)) / double(j - (i - 1)));
			else if (before) v[k] = v[i - 1];
			else if (after) v[k] = v[j];
			else v[k] = 0;
		}
		i = j;
	}
}

// A centred Gaussian of `sigma` samples (truncated at 3σ, renormalised at the ends).
void smoothCentred(std::vector<double>& v, double sigma) {
	if (!(sigma > 0.3) || v.size() < 3) return;
	const long r = long(std::ceil(3 * sigma));
	std::vector<double> k(std::size_t(2 * r + 1));
	for (long i = -r; i <= r; ++i) k[std::size_t(i + r)] = std::exp(-0.5 * double(i * i) / (sigma * sigma));
	const std::vector<double> in = v;
	const long n = long(v.size());
	for (long i = 0; i < n; ++i) {
		double sum = 0, weight = 0;
		for (long j = std::max(0L, i - r); j <= std::min(n - 1, i + r); ++j) sum += k[std::size_t(j - i + r)] * in[std::size_t(j)], weight += k[std::size_t(j - i + r)];
		v[std::size_t(i)] = sum / weight;
	}
}

// min ‖A w − d‖² + λ‖w‖² with 0 ≤ w ≤ hi, by projected coordinate descent (deterministic, a few unknowns).
Eigen::VectorXd boxedRidge(const Eigen::MatrixXd& A, const Eigen::VectorXd& d, double lambda, double hi) {
	pinEigenBlocking();  // products that round the same on every machine (D74)
	const Eigen::MatrixXd G = A.transpose() * A + lambda * Eigen::MatrixXd::Identity(A.cols(), A.cols());
	const Eigen::VectorXd b = A.transpose() * d;
	Eigen::VectorXd w = Eigen::VectorXd::Zero(A.cols());
	for (int it = 0; it < 60; ++it) {
		double change = 0;
		for (Eigen::Index k = 0; k < w.size(); ++k) {
			const double g = b(k) - G.row(k).dot(w) + G(k, k) * w(k);
			const double nw = std::clamp(g / G(k, k), 0.0, hi);
			change = std::max(change, std::abs(nw - w(k)));
			w(k) = nw;
		}
		if (change < 1e-7) break;
	}
	return w;
}

struct Part {
	const char* name;
	int first, last;  // point range (inclusive)
	int side;
	std::vector<const char*> aus;
};

}  // namespace

ControlCurves NonVerbalTrack::curves() const {
	ControlCurves c;
	c.rate = rate;
	c.start = start;
	if (options.head) {
		for (const NonVerbalFrame& f : frames) {
			c.roll.push_back(float(f.roll));
			c.x.push_back(float(f.x));
			c.y.push_back(float(f.y));
			c.scale.push_back(float(f.scale));
		}
	}
	for (std::size_t k = 0; k < channels.size(); ++k) {
		ControlCurves::Au a;
		a.au = channels[k].au;
		a.side = channels[k].side;
		for (const NonVerbalFrame& f : frames) a.weight.push_back(float(f.au[k]));
		c.aus.push_back(std::move(a));
	}
	return c;
}

namespace {

// Neutral: the found, confident frames of the first second (or the first N), each aligned to the first by a
// similarity on the rigid points, then the per-point median. Returns the shape and how many frames made it.
std::pair<Points, std::size_t> neutralShape(const LandmarkTrack& track, const NonVerbalOptions& o, const Eigen::VectorXd& rigid) {
	const std::size_t n = track.frames.size();
	std::vector<const FrameLandmarks*> neutralSet;
	for (const auto& f : track.frames) {
		if (!f.found || f.confidence < o.minConfidence) continue;
		if (o.neutralFrames > 0 ? neutralSet.size() >= std::size_t(o.neutralFrames)
		                        : (!neutralSet.empty() && toSeconds(f.time - neutralSet.front()->time) > o.neutralSeconds))
			break;
		neutralSet.push_back(&f);
	}
	if (neutralSet.size() < 3) {  // a short or sparse first second: the first 25 usable frames
		neutralSet.clear();
		for (const auto& f : track.frames)
			if (f.found && f.confidence >= o.minConfidence && neutralSet.size() < 25) neutralSet.push_back(&f);
	}
	if (neutralSet.size() < 3)
		throw Error(track.source, 0, "too few frames with a face (" + std::to_string(track.foundCount()) + " of " + std::to_string(n) + ") to drive a face");
	Points neutral(kIbugPoints, 2);
	std::vector<Points> aligned;
	const Points& first = unsmoothedPoints(*neutralSet.front());
	for (const FrameLandmarks* f : neutralSet) aligned.push_back(alignSimilarity(unsmoothedPoints(*f), first, rigid).apply(unsmoothedPoints(*f)));
	std::vector<double> v(aligned.size());
	for (int i = 0; i < kIbugPoints; ++i)
		for (int c = 0; c < 2; ++c) {
			for (std::size_t k = 0; k < aligned.size(); ++k) v[k] = aligned[k](i, c);
			neutral(i, c) = percentile(v, 0.5);
		}
	return {neutral, neutralSet.size()};
}

// A face part's action units as a linear model of its points' displacements.
struct PartFit {
	Part part;
	std::size_t firstChannel;
	Eigen::MatrixXd A;  // (2 × points) × AUs, in the neutral eye frame, IOD units
	double lambda;
};

// The parts the options ask for, each with its templates; their channels appended to `channels`.
std::vector<PartFit> partFits(const NonVerbalOptions& o, const Scheme& scheme, std::vector<NonVerbalTrack::Channel>& channels) {
	std::vector<Part> parts;
	if (o.brows) {
		parts.push_back({"brow", 17, 21, -1, {"AU1", "AU2", "AU4"}});
		parts.push_back({"brow", 22, 26, +1, {"AU1", "AU2", "AU4"}});
	}
	if (o.eyes) {
		// AU5 widens, AU43 narrows (a squint; blinks are events). AU7's template barely moves the lids
		// (0.009 eye distances at full intensity): the tracker's jitter alone would read as AU7 0.4.
		parts.push_back({"eye", 36, 41, -1, {"AU5", "AU43"}});
		parts.push_back({"eye", 42, 47, +1, {"AU5", "AU43"}});
	}
	if (o.mouth) parts.push_back({"mouth", 48, 67, 0, {"AU10", "AU12", "AU15", "AU17", "AU20", "AU23", "AU24", "AU25", "AU26"}});
	std::vector<PartFit> fits;
	if (parts.empty()) return fits;
	const std::optional<AuTemplates> templates = findAuTemplates(scheme);
	if (!templates) throw Error("no action-unit templates for scheme ibug-68 (models/au-templates/ibug-68.tsv)");
	for (const Part& p : parts) {
		PartFit f{p, channels.size(), Eigen::MatrixXd(2 * (p.last - p.first + 1), Eigen::Index(p.aus.size())), 0};
		for (std::size_t a = 0; a < p.aus.size(); ++a) {
			const int t = templates->find(p.aus[a]);
			if (t < 0) throw Error("the ibug-68 action-unit templates have no " + std::string(p.aus[a]));
			for (int i = p.first; i <= p.last; ++i) {
				f.A(2 * (i - p.first), Eigen::Index(a)) = templates->offsets[std::size_t(t)](i, 0);
				f.A(2 * (i - p.first) + 1, Eigen::Index(a)) = templates->offsets[std::size_t(t)](i, 1);
			}
			channels.push_back({p.aus[a], p.side, p.name});
		}
		// A ridge against the tracker's jitter (about 0.003 eye distances per coordinate): with it, jitter
		// moves a weight by at most ~0.06, and an AU that moves the points alike with another cannot trade off
		// wildly; it shrinks a real AU5 by 13 %, a brow AU by under 1 %.
		f.lambda = 2.5e-4;
		fits.push_back(std::move(f));
	}
	return fits;
}

// Per frame: pose against the neutral, the parts' displacements projected onto the templates. Returns
// which frames are usable (a confident face, not turned past --max-turn).
std::vector<bool> measureFrames(const LandmarkTrack& track, const NonVerbalOptions& o, const Eigen::VectorXd& rigid, const Points& neutral,
                                const Scheme& scheme, const std::vector<PartFit>& fits, NonVerbalTrack& out) {
	const std::size_t n = track.frames.size();
	const EyeFrame nf = eyeFrame(scheme, neutral);
	// The head turns and scales about the point between the eyes (as the synthesizer draws curves).
	const Eigen::RowVector2d pivot = nf.origin;
	auto across = [&](const Points& p) {  // nose tip across the outer eye corners' midpoint, per their distance
		const Eigen::RowVector2d a = p.row(36), b = p.row(45), axis = (b - a).normalized();
		return (p.row(30) - 0.5 * (a + b)).dot(axis) / (b - a).norm();
	};
	const double neutralAcross = across(neutral);
	out.frames.resize(n);
	std::vector<bool> ok(n, false);
	for (std::size_t k = 0; k < n; ++k) {
		const FrameLandmarks& f = track.frames[k];
		NonVerbalFrame& r = out.frames[k];
		r.time = f.time;
		r.au.assign(out.channels.size(), 0.0);
		r.eyeOpening = kNaN;
		if (!f.found || f.confidence < o.minConfidence) continue;
		// The unsmoothed fit: the one-euro filter is causal and lags; the curves are smoothed centred later.
		const Points& raw = unsmoothedPoints(f);
		const Similarity s = alignSimilarity(neutral, raw, rigid);
		r.roll = s.angle();
		r.scale = s.scale();
		const Points c = s.apply(Points(pivot));
		r.x = (c(0, 0) - pivot(0)) / nf.iod;
		r.y = (c(0, 1) - pivot(1)) / nf.iod;
		r.yaw = std::atan((across(raw) - neutralAcross) / kNoseDepth) * 180 / kPi;
		r.eyeOpening = eyeAspect(raw);
		if (std::abs(r.yaw) > o.maxTurnDegrees) continue;
		ok[k] = true;
		const Points back = s.inverse().apply(raw);
		for (const PartFit& fit : fits) {
			const Part& p = fit.part;
			Eigen::VectorXd d(2 * (p.last - p.first + 1));
			for (int i = p.first; i <= p.last; ++i) {
				const Eigen::RowVector2d v = (back.row(i) - neutral.row(i)) / nf.iod;
				d(2 * (i - p.first)) = v.dot(nf.x);
				d(2 * (i - p.first) + 1) = v.dot(nf.y);
			}
			const Eigen::VectorXd w = boxedRidge(fit.A, d, fit.lambda, 1.5);
			for (Eigen::Index a = 0; a < w.size(); ++a) r.au[fit.firstChannel + std::size_t(a)] = w(a);
		}
	}
	return ok;
}

// Blinks: dips of the eye opening below 60 % of its running median (±2 s), each at its shut moment, into
// out.blinks. Returns the frames the eyes' action units may be read from (not in or around a blink).
std::vector<bool> findBlinks(NonVerbalTrack& out, const std::vector<bool>& ok) {
	const std::size_t n = out.frames.size();
	std::vector<double> openLevel(n, kNaN);
	{
		const long half = long(std::lround(2.0 * out.rate));
		std::vector<double> window;
		for (long k = 0; k < long(n); ++k) {
			window.clear();
			for (long j = std::max(0L, k - half); j <= std::min(long(n) - 1, k + half); ++j)
				if (ok[std::size_t(j)]) window.push_back(out.frames[std::size_t(j)].eyeOpening);
			openLevel[std::size_t(k)] = window.empty() ? kNaN : percentile(window, 0.5);
		}
		std::vector<double> all;
		for (std::size_t k = 0; k < n; ++k)
			if (ok[k]) all.push_back(out.frames[k].eyeOpening);
		out.neutralEyeOpening = percentile(all, 0.5);
	}
	std::vector<bool> eyeOk = ok;
	for (std::size_t k = 0; k < n;) {
		auto low = [&](std::size_t j, double f) { return ok[j] && out.frames[j].eyeOpening < f * openLevel[j]; };
		if (!low(k, 0.75)) {
			++k;
			continue;
		}
		std::size_t j = k, m = k;
		while (j < n && low(j, 0.75)) {
			if (out.frames[j].eyeOpening < out.frames[m].eyeOpening) m = j;
			++j;
		}
		const double length = double(j - k) / out.rate;
		if (low(m, 0.6) && length <= 0.6) {
			// The lids' half-way moment on the way down (the falling edge is fast and sharp; the minimum is
			// blurred by the slow opening): where the opening crosses the middle of the dip, interpolated.
			const double level = 0.5 * (openLevel[m] + out.frames[m].eyeOpening);
			double t = toSeconds(out.frames[m].time);
			for (std::size_t i = m; i > 0 && ok[i - 1]; --i)
				if (out.frames[i - 1].eyeOpening >= level) {
					const double a = out.frames[i - 1].eyeOpening, b = out.frames[i].eyeOpening;
					t = toSeconds(out.frames[i - 1].time) + (a > b ? (a - level) / (a - b) : 0.0) / out.rate;
					break;
				}
			const Ticks start = ticksFromSeconds(std::max(0.0, t - kBlinkHalfClosed));
			if (out.blinks.empty() || start - out.blinks.back() > ticksFromSeconds(0.3)) out.blinks.push_back(start);
		}
		// The eyes' action units hold through the dip, from two frames before it until the eyes are open again.
		std::size_t back = j;
		while (back < n && ok[back] && out.frames[back].eyeOpening < 0.9 * openLevel[back] && back < j + std::size_t(out.rate / 2)) ++back;
		for (std::size_t q = (k > 1 ? k - 2 : 0); q < std::min(n, back + 1); ++q) eyeOk[q] = false;
		k = j;
	}

	return eyeOk;
}

// Dropped frames (and, for the eyes' AUs, blinks) bridged by Hermite interpolation, then smoothed.
void bridgeAndSmooth(NonVerbalTrack& out, const std::vector<bool>& ok, const std::vector<bool>& eyeOk) {
	const std::size_t n = out.frames.size();
	auto column = [&](auto get) {
		std::vector<double> v(n);
		for (std::size_t k = 0; k < n; ++k) v[k] = get(out.frames[k]);
		return v;
	};
	auto fill = [&](auto ref, const std::vector<bool>& valid, double sigma) {
		std::vector<double> v = column([&](NonVerbalFrame& f) { return ref(f); });
		bridge(v, valid);
		smoothCentred(v, sigma);
		for (std::size_t k = 0; k < n; ++k) ref(out.frames[k]) = v[k];
	};
	// Then a centred Gaussian (no lag: the whole video is known) removes the predictor's jitter: 40 ms for
	// the head, 60 ms for the action units.
	const double headSigma = 0.04 * out.rate, auSigma = 0.06 * out.rate;
	fill([](NonVerbalFrame& f) -> double& { return f.roll; }, ok, headSigma);
	fill([](NonVerbalFrame& f) -> double& { return f.x; }, ok, headSigma);
	fill([](NonVerbalFrame& f) -> double& { return f.y; }, ok, headSigma);
	fill([](NonVerbalFrame& f) -> double& { return f.scale; }, ok, headSigma);
	fill([](NonVerbalFrame& f) -> double& { return f.yaw; }, ok, headSigma);
	for (std::size_t c = 0; c < out.channels.size(); ++c)
		fill([c](NonVerbalFrame& f) -> double& { return f.au[c]; }, out.channels[c].part == "eye" ? eyeOk : ok, auSigma);
}

// The spans without a usable face, into out.bridged, with a warning for each of 0.5 s or more.
void noteBridgedSpans(NonVerbalTrack& out, const std::vector<bool>& ok) {
	const std::size_t n = out.frames.size();
	for (std::size_t k = 0; k < n; ++k) out.frames[k].valid = ok[k];
	for (std::size_t k = 0; k < n;) {
		if (ok[k]) {
			++k;
			continue;
		}
		std::size_t j = k;
		while (j < n && !ok[j]) ++j;
		const Ticks a = out.frames[k].time, b = j < n ? out.frames[j].time : out.frames[j - 1].time + ticksFromSeconds(1 / out.rate);
		out.bridged.emplace_back(a, b);
		if (toSeconds(b - a) >= 0.5) {
			char m[200];
			std::snprintf(m, sizeof m, "no usable face from %.2f s to %.2f s (%.1f s): the head and face are bridged over it", toSeconds(a), toSeconds(b),
			              toSeconds(b - a));
			out.warnings.push_back(m);
		}
		k = j;
	}
}

}  // namespace

NonVerbalTrack analyseNonVerbal(const LandmarkTrack& track, const NonVerbalOptions& o) {
	NonVerbalTrack out;
	out.source = track.source;
	out.options = o;
	const std::size_t n = track.frames.size();
	if (n == 0) throw Error(track.source, 0, "no frames");
	for (const auto& f : track.frames)
		if (f.found && f.points.rows() != kIbugPoints) throw Error(track.source, 0, "the tracked faces must have the 68 iBUG points");
	// The rate: the video's, else from the frames' times.
	if (track.info.fpsNum > 0 && track.info.fpsDen > 0) out.rate = double(track.info.fpsNum) / track.info.fpsDen;
	else if (n > 1 && track.frames.back().time > track.frames.front().time)
		out.rate = double(n - 1) / toSeconds(track.frames.back().time - track.frames.front().time);
	out.start = track.frames.front().time;
	const Eigen::VectorXd rigid = rigidWeights();
	const auto [neutral, neutralCount] = neutralShape(track, o, rigid);
	out.neutralCount = neutralCount;
	const Scheme scheme = loadScheme("ibug-68");
	const std::vector<PartFit> fits = partFits(o, scheme, out.channels);
	const std::vector<bool> ok = measureFrames(track, o, rigid, neutral, scheme, fits, out);
	const std::size_t usable = std::size_t(std::count(ok.begin(), ok.end(), true));
	if (usable < 3 || usable * 10 < n)
		throw Error(track.source, 0, "a usable face in only " + std::to_string(usable) + " of " + std::to_string(n) + " frames (lost, unsure or turned past " +
		                                 std::to_string(int(o.maxTurnDegrees)) + "°): too few to drive a face");
	const std::vector<bool> eyeOk = findBlinks(out, ok);
	bridgeAndSmooth(out, ok, eyeOk);
	noteBridgedSpans(out, ok);
	return out;
}

namespace {

// The plot's curves and panels.
struct Series {
	std::string label;
	std::vector<double> v;
	cv::Scalar colour;
};
struct Panel {
	std::string title;
	std::vector<Series> series;
	double lo, hi;
	bool blinks = false;
};

// The plot's panels: head rotation, head position, eye opening, and the action units of each face part.
std::vector<Panel> nonVerbalPanels(const NonVerbalTrack& t) {
	const cv::Scalar palette[] = {{200, 60, 40}, {40, 120, 220}, {40, 160, 60}, {150, 60, 170}, {230, 140, 20}, {20, 170, 170}, {120, 120, 120},
	                              {220, 60, 140}, {90, 90, 20}};
	auto series = [&](auto get) {
		std::vector<double> v;
		for (const auto& f : t.frames) v.push_back(get(f));
		return v;
	};
	std::vector<Panel> panels;
	panels.push_back({"head rotation (deg)", {{"roll", series([](const NonVerbalFrame& f) { return f.roll * 180 / kPi; }), palette[0]},
	                                          {"yaw (estimate)", series([](const NonVerbalFrame& f) { return f.yaw; }), palette[1]}}, -10, 10});
	panels.push_back({"head position (eye distances) and scale - 1",
	                  {{"x", series([](const NonVerbalFrame& f) { return f.x; }), palette[0]},
	                   {"y", series([](const NonVerbalFrame& f) { return f.y; }), palette[1]},
	                   {"scale-1", series([](const NonVerbalFrame& f) { return f.scale - 1; }), palette[2]}}, -0.3, 0.3});
	panels.push_back({"eye opening (blinks marked)", {{"eye aspect", series([](const NonVerbalFrame& f) { return f.eyeOpening; }), palette[3]}}, 0,
	                  std::max(0.1, 1.6 * t.neutralEyeOpening), true});
	for (const char* part : {"brow", "eye", "mouth"}) {
		Panel p{std::string(part) + " action units (weight)", {}, 0, 1};
		for (std::size_t c = 0; c < t.channels.size(); ++c) {
			if (t.channels[c].part != part) continue;
			const std::string side = t.channels[c].side < 0 ? " R" : t.channels[c].side > 0 ? " L" : "";
			p.series.push_back({t.channels[c].au + side, series([c](const NonVerbalFrame& f) { return f.au[c]; }), palette[p.series.size() % 9]});
		}
		for (const auto& s : p.series)
			for (double v : s.v)
				if (std::isfinite(v)) p.hi = std::max(p.hi, v);
		if (!p.series.empty()) panels.push_back(std::move(p));
	}
	for (auto& p : panels)
		if (p.title.rfind("head", 0) == 0)
			for (const auto& s : p.series)
				for (double v : s.v)
					if (std::isfinite(v)) p.lo = std::min(p.lo, v), p.hi = std::max(p.hi, v);
	for (auto& p : panels)
		if (p.title.rfind("head", 0) == 0) p.hi = std::max(std::abs(p.lo), std::abs(p.hi)), p.lo = -p.hi;
	return panels;
}

}  // namespace

Image8 plotNonVerbal(const NonVerbalTrack& t, int width) {
	const std::vector<Panel> panels = nonVerbalPanels(t);
	const int panelH = 150, left = 70, right = 20, top = 30;
	const int height = top + int(panels.size()) * panelH + 30;
	cv::Mat m(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
	const double t0 = toSeconds(t.start), t1 = t.frames.empty() ? t0 + 1 : toSeconds(t.frames.back().time);
	const double span = std::max(1e-3, t1 - t0);
	auto X = [&](double s) { return left + int(std::lround((s - t0) / span * (width - left - right))); };
	cv::putText(m, t.source + ": non-verbal tracks (talkhead track)", {left, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, {0, 0, 0}, 1, cv::LINE_AA);
	for (std::size_t pi = 0; pi < panels.size(); ++pi) {
		const Panel& p = panels[pi];
		const int y0 = top + int(pi) * panelH + 18, y1 = top + int(pi + 1) * panelH - 8;
		for (const auto& [a, b] : t.bridged) cv::rectangle(m, {X(toSeconds(a)), y0}, {X(toSeconds(b)), y1}, {225, 225, 225}, cv::FILLED);
		cv::rectangle(m, {left, y0}, {width - right, y1}, {160, 160, 160}, 1);
		auto Y = [&](double v) { return y1 - int(std::lround((std::clamp(v, p.lo, p.hi) - p.lo) / std::max(1e-9, p.hi - p.lo) * (y1 - y0))); };
		if (p.lo < 0 && p.hi > 0) cv::line(m, {left, Y(0)}, {width - right, Y(0)}, {200, 200, 200}, 1);
		if (p.blinks)
			for (Ticks b : t.blinks) {
				const int x = X(toSeconds(b) + kBlinkShutOffset);
				cv::line(m, {x, y0}, {x, y1}, {60, 60, 230}, 1);
			}
		char lim[64];
		std::snprintf(lim, sizeof lim, "%.3g", p.hi);
		cv::putText(m, lim, {4, y0 + 10}, cv::FONT_HERSHEY_SIMPLEX, 0.38, {0, 0, 0}, 1, cv::LINE_AA);
		std::snprintf(lim, sizeof lim, "%.3g", p.lo);
		cv::putText(m, lim, {4, y1}, cv::FONT_HERSHEY_SIMPLEX, 0.38, {0, 0, 0}, 1, cv::LINE_AA);
		int lx = left + 4;
		cv::putText(m, p.title, {lx, y0 - 4}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1, cv::LINE_AA);
		lx += int(p.title.size()) * 8 + 20;
		for (const auto& s : p.series) {
			std::vector<cv::Point> line;
			for (std::size_t k = 0; k < s.v.size() && k < t.frames.size(); ++k)
				if (std::isfinite(s.v[k])) line.emplace_back(X(toSeconds(t.frames[k].time)), Y(s.v[k]));
			if (line.size() > 1) cv::polylines(m, line, false, s.colour, 1, cv::LINE_AA);
			cv::putText(m, s.label, {lx, y0 - 4}, cv::FONT_HERSHEY_SIMPLEX, 0.42, s.colour, 1, cv::LINE_AA);
			lx += int(s.label.size()) * 8 + 14;
		}
	}
	// Time axis: a tick per second (every 5 s past a minute).
	const int step = span > 60 ? 5 : 1;
	for (int s = int(std::ceil(t0)); s <= int(t1); s += step) {
		const int x = X(s);
		cv::line(m, {x, height - 28}, {x, height - 22}, {0, 0, 0}, 1);
		if (s % (span > 60 ? 10 : (span > 20 ? 5 : 1)) == 0)
			cv::putText(m, std::to_string(s) + " s", {x - 8, height - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.38, {0, 0, 0}, 1, cv::LINE_AA);
	}
	Image8 out(width, height, 3);
	for (int y = 0; y < height; ++y)
		for (int x = 0; x < width; ++x) {
			const cv::Vec3b& p = m.at<cv::Vec3b>(y, x);
			out.at(x, y, 0) = p[2];
			out.at(x, y, 1) = p[1];
			out.at(x, y, 2) = p[0];
		}
	return out;
}

ControlTrack controlsOf(const NonVerbalTrack& nv) {
	ControlTrack c;
	c.path = nv.source;
	c.curves = nv.curves();
	if (nv.options.eyes) {
		c.blinks = nv.blinks;
		c.drawnBlinks = false;
	}
	return c;
}

}  // namespace talkhead
