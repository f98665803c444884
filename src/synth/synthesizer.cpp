// SPDX-License-Identifier: GPL-3.0-or-later
#include "synth/synthesizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "base/error.h"
#include "base/parallel.h"
#include "phonetics/labels.h"
#include "warp/piecewise_affine.h"

namespace talkhead {

Synthesizer::Synthesizer(const FaceModel& model, const SynthOptions& o) : model_(model), o_(o) {
	width_ = o.width > 0 ? o.width : model.width;
	height_ = o.height > 0 ? o.height : model.height;
	scaleX_ = double(width_) / model.width;
	scaleY_ = double(height_) / model.height;
}

namespace {
// The homorganic group (first phone) of a CDV, from phonetics/visemes.tsv.
std::string groupOf(const std::string& cdv) {
	for (const auto& v : visemeLabels())
		if (v.label == cdv) return v.group.empty() ? v.label : v.group.front();
	return cdv;
}
}  // namespace

long Synthesizer::resolve(const std::string& cdv) const {
	// Fallbacks (issue 5): the emotion's entry, then neutral for that CDV, then the group's other CDVs.
	long sample = model_.findSample(o_.emotion, cdv);
	if (sample < 0) sample = model_.findSample("neutral", cdv);
	if (sample < 0)
		for (const auto& v : visemeLabels())
			if (sample < 0 && v.label != cdv && groupOf(v.label) == groupOf(cdv)) {
				sample = model_.findSample(o_.emotion, v.label);
				if (sample < 0) sample = model_.findSample("neutral", v.label);
			}
	if (sample < 0) {
		// Last resort: the emotion's silence, then anything of the emotion, then the first sample.
		sample = model_.findSample(o_.emotion, "sil");
		for (std::size_t i = 0; sample < 0 && i < model_.sampleCount(); ++i)
			if (model_.samples[i].emotion == o_.emotion) sample = long(i);
		if (sample < 0) sample = 0;
	}
	return sample;
}

const KeyposeImage& Synthesizer::keypose(const std::string& cdv) {
	prepare({Keypose{Ticks(0), cdv, 0, 0}});
	return cached(cdv);
}

const KeyposeImage& Synthesizer::cached(const std::string& cdv) const {
	std::lock_guard<std::mutex> lock(mutex_);
	auto it = cache_.find(cdv);
	if (it == cache_.end()) throw std::logic_error("Synthesizer: keypose not prepared: " + cdv);
	return *it->second;
}

std::vector<std::string> Synthesizer::substitutions() const {
	std::lock_guard<std::mutex> lock(mutex_);
	return substitutions_;
}

void Synthesizer::prepare(const std::vector<Keypose>& keys) {
	// Every keypose of the timeline: the appearances of all of them in one GEMM per region (the basis is
	// read once, not once per keypose), then composite and warp each.
	std::vector<std::string> todo;
	{
		std::lock_guard<std::mutex> lock(mutex_);
		for (const auto& k : keys)
			if (!cache_.count(k.cdv) && std::find(todo.begin(), todo.end(), k.cdv) == todo.end()) todo.push_back(k.cdv);
	}
	if (todo.empty()) return;
	std::vector<long> samples;
	for (const auto& cdv : todo) samples.push_back(resolve(cdv));
	// The model's 8-bit cache of every sample's reconstruction when it has one (format 2), else one GEMM
	// per region.
	std::vector<Eigen::MatrixXf> appearances;
	for (const auto& r : model_.regions) {
		if (r.hasAppearanceCache()) {
			Eigen::MatrixXf a(r.appearanceSize(), Eigen::Index(samples.size()));
			for (std::size_t j = 0; j < samples.size(); ++j) a.col(Eigen::Index(j)) = r.cachedAppearance(std::size_t(samples[j]));
			appearances.push_back(std::move(a));
			continue;
		}
		Eigen::MatrixXf c(r.pca.components(), Eigen::Index(samples.size()));
		for (std::size_t j = 0; j < samples.size(); ++j) c.col(Eigen::Index(j)) = sampleCoefficients(r, std::size_t(samples[j]));
		appearances.push_back(synthesizeAppearances(r, c));
	}
	std::vector<std::unique_ptr<KeyposeImage>> made(todo.size());
	parallelFor(todo.size(), 0, [&](std::size_t j) {
		auto k = std::make_unique<KeyposeImage>();
		const SampleInfo& s = model_.samples[std::size_t(samples[j])];
		k->usedEmotion = s.emotion;
		k->usedCdv = s.cdv;
		std::vector<Eigen::VectorXf> a;
		for (const auto& m : appearances) a.push_back(m.col(Eigen::Index(j)));
		k->shape = model_.alignedShapes[std::size_t(samples[j])];
		k->image = warpFromMean(model_, compositeRegions(model_, a), k->shape);
		made[j] = std::move(k);
	});
	std::lock_guard<std::mutex> lock(mutex_);
	for (std::size_t j = 0; j < todo.size(); ++j) {
		if (made[j]->usedEmotion != o_.emotion || made[j]->usedCdv != todo[j])
			substitutions_.push_back(o_.emotion + " " + todo[j] + " -> " + made[j]->usedEmotion + " " + made[j]->usedCdv);
		cache_.emplace(todo[j], std::move(made[j]));
	}
}

Points Synthesizer::trajectory(const Points& s, const Points& t, double u, Trajectory kind) {
	u = std::clamp(u, 0.0, 1.0);
	// Eq. 5.5 with zero tangents: P(t) = S + (T − S)(3t² − 2t³); linear: S + (T − S)t.
	const double h = kind == Trajectory::Hermite ? u * u * (3 - 2 * u) : u;
	return s + (t - s) * h;
}

void Synthesizer::renderFrame(Ticks tau, const std::vector<Keypose>& keys, Workspace& ws, Image8& out, Points& points) const {
	if (keys.empty()) throw std::logic_error("renderFrame: no keyposes");
	if (out.width != width_ || out.height != height_) out = Image8(width_, height_, 3);
	// The bracketing keyposes; before the first and after the last the face holds.
	std::size_t i = 0;
	while (i + 1 < keys.size() && keys[i + 1].time <= tau) ++i;
	const KeyposeImage& src = cached(keys[i].cdv);
	const bool hold = tau <= keys.front().time || i + 1 >= keys.size();
	const KeyposeImage& dst = hold ? src : cached(keys[i + 1].cdv);
	double u = 0;
	if (!hold) u = double((tau - keys[i].time).count()) / double((keys[i + 1].time - keys[i].time).count());
	if (tau <= keys.front().time) u = 0;
	const Points p = trajectory(src.shape, dst.shape, u, o_.trajectory);
	points = p;
	points.col(0) *= scaleX_;
	points.col(1) *= scaleY_;
	const auto t0 = std::chrono::steady_clock::now();
	const Points pOut = withFrameBorder(points, width_, height_);
	if (!ws.warp) ws.warp = std::make_unique<PiecewiseAffineWarp>(model_.frameMesh, pOut, width_, height_);
	else ws.warp->setDestination(pOut);
	if (hold || u <= 0) {
		ws.warp->setSource(withFrameBorder(src.shape, model_.width, model_.height));
		ws.warp->apply(src.image, out);
		ws.warpSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		return;
	}
	// Eq. 5.4 in one pass: F = K_f (1 − t) + K_b t, K_f = source warped S → P(t), K_b = target warped T → P(t).
	const double w = o_.dissolve == Trajectory::Hermite ? u * u * (3 - 2 * u) : u;
	ws.warp->dissolve(src.image, withFrameBorder(src.shape, model_.width, model_.height), dst.image,
	                  withFrameBorder(dst.shape, model_.width, model_.height), w, out);
	ws.warpSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace talkhead
