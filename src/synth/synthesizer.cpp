// SPDX-License-Identifier: GPL-3.0-or-later
#include "synth/synthesizer.h"

#include <algorithm>
#include <cmath>

#include "base/error.h"
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

const KeyposeImage& Synthesizer::keypose(const std::string& cdv) {
	std::lock_guard<std::mutex> lock(mutex_);
	if (auto it = cache_.find(cdv); it != cache_.end()) return *it->second;
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
	auto k = std::make_unique<KeyposeImage>();
	const SampleInfo& s = model_.samples[std::size_t(sample)];
	k->usedEmotion = s.emotion;
	k->usedCdv = s.cdv;
	if (s.emotion != o_.emotion || s.cdv != cdv) substitutions_.push_back(o_.emotion + " " + cdv + " -> " + s.emotion + " " + s.cdv);
	// Spec §5.3: appearance per region from its coefficients, composited coarse to fine into the
	// baseface (mean-shape frame), then warped to the keypose shape (the entry's aligned shape).
	std::vector<Eigen::VectorXf> coeffs;
	for (const auto& r : model_.regions) coeffs.push_back(sampleCoefficients(r, std::size_t(sample)));
	k->shape = model_.alignedShapes[std::size_t(sample)];
	k->image = warpFromMean(model_, compositeAppearance(model_, coeffs), k->shape);
	return *cache_.emplace(cdv, std::move(k)).first->second;
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
	for (const auto& k : keys) keypose(k.cdv);
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
	const Points pOut = withFrameBorder(points, width_, height_);
	if (!ws.warp) ws.warp = std::make_unique<PiecewiseAffineWarp>(model_.frameMesh, pOut, width_, height_);
	else ws.warp->setDestination(pOut);
	// Forward warp of the source keypose S → P(t); backward warp of the target T → P(t); dissolve.
	ws.warp->setSource(withFrameBorder(src.shape, model_.width, model_.height));
	if (hold || u <= 0) {
		ws.warp->apply(src.image, out);
		return;
	}
	if (ws.a.width != width_ || ws.a.height != height_) ws.a = Image8(width_, height_, 3), ws.b = Image8(width_, height_, 3);
	ws.warp->apply(src.image, ws.a);
	ws.warp->setSource(withFrameBorder(dst.shape, model_.width, model_.height));
	ws.warp->apply(dst.image, ws.b);
	const double w = o_.dissolve == Trajectory::Hermite ? u * u * (3 - 2 * u) : u;  // Eq. 5.4: F = K_f (1 − t) + K_b t
	const int wb = int(std::lround(w * 256)), wa = 256 - wb;
	const std::uint8_t* a = ws.a.data.data();
	const std::uint8_t* b = ws.b.data.data();
	std::uint8_t* o = out.data.data();
	const std::size_t n = out.data.size();
	for (std::size_t k = 0; k < n; ++k) o[k] = std::uint8_t((a[k] * wa + b[k] * wb + 128) >> 8);
}

}  // namespace talkhead
