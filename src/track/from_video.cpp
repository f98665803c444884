// SPDX-License-Identifier: GPL-3.0-or-later
#include "track/from_video.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "base/atomic_file.h"
#include "base/data_dirs.h"
#include "base/error.h"
#include "base/tsv.h"
#include "corpus/corpus.h"
#include "media/image_io.h"
#include "media/video_reader.h"
#include "phonetics/labels.h"

namespace talkhead {

namespace fs = std::filesystem;

namespace {

constexpr int kMeasures = 4;

// Eye-line frame: rotation by −roll, scaled by the eye distance.
struct TakeEyeFrame {
	double c = 1, s = 0, iod = 1;
	explicit TakeEyeFrame(const Points& p) {
		const double ex = p(45, 0) - p(36, 0), ey = p(45, 1) - p(36, 1);
		iod = std::max(1e-9, std::hypot(ex, ey));
		c = ex / iod, s = ey / iod;
	}
	// Coordinates of point i relative to the eye line (x along it, y down), in eye distances.
	double x(const Points& p, int i) const { return (c * p(i, 0) + s * p(i, 1)) / iod; }
	double y(const Points& p, int i) const { return (-s * p(i, 0) + c * p(i, 1)) / iod; }
};

}  // namespace

double percentile(std::vector<double> v, double q) {
	if (v.empty()) return 0;
	std::sort(v.begin(), v.end());
	const double pos = q * double(v.size() - 1);
	const std::size_t i = std::size_t(std::floor(pos));
	const double w = pos - double(i);
	return i + 1 < v.size() ? (1 - w) * v[i] + w * v[i + 1] : v[i];
}

namespace {

// Frames that may be chosen: a confident, frontal face with its eyes open as usual.
std::vector<std::size_t> candidates(const LandmarkTrack& track, const FromVideoOptions& o) {
	std::vector<std::size_t> c;
	std::vector<double> eyes(track.frames.size(), 0), found;
	const double maxRoll = o.maxRollDegrees * M_PI / 180;
	for (std::size_t i = 0; i < track.frames.size(); ++i) {
		const auto& f = track.frames[i];
		if (!f.found || f.confidence < o.minConfidence) continue;
		eyes[i] = eyeAspect(f.points);
		if (std::isfinite(eyes[i])) found.push_back(eyes[i]);
	}
	const double minEyes = o.minEyeOpening * percentile(found, 0.5);
	for (std::size_t i = 0; i < track.frames.size(); ++i) {
		const auto& f = track.frames[i];
		if (!f.found || f.confidence < o.minConfidence) continue;
		if (std::abs(headRoll(f.points)) > maxRoll || std::abs(headYaw(f.points)) > o.maxYaw) continue;
		if (!(eyes[i] >= minEyes)) continue;
		c.push_back(i);
	}
	return c;
}

// Mouth-point speed around frame i (eye distances per second, normalised mouths): 0 at the ends.
double mouthSpeed(const LandmarkTrack& track, std::size_t i) {
	if (i == 0 || i + 1 >= track.frames.size()) return 0;
	const auto &a = track.frames[i - 1], &b = track.frames[i + 1];
	if (!a.found || !b.found) return 1e9;
	const double dt = std::max(1e-6, toSeconds(b.time - a.time));
	return (normalisedMouth(b.points) - normalisedMouth(a.points)).rowwise().norm().mean() / dt;
}

// Mouth measures, corner lift and mouth speed of every found frame, computed once per track.
struct TrackMeasures {
	std::vector<MouthMeasures> m;
	std::vector<double> lift, speed;
	explicit TrackMeasures(const LandmarkTrack& track) : m(track.frames.size()), lift(track.frames.size(), 0), speed(track.frames.size(), 0) {
		for (std::size_t i = 0; i < track.frames.size(); ++i)
			if (track.frames[i].found)
				m[i] = mouthMeasures(track.frames[i].points), lift[i] = cornerLift(track.frames[i].points), speed[i] = mouthSpeed(track, i);
	}
	// D73: the person's usual corner lift by opening, over these frames.
	UsualLift usualLift(const std::vector<std::size_t>& frames) const {
		std::vector<double> o, l;
		for (std::size_t i : frames) o.push_back(m[i].opening), l.push_back(lift[i]);
		return UsualLift(std::move(o), std::move(l));
	}
	// How far frame i's corners are from where this person's usually are at its opening, in spreads: a
	// smile (or a grimace) the moment brought, not the person's neutral.
	double liftCost(const UsualLift& u, std::size_t i) const { return std::pow((lift[i] - u.at(m[i].opening)) / u.spread(), 2); }
};

bool nearDuplicate(const Points& a, const Points& b, double fraction) {
	const Points ma = normalisedMouth(a), mb = normalisedMouth(b);
	const double corner = std::hypot(ma(6, 0) - ma(0, 0), ma(6, 1) - ma(0, 1));
	const double rms = std::sqrt((ma - mb).rowwise().squaredNorm().mean());
	return rms < fraction * corner;
}

std::map<std::string, int> cdvOrder() {
	std::map<std::string, int> order;
	int k = 0;
	for (const auto& v : visemeLabels()) order[v.label] = k++;
	return order;
}

void sortPlan(VideoCorpusPlan& plan) {
	const auto order = cdvOrder();
	auto rank = [&](const std::string& cdv) {
		auto it = order.find(cdv);
		return it == order.end() ? 1000 : it->second;
	};
	std::stable_sort(plan.entries.begin(), plan.entries.end(), [&](const ChosenFrame& a, const ChosenFrame& b) {
		if (rank(a.cdv) != rank(b.cdv)) return rank(a.cdv) < rank(b.cdv);
		return a.cost < b.cost;
	});
}

ChosenFrame chosen(const LandmarkTrack& track, std::size_t i, const std::string& emotion, const std::string& cdv, double cost) {
	ChosenFrame c;
	c.frame = track.frames[i].frame;
	c.time = track.frames[i].time;
	c.emotion = emotion;
	c.cdv = cdv;
	c.word = "-";
	c.points = track.frames[i].points;
	c.cost = cost;
	return c;
}

std::string frameName(std::int64_t frame) {
	char b[48];
	std::snprintf(b, sizeof b, "frames/frame_%06lld.png", (long long)frame);
	return b;
}

}  // namespace

double headRoll(const Points& p) { return std::atan2(p(45, 1) - p(36, 1), p(45, 0) - p(36, 0)); }

double headYaw(const Points& p) {
	const TakeEyeFrame e(p);
	return e.x(p, 30) - 0.5 * (e.x(p, 36) + e.x(p, 45));
}

double eyeAspect(const Points& p) {
	auto one = [&](int o) {
		auto d = [&](int a, int b) { return (p.row(o + a) - p.row(o + b)).norm(); };
		const double width = d(0, 3);
		return width > 0 ? (d(1, 5) + d(2, 4)) / (2 * width) : std::numeric_limits<double>::quiet_NaN();
	};
	return 0.5 * (one(36) + one(42));
}

double cornerLift(const Points& p) {
	const TakeEyeFrame e(p);
	const double centre = (e.y(p, 61) + e.y(p, 62) + e.y(p, 63) + e.y(p, 65) + e.y(p, 66) + e.y(p, 67)) / 6;
	return centre - 0.5 * (e.y(p, 48) + e.y(p, 54));
}

UsualLift::UsualLift(std::vector<double> openings, std::vector<double> lifts) {
	if (openings.size() != lifts.size()) throw std::logic_error("UsualLift: one lift per opening");
	for (std::size_t i = 0; i < openings.size(); ++i) byOpening_.emplace_back(openings[i], lifts[i]);
	std::sort(byOpening_.begin(), byOpening_.end());
	// The scale: half the 5th–95th percentile range of the lifts off the usual (a person whose corners rise
	// as the jaw opens, franck, has a wide range of lifts but a narrow one of lifts for an opening).
	std::vector<double> off;
	for (const auto& [o, l] : byOpening_) off.push_back(l - at(o));
	spread_ = std::max(1e-4, 0.5 * (percentile(off, 0.95) - percentile(off, 0.05)));
}

double UsualLift::at(double opening) const {
	if (byOpening_.empty()) return 0;
	const std::size_t n = byOpening_.size(), k = std::min(n, std::max<std::size_t>(25, n / 20));
	// The k nearest openings form a window around the first opening not below this one.
	std::size_t lo = std::size_t(std::lower_bound(byOpening_.begin(), byOpening_.end(), std::make_pair(opening, -1e300)) - byOpening_.begin());
	std::size_t hi = lo;
	while (hi - lo < k) {
		if (lo == 0) ++hi;
		else if (hi == n) --lo;
		else if (opening - byOpening_[lo - 1].first <= byOpening_[hi].first - opening) --lo;
		else ++hi;
	}
	// Equal openings come in or stay out together (many shut mouths measure 0: a window cut among them
	// would take the ones with the lowest lifts).
	while (lo > 0 && byOpening_[lo - 1].first == byOpening_[lo].first) --lo;
	while (hi < n && byOpening_[hi].first == byOpening_[hi - 1].first) ++hi;
	std::vector<double> v;
	for (std::size_t i = lo; i < hi; ++i) v.push_back(byOpening_[i].second);
	return percentile(v, 0.5);
}

Points normalisedMouth(const Points& p) {
	const TakeEyeFrame e(p);
	Points m(20, 2);
	for (int i = 0; i < 20; ++i) m(i, 0) = e.x(p, 48 + i), m(i, 1) = e.y(p, 48 + i);
	const double cx = m.col(0).mean(), cy = m.col(1).mean();
	m.col(0).array() -= cx;
	m.col(1).array() -= cy;
	return m;
}

MouthMeasures mouthMeasures(const Points& p) {
	if (p.rows() != kIbugPoints) throw std::logic_error("mouthMeasures: 68 points expected");
	const TakeEyeFrame e(p);
	MouthMeasures m;
	m.opening = (std::max(0.0, e.y(p, 67) - e.y(p, 61)) + std::max(0.0, e.y(p, 66) - e.y(p, 62)) + std::max(0.0, e.y(p, 65) - e.y(p, 63))) / 3;
	m.width = std::hypot(e.x(p, 54) - e.x(p, 48), e.y(p, 54) - e.y(p, 48));
	m.height = e.y(p, 57) - e.y(p, 51);
	m.jaw = e.y(p, 8) - e.y(p, 33);
	return m;
}

std::vector<CdvMouthTarget> loadCdvMouthTargets(const std::string& pathIn) {
	std::string path = pathIn;
	if (path.empty()) {
		auto f = findDataFile("phonetics/cdv-mouth-targets.tsv");
		if (!f) throw Error("phonetics/cdv-mouth-targets.tsv: not found in the data folders (set TALKHEAD_DATA_DIR)");
		path = *f;
	}
	const TsvTable t = readTsv(path);
	const std::size_t cc = t.column("cdv");
	const std::size_t cols[kMeasures] = {t.column("opening"), t.column("width"), t.column("height"), t.column("jaw")};
	std::vector<CdvMouthTarget> out;
	for (const auto& row : t.rows) {
		CdvMouthTarget c;
		auto canon = canonicalViseme(row.fields[cc]);
		if (!canon) throw Error(path, row.line, "unknown CDV '" + row.fields[cc] + "'");
		c.cdv = *canon;
		for (int k = 0; k < kMeasures; ++k) c.delta[k] = t.number(row, cols[k], -1, 1);
		out.push_back(c);
	}
	if (out.empty()) throw Error(path, 0, "no CDV targets");
	return out;
}

namespace {

std::int64_t mostNeutralFrame(const LandmarkTrack& track, const TrackMeasures& tm, const FromVideoOptions& o) {
	const auto cand = candidates(track, o);
	if (cand.empty()) throw Error(track.source, 0, "no frame with a confidently tracked, frontal face");
	std::vector<double> v[kMeasures];
	for (std::size_t i : cand)
		for (int k = 0; k < kMeasures; ++k) v[k].push_back(tm.m[i][k]);
	double spread[kMeasures], ref[kMeasures];
	for (int k = 0; k < kMeasures; ++k) spread[k] = std::max(1e-4, percentile(v[k], 0.95) - percentile(v[k], 0.05));
	ref[0] = percentile(v[0], 0.05);  // lips closed
	ref[1] = percentile(v[1], 0.5);   // relaxed width
	ref[2] = percentile(v[2], 0.5);
	ref[3] = percentile(v[3], 0.2);   // jaw up
	// Issue 47: the corners where this person's usually are with the lips shut (D73's usual lift), a smile
	// above it costing four times a droop below it: a closed-mouth smile held between sentences is not the
	// person's rest, and the baseface is every frame's rest (franck's first baseface read happy 1.0).
	// The eyes as usual too: lids narrowed below the person's median (a smile's squint) cost (narrowing /
	// 10 %)², as much as a mouth measure a spread off at 10 % narrower.
	const UsualLift usual = tm.usualLift(cand);
	const double shutLift = usual.at(ref[0]);
	std::vector<double> eyes(track.frames.size(), NAN), eyeValues;
	for (std::size_t i : cand)
		if (const double e = eyeAspect(track.frames[i].points); std::isfinite(e)) eyes[i] = e, eyeValues.push_back(e);
	const double usualEyes = std::max(1e-6, percentile(eyeValues, 0.5));
	double best = 1e300;
	std::int64_t bestFrame = -1;
	for (std::size_t i : cand) {
		const auto& f = track.frames[i];
		double cost = 0;
		for (int k = 0; k < kMeasures; ++k) cost += std::pow((tm.m[i][k] - ref[k]) / spread[k], 2);
		const double smile = (tm.lift[i] - shutLift) / usual.spread();  // against the usual of shut lips
		cost += (smile > 0 ? 2.0 : 0.5) * smile * smile;
		if (std::isfinite(eyes[i])) cost += std::pow(std::max(0.0, 1 - eyes[i] / usualEyes) / 0.1, 2);
		cost += std::pow(headRoll(f.points) / (5 * M_PI / 180), 2) + std::pow(headYaw(f.points) / 0.04, 2);
		cost += std::pow(tm.speed[i] / 0.5, 2) + 4 * (1 - f.confidence);
		if (cost < best) best = cost, bestFrame = std::int64_t(i);
	}
	return track.frames[std::size_t(bestFrame)].frame;
}

}  // namespace

std::int64_t mostNeutralFrame(const LandmarkTrack& track, const FromVideoOptions& o) { return mostNeutralFrame(track, TrackMeasures(track), o); }

std::optional<ChosenFrame> closedEyesFrame(const LandmarkTrack& track, std::int64_t basefaceFrame, const FromVideoOptions& o) {
	if (!(o.maxShutEyes > 0)) return std::nullopt;
	const double maxRoll = o.maxRollDegrees * M_PI / 180;
	std::vector<double> eyes(track.frames.size(), NAN), open, opening;
	const FrameLandmarks* base = nullptr;
	for (std::size_t i = 0; i < track.frames.size(); ++i) {
		const auto& f = track.frames[i];
		if (f.frame == basefaceFrame && f.found) base = &f;
		if (!f.found || f.confidence < o.minConfidence) continue;
		eyes[i] = eyeAspect(f.points);
		if (std::isfinite(eyes[i])) open.push_back(eyes[i]), opening.push_back(mouthMeasures(f.points).opening);
	}
	if (open.size() < 10 || !base) return std::nullopt;
	const double median = percentile(open, 0.5), shut = o.maxShutEyes * median;
	// The mouth at rest: no more open than most of this person's frames (the lips of a blink in a pause).
	const double restOpening = percentile(opening, 0.05), openingSpread = std::max(1e-4, percentile(opening, 0.95) - restOpening);
	const double baseRoll = headRoll(base->points), baseYaw = headYaw(base->points);
	double best = 1e300;
	std::optional<std::size_t> pick;
	for (std::size_t i = 0; i < track.frames.size(); ++i) {
		const auto& f = track.frames[i];
		if (!(eyes[i] <= shut)) continue;  // NaN and open eyes out
		const double roll = headRoll(f.points), yaw = headYaw(f.points);
		if (std::abs(roll) > maxRoll || std::abs(yaw) > o.maxYaw) continue;
		const double open = (mouthMeasures(f.points).opening - restOpening) / openingSpread;
		if (open > 0.25) continue;  // speaking: the lids' composite would carry another mouth's shading
		// The most shut, posed as the baseface (the lids are composited in the mean frame), mouth at rest.
		double cost = 4 * eyes[i] / median + open * open;
		cost += std::pow((roll - baseRoll) / (5 * M_PI / 180), 2) + std::pow((yaw - baseYaw) / 0.04, 2) + 4 * (1 - f.confidence);
		if (cost < best) best = cost, pick = i;
	}
	if (!pick) return std::nullopt;
	return chosen(track, *pick, "-", "closed-eyes", best);
}

namespace {
// The plan's shut eyes, unless that frame is one of its visemes too (--min-eye-opening 0): one row per image.
void setClosedEyes(VideoCorpusPlan& plan, const LandmarkTrack& track, const FromVideoOptions& o) {
	plan.closedEyes = closedEyesFrame(track, plan.basefaceFrame, o);
	if (plan.closedEyes && std::any_of(plan.entries.begin(), plan.entries.end(), [&](const ChosenFrame& c) { return c.frame == plan.closedEyes->frame; }))
		plan.closedEyes.reset();
}
}  // namespace

VideoCorpusPlan selectByShape(const LandmarkTrack& track, const std::vector<CdvMouthTarget>& targets, const FromVideoOptions& o) {
	VideoCorpusPlan plan;
	plan.method = "shape";
	const auto cand = candidates(track, o);
	if (cand.size() < 10)
		throw Error(track.source, 0, "only " + std::to_string(cand.size()) + " frames with a confidently tracked, frontal face: too few to choose visemes from");
	const TrackMeasures tm(track);
	const std::vector<MouthMeasures>& m = tm.m;
	std::vector<double> v[kMeasures];
	for (std::size_t i : cand)
		for (int k = 0; k < kMeasures; ++k) v[k].push_back(m[i][k]);
	// The baseface (rest shape).
	plan.basefaceFrame = o.baseface >= 0 ? o.baseface : mostNeutralFrame(track, tm, o);
	std::size_t baseIndex = track.frames.size();
	for (std::size_t i = 0; i < track.frames.size(); ++i)
		if (track.frames[i].frame == plan.basefaceFrame) baseIndex = i;
	if (baseIndex == track.frames.size() || !track.frames[baseIndex].found)
		throw Error(track.source, 0, "{{baseface}} " + std::to_string(plan.basefaceFrame) + ": no tracked face in that frame");
	plan.rest = mouthMeasures(track.frames[baseIndex].points);
	const double baseYaw = headYaw(track.frames[baseIndex].points);
	// D55: a yaw 0.03 eye distances (about 4°) from the baseface's costs 0.2, a fifth of a mouth measure one
	// spread off: franck's chosen frames' yaw sd 0.041 → 0.007.
	constexpr double kPoseWeight = 0.2;
	// Scale each measure's target offsets to this speaker's range.
	double spread[kMeasures];
	for (int k = 0; k < kMeasures; ++k) {
		double lo = 0, hi = 0;
		for (const auto& t : targets) lo = std::min(lo, t.delta[k]), hi = std::max(hi, t.delta[k]);
		spread[k] = std::max(1e-4, percentile(v[k], 0.98) - percentile(v[k], 0.02));
		plan.scale[k] = hi - lo > 1e-6 ? spread[k] / (hi - lo) : 1;
	}
	const double weight[kMeasures] = {1.0, 1.0, 0.5, 0.5};
	const UsualLift usual = tm.usualLift(cand);
	std::vector<double> liftCost(track.frames.size(), 0);
	for (std::size_t i : cand) liftCost[i] = tm.liftCost(usual, i);
	for (const auto& t : targets) {
		MouthMeasures goal;
		for (int k = 0; k < kMeasures; ++k) goal[k] = plan.rest[k] + plan.scale[k] * t.delta[k];
		std::vector<std::pair<double, std::size_t>> ranked;
		for (std::size_t i : cand) {
			double cost = 0;
			for (int k = 0; k < kMeasures; ++k) cost += weight[k] * std::pow((m[i][k] - goal[k]) / spread[k], 2);
			// D73: the corners where this person's usually are at that opening — but not for a shut target
			// (/p b m/, the rest): there the lips' closure comes first.
			if (t.delta[0] > 0) cost += liftCost[i];
			// Prefer still, confident frames (a frame mid-transition is blurred), posed like the baseface (a
			// 2D model cannot undo a turned head: exemplars turned differently make the head wobble).
			cost += 0.05 * std::pow(tm.speed[i] / 0.5, 2) + 0.2 * (1 - track.frames[i].confidence);
			cost += kPoseWeight * std::pow((headYaw(track.frames[i].points) - baseYaw) / 0.03, 2);
			ranked.emplace_back(cost, i);
		}
		std::sort(ranked.begin(), ranked.end());
		std::vector<std::pair<double, std::size_t>> kept;
		if (t.cdv == "sil") kept.emplace_back(0.0, baseIndex);
		for (const auto& [cost, i] : ranked) {
			if (int(kept.size()) >= o.perCdv) break;
			bool dup = false;
			for (const auto& k : kept) dup = dup || nearDuplicate(track.frames[i].points, track.frames[k.second].points, o.duplicateFraction);
			if (!dup) kept.emplace_back(cost, i);
		}
		for (const auto& [cost, i] : kept) plan.entries.push_back(chosen(track, i, o.emotion, t.cdv, cost));
	}
	if (std::none_of(plan.entries.begin(), plan.entries.end(), [&](const ChosenFrame& c) { return c.frame == plan.basefaceFrame; }))
		plan.entries.push_back(chosen(track, baseIndex, o.emotion, "sil", 0));
	setClosedEyes(plan, track, o);
	sortPlan(plan);
	return plan;
}

namespace {

// The frame that shows a phone: its inflection point, the interior extremum of the opening (else of the
// width) that departs most from the interval's mean; the midpoint frame when the signal is monotonic; −1
// when no usable frame falls in the phone.
long inflectionFrame(const LandmarkTrack& track, const TrackMeasures& tm, const std::vector<char>& ok, const PhoneSegment& ph) {
	std::vector<std::size_t> in;  // frames are in time order
	auto first = std::lower_bound(track.frames.begin(), track.frames.end(), ph.start, [](const FrameLandmarks& f, Ticks t) { return f.time < t; });
	for (std::size_t i = std::size_t(first - track.frames.begin()); i < track.frames.size() && track.frames[i].time < ph.end; ++i)
		if (ok[i]) in.push_back(i);
	if (in.empty()) return -1;
	auto extremum = [&](int measure) -> long {
		if (in.size() < 3) return -1;
		double mean = 0;
		for (std::size_t i : in) mean += tm.m[i][measure];
		mean /= double(in.size());
		long best = -1;
		double bestDev = -1;
		for (std::size_t k = 1; k + 1 < in.size(); ++k) {
			const double a = tm.m[in[k - 1]][measure], b = tm.m[in[k]][measure], c = tm.m[in[k + 1]][measure];
			if ((b - a) * (c - b) <= 0 && std::abs(b - a) + std::abs(c - b) > 1e-4 && std::abs(b - mean) > bestDev)
				bestDev = std::abs(b - mean), best = long(in[k]);
		}
		return best;
	};
	long pick = extremum(0);
	if (pick < 0) pick = extremum(1);
	if (pick < 0) {
		const Ticks mid = ph.start + (ph.end - ph.start) / 2;
		pick = long(in.front());
		for (std::size_t i : in)
			if (std::abs((track.frames[i].time - mid).count()) < std::abs((track.frames[std::size_t(pick)].time - mid).count())) pick = long(i);
	}
	return pick;
}

// A frame chosen for a phone: with the phone, its context of five and the word it falls in.
ChosenFrame phoneChosen(const LandmarkTrack& track, std::size_t frame, const std::vector<PhoneSegment>& phones, std::size_t phone,
                        const std::vector<Interval>& words, const std::string& emotion, const std::string& cdv, double d) {
	ChosenFrame c = chosen(track, frame, emotion, cdv, d);
	c.phone = phones[phone].phone;
	for (int k = -2; k <= 2; ++k) {
		const long q = long(phone) + k;
		c.context[std::size_t(k + 2)] = q < 0 || q >= long(phones.size()) || phones[std::size_t(q)].phone.empty() ? "_" : phones[std::size_t(q)].phone;
	}
	const Ticks mid = phones[phone].start + (phones[phone].end - phones[phone].start) / 2;
	for (const auto& w : words)
		if (mid >= w.start && mid < w.end && !w.label.empty()) c.word = w.label;
	return c;
}

}  // namespace

VideoCorpusPlan selectByPhones(const LandmarkTrack& track, const std::vector<PhoneSegment>& phones, const std::vector<Interval>& words,
                               const FromVideoOptions& o) {
	VideoCorpusPlan plan;
	plan.method = "phones";
	if (phones.empty()) throw Error(track.source, 0, "the transcript has no phones");
	const auto cand = candidates(track, o);
	const TrackMeasures tm(track);
	std::vector<char> ok(track.frames.size(), 0);
	for (std::size_t i : cand) ok[i] = 1;
	struct Pick {
		std::size_t frame;
		std::size_t phone;
	};
	std::map<std::string, std::vector<Pick>> byCdv;
	for (std::size_t p = 0; p < phones.size(); ++p) {
		const auto& ph = phones[p];
		const long pick = inflectionFrame(track, tm, ok, ph);
		if (pick < 0) continue;
		byCdv[ph.cdv.label()].push_back({std::size_t(pick), p});
	}
	if (byCdv.empty()) throw Error(track.source, 0, "no phone of the transcript falls on a frame with a tracked face");
	const UsualLift usual = tm.usualLift(cand);
	for (auto& [cdv, picks] : byCdv) {
		// Most typical first: nearest the CDV's median measures.
		MouthMeasures med;
		for (int k = 0; k < kMeasures; ++k) {
			std::vector<double> v;
			for (const auto& pk : picks) v.push_back(tm.m[pk.frame][k]);
			med[k] = percentile(v, 0.5);
		}
		std::vector<std::pair<double, Pick>> ranked;
		for (const auto& pk : picks) {
			const MouthMeasures& m = tm.m[pk.frame];
			double d = 0;
			for (int k = 0; k < kMeasures; ++k) d += std::pow(m[k] - med[k], 2);
			d += std::pow(tm.lift[pk.frame] - usual.at(m.opening), 2);  // D73: not a smile the moment brought
			ranked.push_back({std::sqrt(d), pk});
		}
		std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
		std::vector<std::size_t> kept;
		for (const auto& [d, pk] : ranked) {
			if (int(kept.size()) >= o.perCdv) break;
			bool dup = false;
			for (std::size_t j : kept) dup = dup || j == pk.frame || nearDuplicate(track.frames[pk.frame].points, track.frames[j].points, o.duplicateFraction);
			if (dup) continue;
			kept.push_back(pk.frame);
			plan.entries.push_back(phoneChosen(track, pk.frame, phones, pk.phone, words, o.emotion, cdv, d));
		}
	}
	for (const auto& v : visemeLabels())
		if (!byCdv.count(v.label)) plan.missing.push_back(v.label);
	plan.basefaceFrame = o.baseface >= 0 ? o.baseface : mostNeutralFrame(track, tm, o);
	if (std::none_of(plan.entries.begin(), plan.entries.end(), [&](const ChosenFrame& c) { return c.frame == plan.basefaceFrame; })) {
		for (std::size_t i = 0; i < track.frames.size(); ++i)
			if (track.frames[i].frame == plan.basefaceFrame && track.frames[i].found) plan.entries.push_back(chosen(track, i, o.emotion, "sil", 0));
		if (std::none_of(plan.entries.begin(), plan.entries.end(), [&](const ChosenFrame& c) { return c.frame == plan.basefaceFrame; }))
			throw Error(track.source, 0, "{{baseface}} " + std::to_string(plan.basefaceFrame) + ": no tracked face in that frame");
	}
	setClosedEyes(plan, track, o);
	sortPlan(plan);
	return plan;
}

void writeVideoCorpus(const std::string& video, const LandmarkTrack& track, const VideoCorpusPlan& plan, const std::string& dir) {
	TakePlan t;
	t.take.video = video;
	t.track = track;
	t.plan = plan;
	writeTakesCorpus({t}, 0, dir);
}

VideoTake parseTakeSpec(const std::string& spec) {
	VideoTake t;
	t.where = "{{take}} " + spec;
	const auto colon = spec.rfind(':');
	if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size())
		throw Error("{{take}} takes VIDEO:EMOTION (e.g. anger.mp4:anger), not '" + spec + "'");
	t.video = spec.substr(0, colon);
	const std::string e = spec.substr(colon + 1);
	const auto c = canonicalEmotion(e);
	if (!c) throw Error(t.video, 0, "{{take}}: unknown emotion '" + e + "'");
	t.emotion = *c;
	std::error_code ec;  // not the throwing overload: a name too long for the system is no such file too
	if (!fs::is_regular_file(t.video, ec)) throw Error(t.video, 0, "{{take}}: no such file" + (ec ? " (" + ec.message() + ")" : std::string()));
	return t;
}

std::vector<VideoTake> readTakeList(const std::string& path) {
	const TsvTable tab = readTsv(path);
	const fs::path folder = fs::path(path).parent_path();
	auto optional = [&](const char* name) -> long {
		const auto it = std::find(tab.header.begin(), tab.header.end(), name);
		return it == tab.header.end() ? -1 : long(it - tab.header.begin());
	};
	const std::size_t cv = tab.column("video"), ce = tab.column("emotion");
	const long cs = optional("start"), cd = optional("duration"), ct = optional("transcript"), cx = optional("text"), ca = optional("audio");
	std::vector<VideoTake> out;
	for (const auto& r : tab.rows) {
		VideoTake t;
		t.where = path + ":" + std::to_string(r.line);
		auto file = [&](long column, const char* what) -> std::string {
			if (column < 0 || r.fields[std::size_t(column)].empty() || r.fields[std::size_t(column)] == "-") return "";
			const fs::path f = fs::path(r.fields[std::size_t(column)]);
			const std::string p = (f.is_absolute() ? f : folder / f).string();
			std::error_code ec;  // not the throwing overload (a name too long for the system: fuzz finding)
			if (!fs::is_regular_file(p, ec)) throw Error(path, r.line, std::string("no such ") + what + " file: " + p + (ec ? " (" + ec.message() + ")" : ""));
			return p;
		};
		t.video = file(long(cv), "video");
		if (t.video.empty()) throw Error(path, r.line, "the take names no video");
		const auto c = canonicalEmotion(r.fields[ce]);
		if (!c) throw Error(path, r.line, "unknown emotion '" + r.fields[ce] + "'");
		t.emotion = *c;
		if (cs >= 0 && !r.fields[std::size_t(cs)].empty() && r.fields[std::size_t(cs)] != "-") t.start = ticksFromSeconds(tab.number(r, std::size_t(cs), 0, 1e6));
		if (cd >= 0 && !r.fields[std::size_t(cd)].empty() && r.fields[std::size_t(cd)] != "-") t.duration = ticksFromSeconds(tab.number(r, std::size_t(cd), 0.1, 1e6));
		t.transcript = file(ct, "transcript");
		t.audio = file(ca, "audio");
		if (cx >= 0 && r.fields[std::size_t(cx)] != "-") t.text = r.fields[std::size_t(cx)];
		if (!t.transcript.empty() && !t.text.empty()) throw Error(path, r.line, "give a take's transcript or its text, not both");
		out.push_back(std::move(t));
	}
	if (out.empty()) throw Error(path, 0, "the take list has no takes");
	return out;
}

bool ColourMatch::identity() const {
	for (int c = 0; c < 3; ++c)
		if (gain[c] != 1 || offset[c] != 0) return false;
	return true;
}

namespace {

// Mean and standard deviation per channel of the face pixels: inside the landmarks' convex hull, without
// the mouth and the eyes (D73: a frame's gain must not follow what it says — an open mouth's teeth and dark
// inside — or a blink).
struct ColourStats {
	double sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
	double n = 0;
	void add(const Image8& img, const Points& points) {
		std::vector<cv::Point> pts, hull;
		for (Eigen::Index i = 0; i < points.rows(); ++i) pts.emplace_back(int(std::lround(points(i, 0))), int(std::lround(points(i, 1))));
		cv::convexHull(pts, hull);
		cv::Mat mask = cv::Mat::zeros(img.height, img.width, CV_8U);
		cv::fillConvexPoly(mask, hull, cv::Scalar(255));
		if (points.rows() == kIbugPoints) {
			const double iod = std::hypot(points(45, 0) - points(36, 0), points(45, 1) - points(36, 1));
			const int margin = std::max(1, int(std::lround(0.08 * iod)));
			for (const auto& [first, count] : {std::pair{48, 12}, std::pair{36, 6}, std::pair{42, 6}}) {
				const std::vector<cv::Point> part(pts.begin() + first, pts.begin() + first + count);
				cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{part}, cv::Scalar(0));
				cv::polylines(mask, std::vector<std::vector<cv::Point>>{part}, true, cv::Scalar(0), margin);
			}
		}
		for (int y = 0; y < img.height; ++y) {
			const std::uint8_t* m = mask.ptr<std::uint8_t>(y);
			const std::uint8_t* p = &img.data[std::size_t(y) * std::size_t(img.width) * 3];
			for (int x = 0; x < img.width; ++x) {
				if (!m[x]) continue;
				n += 1;
				for (int c = 0; c < 3; ++c) {
					const double v = p[3 * x + c];
					sum[c] += v, sq[c] += v * v;
				}
			}
		}
	}
	double mean(int c) const { return n > 0 ? sum[c] / n : 0; }
	double sd(int c) const { return n > 1 ? std::sqrt(std::max(0.0, sq[c] / n - mean(c) * mean(c))) : 0; }
};

ColourMatch matchTo(const ColourStats& from, const ColourStats& to) {
	ColourMatch m;
	for (int c = 0; c < 3; ++c) {
		m.gain[c] = from.sd(c) > 1 ? std::clamp(to.sd(c) / from.sd(c), 0.8, 1.25) : 1.0;
		m.offset[c] = to.mean(c) - m.gain[c] * from.mean(c);
	}
	return m;
}

void applyMatch(Image8& img, const ColourMatch& m) {
	if (m.identity()) return;
	std::uint8_t lut[3][256];
	for (int c = 0; c < 3; ++c)
		for (int v = 0; v < 256; ++v) lut[c][v] = std::uint8_t(std::clamp(std::lround(m.gain[c] * v + m.offset[c]), 0L, 255L));
	for (std::size_t i = 0; i < img.data.size(); i += 3)
		for (int c = 0; c < 3; ++c) img.data[i + std::size_t(c)] = lut[c][img.data[i + std::size_t(c)]];
}

// The chosen frames of a video, decoded once more (absolute frame indices, as the track has them).
std::map<std::int64_t, Image8> decodeFrames(const std::string& video, const VideoCorpusPlan& plan) {
	std::set<std::int64_t> wanted;
	for (const auto& e : plan.entries) wanted.insert(e.frame);
	if (plan.closedEyes) wanted.insert(plan.closedEyes->frame);
	std::map<std::int64_t, Image8> frames;
	VideoReader reader(video);
	Image8 rgb;
	Ticks t{0};
	std::int64_t index = 0;
	const std::int64_t last = wanted.empty() ? -1 : *wanted.rbegin();
	while (index < last && reader.read(rgb, t, index))
		if (wanted.count(index)) frames[index] = rgb;
	for (std::int64_t f : wanted)
		if (!frames.count(f)) throw Error(video, 0, "frame " + std::to_string(f) + " could not be decoded again");
	return frames;
}

}  // namespace

namespace {

// A chosen frame's image in the corpus folder: frames/NNNNNN.png, or per take with several.
std::string takeImageName(bool several, std::size_t k, std::int64_t frame) {
	return several ? "frames/take" + std::to_string(k + 1) + "_" + frameName(frame).substr(7) : frameName(frame);
}

// Decodes every take's chosen frames into `frames` and brings their colours together; returns each take's map.
std::vector<ColourMatch> decodeAndMatchColours(const std::vector<TakePlan>& takes, std::size_t baseTake, std::vector<std::map<std::int64_t, Image8>>& frames) {
	const bool several = takes.size() > 1;
	// Decode every take's chosen frames and bring their colours together, in two steps (D73).
	// (1) Within a take, one gain per frame and channel brings the mean of the frame's face to the take's
	// median: lighting drifts within a recording (franck's own: 4–6 levels in 50 s) and a face's exemplars
	// come from moments seconds or minutes apart, so they flickered as they followed one another, and a
	// take's match hung on which frames were chosen. A gain is what a change of exposure or of the light's
	// strength does; one over the whole face keeps the expression's own shading (a frown's darker glabella).
	// (2) Between takes (D61), one map per take (gain × value + offset, per channel: the mean and spread of
	// its faces brought to the base take's) so that lighting that drifted between recordings does not flash.
	std::vector<ColourStats> takeStats(takes.size());
	std::vector<std::map<std::int64_t, std::array<double, 3>>> frameGain(takes.size());
	for (std::size_t k = 0; k < takes.size(); ++k) {
		frames.push_back(decodeFrames(takes[k].take.video, takes[k].plan));
		std::map<std::int64_t, const Points*> points;  // each frame once
		for (const auto& e : takes[k].plan.entries) points.emplace(e.frame, &e.points);
		std::map<std::int64_t, ColourStats> stats;
		for (const auto& [f, p] : points) stats[f].add(frames[k].at(f), *p);
		double median[3];
		for (int c = 0; c < 3; ++c) {
			std::vector<double> v;
			for (const auto& [f, st] : stats)
				if (st.n > 0) v.push_back(st.mean(c));
			median[c] = percentile(v, 0.5);
		}
		// The shut eyes' frame takes the same gain to the median, the median left as the chosen frames make it.
		if (const auto& shut = takes[k].plan.closedEyes; shut && !points.count(shut->frame)) {
			points.emplace(shut->frame, &shut->points);
			stats[shut->frame].add(frames[k].at(shut->frame), shut->points);
		}
		for (const auto& [f, p] : points) {
			ColourMatch m;
			for (int c = 0; c < 3; ++c) {
				const double own = stats[f].mean(c);
				m.gain[c] = own > 1 && median[c] > 1 ? std::clamp(median[c] / own, 0.8, 1.25) : 1.0;
				frameGain[k][f][std::size_t(c)] = m.gain[c];
			}
			applyMatch(frames[k].at(f), m);
		}
		if (several)
			for (const auto& e : takes[k].plan.entries) takeStats[k].add(frames[k].at(e.frame), e.points);  // every entry, as D61 counted them
	}
	std::vector<ColourMatch> matches(takes.size());
	for (std::size_t k = 0; k < takes.size(); ++k) {
		ColourMatch take;
		if (k != baseTake) take = matchTo(takeStats[k], takeStats[baseTake]);
		std::vector<double> gains[3];
		for (auto& [index, img] : frames[k]) {
			applyMatch(img, take);
			for (int c = 0; c < 3; ++c) gains[c].push_back(take.gain[c] * frameGain[k].at(index)[std::size_t(c)]);
		}
		matches[k] = take;
		for (int c = 0; c < 3; ++c) matches[k].low[c] = percentile(gains[c], 0), matches[k].high[c] = percentile(gains[c], 1);
	}
	return matches;
}

// The take whose shut eyes the corpus keeps: the base take's (lit as the baseface), else the first that has them.
std::optional<std::size_t> closedEyesTake(const std::vector<TakePlan>& takes, std::size_t baseTake) {
	if (takes[baseTake].plan.closedEyes) return baseTake;
	for (std::size_t k = 0; k < takes.size(); ++k)
		if (takes[k].plan.closedEyes) return k;
	return std::nullopt;
}

// corpus.csv: a header naming the takes (and their colour maps), the baseface, then one row per chosen frame.
std::string takesCorpusCsv(const std::vector<TakePlan>& takes, std::size_t baseTake, const std::vector<ColourMatch>& matches) {
	const bool several = takes.size() > 1;
	auto imageName = [&](std::size_t k, std::int64_t frame) { return takeImageName(several, k, frame); };
	std::ostringstream csv;
	std::size_t count = 0;
	for (const auto& t : takes) count += t.plan.entries.size();
	if (!several) {
		const VideoCorpusPlan& plan = takes[0].plan;
		csv << "# talkhead corpus from-video: " << fs::path(takes[0].take.video).filename().string() << ", " << plan.entries.size() << " frames chosen by "
		    << (plan.method == "shape" ? "mouth shape" : "phone alignment") << ", ibug-68 points (dlib)\n";
	} else {
		csv << "# talkhead corpus from-video: " << takes.size() << " takes, " << count << " frames, ibug-68 points (dlib); colours matched to take "
		    << baseTake + 1 << "\n";
		for (std::size_t k = 0; k < takes.size(); ++k) {
			char b[160];
			std::snprintf(b, sizeof b, "gain %.3f %.3f %.3f offset %.1f %.1f %.1f; with each frame's %.3f–%.3f", matches[k].gain[0], matches[k].gain[1],
			              matches[k].gain[2], matches[k].offset[0], matches[k].offset[1], matches[k].offset[2],
			              std::min({matches[k].low[0], matches[k].low[1], matches[k].low[2]}), std::max({matches[k].high[0], matches[k].high[1], matches[k].high[2]}));
			csv << "# take " << k + 1 << ": " << fs::path(takes[k].take.video).filename().string() << ", " << takes[k].take.emotion << ", "
			    << takes[k].plan.entries.size() << " frames by " << (takes[k].plan.method == "shape" ? "mouth shape" : "phone alignment") << "; " << b << "\n";
		}
	}
	csv << "# baseface: " << imageName(baseTake, takes[baseTake].plan.basefaceFrame) << "\n";
	const auto shut = closedEyesTake(takes, baseTake);
	if (shut) csv << "# closed-eyes: " << imageName(*shut, takes[*shut].plan.closedEyes->frame) << "\n";
	auto row = [&](std::size_t k, const ChosenFrame& e) {
		CorpusEntry r;
		r.imagePath = imageName(k, e.frame), r.context = e.context, r.word = e.word;
		r.setLabels(e.emotion, e.cdv);
		r.points = e.points.topRows(kIbugPoints);
		csv << chUnicampCsvRow(r) << "\n";
	};
	for (std::size_t k = 0; k < takes.size(); ++k)
		for (const auto& e : takes[k].plan.entries) row(k, e);
	if (shut) row(*shut, *takes[*shut].plan.closedEyes);  // unlabelled: no keypose uses it, blinks do (D50)
	return csv.str();
}

// Contact sheet: the face of each chosen frame (CDV label, and the take's emotion with several), baseface first.
Image8 takesContactSheet(const std::vector<TakePlan>& takes, std::size_t baseTake, const std::vector<std::map<std::int64_t, Image8>>& frames) {
	const bool several = takes.size() > 1;
	char buf[64];
	const int cell = 160, labelH = 16, cols = 8;
	std::vector<std::pair<std::size_t, const ChosenFrame*>> order;
	for (std::size_t k = 0; k < takes.size(); ++k)
		for (const auto& e : takes[k].plan.entries)
			if (k == baseTake && e.frame == takes[k].plan.basefaceFrame) order.insert(order.begin(), {k, &e});
			else order.emplace_back(k, &e);
	if (const auto shut = closedEyesTake(takes, baseTake)) order.emplace_back(*shut, &*takes[*shut].plan.closedEyes);
	const int rows = (int(order.size()) + cols - 1) / cols;
	Image8 sheet(cols * cell, rows * (cell + labelH), 3, 30);
	cv::Mat sm(sheet.height, sheet.width, CV_8UC3, sheet.data.data());
	for (std::size_t n = 0; n < order.size(); ++n) {
		const auto [k, ep] = order[n];
		const ChosenFrame& e = *ep;
		const bool base = k == baseTake && e.frame == takes[k].plan.basefaceFrame;
		Image8 img = frames[k].at(e.frame);
		drawLandmarks(img, e.points, true);
		// A square around the lower face.
		const double iod = eyeDistance(e.points);
		const double cx = e.points.col(0).mean(), cy = 0.5 * (e.points(33, 1) + e.points(8, 1));
		const double half = 0.9 * iod;
		cv::Mat src(img.height, img.width, CV_8UC3, img.data.data()), crop;
		const cv::Matx23d m(2 * half / cell, 0, cx - half, 0, 2 * half / cell, cy - half);
		cv::warpAffine(src, crop, m, cv::Size(cell, cell), cv::INTER_AREA | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar(30, 30, 30));
		const int x = int(n % cols) * cell, y = int(n / cols) * (cell + labelH);
		crop.copyTo(sm(cv::Rect(x, y, cell, cell)));
		std::string label = e.cdv;  // OpenCV's font is ASCII: the CDV's ASCII alias
		for (const auto& v : visemeLabels())
			if (v.label == e.cdv && !v.ascii.empty()) label = v.ascii;
		if (several) label = e.emotion.substr(0, 5) + " " + label;
		std::snprintf(buf, sizeof buf, "%s%s #%lld", base ? "BASE " : "", label.c_str(), (long long)e.frame);
		cv::putText(sm, buf, cv::Point(x + 3, y + cell + 12), cv::FONT_HERSHEY_SIMPLEX, 0.38, cv::Scalar(230, 230, 230), 1, cv::LINE_AA);
	}
	return sheet;
}

}  // namespace

std::vector<ColourMatch> writeTakesCorpus(const std::vector<TakePlan>& takes, std::size_t baseTake, const std::string& dir, int pngCompression) {
	if (takes.empty() || baseTake >= takes.size()) throw std::logic_error("writeTakesCorpus: no takes or no base take");
	fs::create_directories(fs::path(dir) / "frames");
	const bool several = takes.size() > 1;
	std::vector<std::map<std::int64_t, Image8>> frames;
	const std::vector<ColourMatch> matches = decodeAndMatchColours(takes, baseTake, frames);
	int width = -1, height = -1;
	for (std::size_t k = 0; k < takes.size(); ++k)
		for (const auto& [index, img] : frames[k]) {
			if (width < 0) width = img.width, height = img.height;
			if (img.width != width || img.height != height)
				throw Error(takes[k].take.video, 0, "its frames are " + std::to_string(img.width) + "x" + std::to_string(img.height) + ", the first take's " +
				                                        std::to_string(width) + "x" + std::to_string(height) + ": the takes of one corpus must be the same size");
			writeImage((fs::path(dir) / takeImageName(several, k, index)).string(), img, pngCompression);
		}
	writeFileAtomically((fs::path(dir) / "corpus.csv").string(), takesCorpusCsv(takes, baseTake, matches));
	writeImage((fs::path(dir) / "contact.png").string(), takesContactSheet(takes, baseTake, frames));
	return matches;
}

}  // namespace talkhead
