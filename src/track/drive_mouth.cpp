// SPDX-License-Identifier: GPL-3.0-or-later
#include "track/drive_mouth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/error.h"
#include "phonetics/emotion.h"

namespace talkhead {

namespace {

constexpr int kMeasureCount = 4;
// The opening and the width decide most; the outer lip height and the jaw follow them (D32's weights).
constexpr double kWeight[kMeasureCount] = {1.0, 1.0, 0.5, 0.5};

}  // namespace

double modifiedHausdorff(const Points& a, const Points& b) {
	auto directed = [](const Points& p, const Points& q) {
		double sum = 0;
		for (Eigen::Index i = 0; i < p.rows(); ++i) {
			double best = std::numeric_limits<double>::max();
			for (Eigen::Index j = 0; j < q.rows(); ++j) best = std::min(best, (p.row(i) - q.row(j)).norm());
			sum += best;
		}
		return p.rows() > 0 ? sum / double(p.rows()) : 0.0;
	};
	return std::max(directed(a, b), directed(b, a));
}

MouthClassifier MouthClassifier::fromTargets(const std::vector<CdvMouthTarget>& targets) {
	MouthClassifier c;
	for (const auto& t : targets) {
		c.classes.push_back(t.cdv);
		c.targets.push_back(t.delta);
	}
	return c;
}

MouthClassifier MouthClassifier::forModel(const FaceModel& model, const std::string& emotion) {
	auto has = [&](const std::string& cdv) { return model.findSample(emotion, cdv) >= 0 || model.findSample(Emotion::neutralLabel(), cdv) >= 0; };
	if (model.scheme.name == "ch-unicamp-56") {  // the synthetic corpus's CDV shapes: the default face's own
		std::vector<CdvMouthTarget> kept;
		for (const auto& t : loadCdvMouthTargets())
			if (has(t.cdv)) kept.push_back(t);
		if (kept.empty()) throw Error("{{drive-mouth}}: the model has none of the CDVs of phonetics/cdv-mouth-targets.tsv");
		return fromTargets(kept);
	}
	if (model.scheme.name != "ibug-68" || model.pointCount() != kIbugPoints)
		throw Error("{{drive-mouth}}: models of scheme " + model.scheme.name + " have no mouth measures (faces of the ibug-68 and ch-unicamp-56 schemes do)");
	// A real-face corpus: the model's own samples, each CDV's mean measures against the baseface's.
	const MouthMeasures rest = mouthMeasures(model.alignedShapes.at(model.basefaceIndex));
	MouthClassifier c;
	std::vector<std::string> seen;
	for (const auto& s : model.samples) {
		if (s.cdv.empty() || std::find(seen.begin(), seen.end(), s.cdv) != seen.end()) continue;
		seen.push_back(s.cdv);
		const std::string& e = model.findSample(emotion, s.cdv) >= 0 ? emotion : Emotion::neutralLabel();
		MouthMeasures sum;
		int n = 0;
		for (std::size_t i = 0; i < model.sampleCount(); ++i)
			if (model.samples[i].cdv == s.cdv && model.samples[i].emotion == e) {
				const MouthMeasures m = mouthMeasures(model.alignedShapes[i]);
				for (int k = 0; k < kMeasureCount; ++k) sum[k] += m[k] - rest[k];
				++n;
			}
		if (n == 0) continue;
		for (int k = 0; k < kMeasureCount; ++k) sum[k] /= n;
		c.classes.push_back(s.cdv);
		c.targets.push_back(sum);
	}
	if (c.classes.size() < 2) throw Error("{{drive-mouth}}: the model has fewer than two mouth classes (CDVs)");
	return c;
}

void MouthClassifier::calibrate(const MouthMeasures& r, const std::vector<MouthMeasures>& frames) {
	rest = r;
	for (int k = 0; k < kMeasureCount; ++k) {
		std::vector<double> v;
		for (const auto& m : frames) v.push_back(m[k]);
		double lo = 0, hi = 0;
		for (const auto& t : targets) lo = std::min(lo, t[k]), hi = std::max(hi, t[k]);
		spread[k] = std::max(1e-4, percentile(v, 0.98) - percentile(v, 0.02));
		scale[k] = hi - lo > 1e-6 ? spread[k] / (hi - lo) : 1;
	}
}

void MouthClassifier::calibrate(const LandmarkTrack& driver) {
	FromVideoOptions o;
	o.minConfidence = 0.5;
	restFrame = mostNeutralFrame(driver, o);
	std::vector<MouthMeasures> all;
	MouthMeasures r;
	bool found = false;
	for (const auto& f : driver.frames) {
		if (!f.found) continue;
		all.push_back(mouthMeasures(unsmoothedPoints(f)));
		if (f.frame == restFrame) r = all.back(), found = true;
	}
	if (all.empty()) throw Error(driver.source, 0, "no face found");
	if (!found) r = all.front();
	calibrate(r, all);
}

std::size_t MouthClassifier::classify(const MouthMeasures& m) const {
	std::size_t best = 0;
	double bestCost = std::numeric_limits<double>::max();
	for (std::size_t c = 0; c < classes.size(); ++c) {
		double cost = 0;
		for (int k = 0; k < kMeasureCount; ++k) cost += kWeight[k] * std::pow((m[k] - rest[k] - scale[k] * targets[c][k]) / spread[k], 2);
		if (cost < bestCost) bestCost = cost, best = c;
	}
	return best;
}

DrivenMouth driveMouth(const LandmarkTrack& driver, const FaceModel& model, const std::string& emotion) {
	MouthClassifier classifier = MouthClassifier::forModel(model, emotion);
	classifier.calibrate(driver);
	const std::size_t n = driver.frames.size();
	double rate = 25;
	if (driver.info.fpsNum > 0 && driver.info.fpsDen > 0) rate = double(driver.info.fpsNum) / driver.info.fpsDen;
	// Measures of the found frames, smoothed by a centred Gaussian of 40 ms over the found neighbours.
	std::vector<MouthMeasures> raw(n);
	std::vector<bool> ok(n, false);
	for (std::size_t i = 0; i < n; ++i)
		if (driver.frames[i].found && driver.frames[i].confidence >= 0.5) ok[i] = true, raw[i] = mouthMeasures(unsmoothedPoints(driver.frames[i]));
	const double sigma = 0.04 * rate;
	const long radius = long(std::ceil(3 * sigma));
	std::vector<MouthMeasures> m(n);
	for (long i = 0; i < long(n); ++i) {
		if (!ok[std::size_t(i)]) continue;
		double w = 0;
		MouthMeasures s;
		for (long j = std::max(0L, i - radius); j <= std::min(long(n) - 1, i + radius); ++j) {
			if (!ok[std::size_t(j)]) continue;
			const double g = sigma > 0.3 ? std::exp(-0.5 * double((j - i) * (j - i)) / (sigma * sigma)) : (j == i ? 1.0 : 0.0);
			for (int k = 0; k < kMeasureCount; ++k) s[k] += g * raw[std::size_t(j)][k];
			w += g;
		}
		for (int k = 0; k < kMeasureCount; ++k) s[k] /= w;
		m[std::size_t(i)] = s;
	}
	DrivenMouth out;
	out.perFrame.assign(n, "");
	std::vector<long> cls(n, -1);
	for (std::size_t i = 0; i < n; ++i)
		if (ok[i]) cls[i] = long(classifier.classify(m[i])), out.perFrame[i] = classifier.classes[std::size_t(cls[i])];
	// The actor's rest mouth, for moving the driver's displacement onto it (exemplar choice, ibug-68).
	bool ibug = model.scheme.name == "ibug-68" && model.pointCount() == kIbugPoints;
	Points actorRest, driverRest;
	if (ibug) {
		actorRest = normalisedMouth(model.alignedShapes.at(model.basefaceIndex));
		for (const auto& f : driver.frames)
			if (f.found && f.frame == classifier.restFrame) driverRest = normalisedMouth(unsmoothedPoints(f));
		if (driverRest.rows() == 0) ibug = false;
	}
	// A keypose per run of one class, at its middle.
	for (std::size_t i = 0; i < n;) {
		if (cls[i] < 0) {
			++i;
			continue;
		}
		std::size_t j = i;
		while (j < n && cls[j] == cls[i]) ++j;
		const std::size_t mid = (i + j - 1) / 2;
		Keypose k;
		k.time = driver.frames[mid].time;
		k.cdv = Cdv::parse(classifier.classes[std::size_t(cls[i])]);
		k.first = k.last = mid;
		if (ibug) {
			const std::string& e = model.findSample(emotion, k.cdv.label()) >= 0 ? emotion : Emotion::neutralLabel();
			std::vector<std::size_t> exemplars;
			for (std::size_t s = 0; s < model.sampleCount(); ++s)
				if (model.samples[s].cdv == k.cdv.label() && model.samples[s].emotion == e) exemplars.push_back(s);
			if (exemplars.size() > 1) {
				const Points moved = actorRest + (normalisedMouth(unsmoothedPoints(driver.frames[mid])) - driverRest);
				double best = std::numeric_limits<double>::max();
				for (std::size_t s : exemplars) {
					const double d = modifiedHausdorff(moved, normalisedMouth(model.alignedShapes[s]));
					if (d < best) best = d, k.sample = long(s);
				}
				++out.exemplarChoices;
			}
		}
		out.keys.push_back(k);
		i = j;
	}
	if (out.keys.empty()) throw Error(driver.source, 0, "no frame with a face to drive the mouth from");
	return out;
}

}  // namespace talkhead
