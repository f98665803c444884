// SPDX-License-Identifier: GPL-3.0-or-later
// The keypose cache (issue 30: the synthesizer split in three): which model sample each keypose uses
// (emotion, CDV and context, with the fallbacks), its appearance composited once, shared by every frame.
#include "synth/keypose_cache.h"

#include <algorithm>
#include <limits>

#include "base/parallel.h"
#include "phonetics/emotion.h"
#include "phonetics/labels.h"
#include "synth/coarticulation.h"
#include "synth/face_rig.h"
#include "warp/dissolve_detail.h"
#include "warp/piecewise_affine.h"
#include "warp/prefilter.h"

namespace talkhead {

KeyposeCache::KeyposeCache(const Face& face, const SynthOptions& options, const FaceRig& rig)
    : face_(face), model_(face.model()), o_(options), rig_(rig), lipScheme_(mouthScheme(model_, scheme_)) {}
KeyposeCache::~KeyposeCache() = default;

// D71: the neutral samples' mouths, for the skin of keyposes made from action units.
struct KeyposeCache::NeutralMouths {
	Scheme scheme;
	std::vector<MouthSize> size;
	MouthPool pool;
	std::vector<bool> regions;  // the model's regions that show the mouth and not the eyes: those that take its skin
	bool usable = false;
	double restLift = 0;  // the corners' lift (MouthSize::lift) of the face's shut mouths: its resting level
};

namespace {
// The homorganic group (first phone) of a CDV, from phonetics/visemes.tsv.
std::string groupOf(const std::string& cdv) {
	for (const auto& v : visemeLabels())
		if (v.label == cdv) return v.group.empty() ? v.label : v.group.front();
	return cdv;
}
}  // namespace

bool KeyposeCache::hasEmotion(const std::string& emotion) const {
	for (const auto& s : model_.samples)
		if (s.emotion == emotion) return true;
	return false;
}

bool KeyposeCache::ownsMouth(const std::string& emotion, const std::string& cdv) const {
	for (const auto& s : model_.samples)
		if (s.emotion == emotion && groupOf(s.cdv) == groupOf(cdv)) return true;
	return false;
}

bool KeyposeCache::fromActionUnits(const Keypose& key) const {
	if (!rig_.auTemplates || o_.emotionSource == EmotionSource::Corpus) return false;
	const std::string& emotion = emotionOf(key).label();
	if (emotion == Emotion::neutralLabel() || !defaultAuProfiles().count(emotion)) return false;
	if (o_.emotionSource == EmotionSource::ActionUnits) return true;
	if (key.sample >= 0 && std::size_t(key.sample) < model_.sampleCount() && model_.samples[std::size_t(key.sample)].emotion == emotion) return false;
	if (!hasEmotion(emotion)) return true;
	// Issue 47: an emotion recorded in a short take lacks some CDVs. One it lacks with its whole group is
	// drawn from the neutral face's mouth for it, moved by the emotion's action units — not the neutral face
	// itself (the emotion would vanish for that keypose) nor the emotion's shut silence (it would mumble).
	return !ownsMouth(emotion, key.cdv.label()) && ownsMouth(Emotion::neutralLabel(), key.cdv.label());
}

std::pair<long, long> KeyposeCache::resolvePair(const Keypose& key) const {
	if (fromActionUnits(key)) return {resolve(key, Emotion::neutralLabel()), -1};
	const long sample = resolve(key);
	// Intensity (D43): between the neutral keypose of the same CDV and context (0) and the emotion's (1).
	const double intensity = intensityOf(key);
	if (emotionOf(key).isNeutral() || intensity == 1.0) return {sample, -1};
	return {sample, resolve(key, Emotion::neutralLabel())};
}

Emotion KeyposeCache::emotionOf(const Keypose& key) const { return key.emotion.value_or(o_.expression.emotion()); }
double KeyposeCache::intensityOf(const Keypose& key) const { return key.intensity.value_or(o_.expression.intensity()); }
std::string KeyposeCache::indexKey(const Keypose& key) const {
	const long step = lipScheme_ ? openingStep(key) : -1;
	return key.cdv.label() + "\t" + emotionOf(key).label() + "\t" + std::to_string(intensityOf(key)) + (key.sample >= 0 ? "\t#" + std::to_string(key.sample) : "") +
	       (step >= 0 ? "\t@" + std::to_string(step) : "");
}

long KeyposeCache::resolve(const Keypose& key) const { return resolve(key, emotionOf(key).label()); }

long KeyposeCache::resolve(const Keypose& key, const std::string& emotion) const {
	// Fallbacks (issue 5, 47): the emotion's entry, its own group's other CDVs, neutral for that CDV, then
	// neutral's in the group, then the emotion's nearest mouth; among several samples of one entry, the
	// best phone context (FaceModel::findSample).
	const std::string& cdv = key.cdv.label();
	const auto* context = &key.context;
	if (key.sample >= 0 && std::size_t(key.sample) < model_.sampleCount() && model_.samples[std::size_t(key.sample)].emotion == emotion) return key.sample;
	long sample = model_.findSample(emotion, cdv, context);
	// Issue 47: an emotion recorded in the CDV's group keeps itself (a homorganic sibling) before it is
	// dropped for neutral's sample of the CDV.
	if (sample < 0 && ownsMouth(emotion, cdv))
		for (const auto& v : visemeLabels())
			if (sample < 0 && v.label != cdv && groupOf(v.label) == groupOf(cdv)) sample = model_.findSample(emotion, v.label, context);
	if (sample < 0) sample = model_.findSample(Emotion::neutralLabel(), cdv, context);
	if (sample < 0)  // the emotion has none of the group (above): neutral's
		for (const auto& v : visemeLabels())
			if (sample < 0 && v.label != cdv && groupOf(v.label) == groupOf(cdv)) sample = model_.findSample(Emotion::neutralLabel(), v.label, context);
	if (sample < 0) {
		// Issue 47: the emotion's CDV whose mouth is nearest this one's (a short take lacks CDVs that neither
		// it nor the neutral take has, all of one sentence): a spread /i/ for a missing /ɪ/, not the shut rest.
		double best = std::numeric_limits<double>::max();
		for (std::size_t i = 0; i < model_.sampleCount(); ++i) {
			const SampleInfo& s = model_.samples[i];
			const auto other = s.emotion == emotion ? Cdv::find(s.cdv) : std::nullopt;
			if (!other) continue;
			const double d = key.cdv.mouthDistance(*other);
			if (d < best) best = d, sample = model_.findSample(emotion, s.cdv, context);
		}
	}
	if (sample < 0) {
		// Last resort: the emotion's silence, then anything of the emotion, then the first sample.
		sample = model_.findSample(emotion, "sil");
		for (std::size_t i = 0; sample < 0 && i < model_.sampleCount(); ++i)
			if (model_.samples[i].emotion == emotion) sample = long(i);
		if (sample < 0) sample = 0;
	}
	return sample;
}

const KeyposeImage& KeyposeCache::keypose(Cdv cdv) {
	Keypose k{Ticks(0), cdv, 0, 0};
	k.context = {"", "", "", "", ""};  // no context: the corpus's first sample of the CDV
	prepare({k});
	return cached(k);
}

const KeyposeImage& KeyposeCache::cached(const Keypose& key) const {
	std::lock_guard<std::mutex> lock(mutex_);
	auto it = index_.find(indexKey(key));
	if (it != index_.end()) {
		auto jt = it->second.find(key.context);
		if (jt != it->second.end()) return *jt->second;
	}
	throw std::logic_error("Synthesizer: keypose not prepared: " + key.cdv.label());
}

std::vector<std::string> KeyposeCache::substitutions() const {
	std::lock_guard<std::mutex> lock(mutex_);
	return substitutions_;
}

namespace {

std::string actionUnitLine(const std::string& emotion) {
	return emotion + " from the neutral images by its action units (the model has no " + emotion + " images)";
}
std::string actionUnitLine(const std::string& emotion, const std::string& cdv) {
	return emotion + " " + cdv + " -> neutral " + cdv + " with " + emotion + "'s action units (the model's " + emotion + " has no " + cdv + " nor its group)";
}

}  // namespace

KeyposeSource KeyposeCache::sourceOf(const Keypose& key) const {
	KeyposeSource s;
	if (fromActionUnits(key)) {
		s.kind = KeyposeSource::Kind::ActionUnits;
		const SampleInfo& n = model_.samples[std::size_t(resolve(key, Emotion::neutralLabel()))];
		s.emotion = n.emotion, s.cdv = n.cdv;
		return s;
	}
	const SampleInfo& u = model_.samples[std::size_t(resolve(key))];
	s.emotion = u.emotion, s.cdv = u.cdv;
	s.kind = u.emotion == emotionOf(key).label() && u.cdv == key.cdv.label() ? KeyposeSource::Kind::Own : KeyposeSource::Kind::Borrowed;
	return s;
}

std::vector<std::string> KeyposeCache::substitutionsFor(const std::vector<Keypose>& keys) const {
	std::vector<std::string> out;
	for (const auto& k : keys) {
		const std::string& emotion = emotionOf(k).label();
		if (fromActionUnits(k)) {  // issue 31: an emotion the model lacks comes from its action units
			if (o_.emotionSource == EmotionSource::ActionUnits) continue;  // asked for
			const std::string line = hasEmotion(emotion) ? actionUnitLine(emotion, k.cdv.label()) : actionUnitLine(emotion);
			if (std::find(out.begin(), out.end(), line) == out.end()) out.push_back(line);
			continue;
		}
		if (k.mouthOpening && k.sample >= 0) continue;  // D62: an exemplar chosen for its mouth, not a substitute
		const SampleInfo& s = model_.samples[std::size_t(resolve(k))];
		const std::string line = emotion + " " + k.cdv.label() + " -> " + s.emotion + " " + s.cdv;
		if ((s.emotion != emotion || s.cdv != k.cdv.label()) && std::find(out.begin(), out.end(), line) == out.end()) out.push_back(line);
	}
	return out;
}


KeyposeImage KeyposeCache::makeKeypose(long sample, const Points& shape, const std::vector<const std::uint8_t*>& cached8,
                                      const std::vector<Eigen::VectorXf>& synthesized, const std::vector<float>& gain) const {
	KeyposeImage k;
	const SampleInfo& s = model_.samples[std::size_t(sample)];
	k.usedEmotion = s.emotion;
	k.usedCdv = s.cdv;
	k.shape = shape;
	const std::size_t nr = model_.regions.size();
	if (o_.warpPath == WarpPath::Keypose) {
		std::vector<Eigen::VectorXf> a(nr);
		for (std::size_t r = 0; r < nr; ++r) {
			if (cached8[r]) {
				a[r].resize(model_.regions[r].appearanceSize());
				for (Eigen::Index j = 0; j < a[r].size(); ++j) a[r](j) = cached8[r][j];
			} else {
				a[r] = synthesized[r];
			}
		}
		PiecewiseAffineWarp warp(rig_.mesh, withAnchors(k.shape, rig_.anchors, model_.width, model_.height), model_.width, model_.height);
		warp.setSource(rig_.meanSource);
		k.image = Image8(model_.width, model_.height, 3);
		Image composite = compositeRegions(model_, a);
		if (!gain.empty()) {
			const int rw = rig_.roiX1 - rig_.roiX0;
			for (int y = rig_.roiY0; y < rig_.roiY1; ++y)
				for (int x = rig_.roiX0; x < rig_.roiX1; ++x)
					for (int c = 0; c < 3; ++c) composite.at(x, y, c) *= gain[std::size_t(y - rig_.roiY0) * std::size_t(rw) + std::size_t(x - rig_.roiX0)];
		}
		warp.apply(composite, k.image);
		return k;
	}
	// Spec §5.3 in the face box only (the baseface elsewhere): regions pasted coarse → fine through their
	// soft masks, in float, then rounded to 8 bits.
	const int rw = rig_.roiX1 - rig_.roiX0, rh = rig_.roiY1 - rig_.roiY0, W = model_.width;
	thread_local std::vector<float> crop;  // reused: fresh pages cost more than the compositing here
	crop.resize(std::size_t(rw) * rh * 3);
	for (int y = 0; y < rh; ++y) {
		const std::uint8_t* b = model_.baseface.row(rig_.roiY0 + y) + std::size_t(rig_.roiX0) * 3;
		for (int i = 0; i < rw * 3; ++i) crop[std::size_t(y) * rw * 3 + std::size_t(i)] = b[i];
	}
	for (std::size_t r = 0; r < nr; ++r) {
		const RegionModel& reg = model_.regions[r];
		const std::size_t q = reg.pixels.size();
		for (std::size_t p = 0; p < q; ++p) {
			const int idx = reg.pixels[p], x = idx % W - rig_.roiX0, y = idx / W - rig_.roiY0;
			float* px = &crop[(std::size_t(y) * rw + std::size_t(x)) * 3];
			const float w = reg.alpha[p];
			for (std::size_t c = 0; c < 3; ++c) {
				const float a = cached8[r] ? float(cached8[r][c * q + p]) : synthesized[r](Eigen::Index(c * q + p));
				px[c] = w * a + (1 - w) * px[c];
			}
		}
	}
	if (!gain.empty())  // the skin's luminance, all three channels alike (no hue change)
		for (std::size_t p = 0; p < gain.size(); ++p)
			for (std::size_t c = 0; c < 3; ++c) crop[3 * p + c] *= gain[p];
	k.rgb.resize(crop.size());
	if (rig_.prefilter > 0) {  // D84: as the frame warp samples it, over the box and a pixel of baseface around it
		thread_local std::vector<float> framed;
		const int fw = rw + 2, fh = rh + 2;
		framed.resize(std::size_t(fw) * fh * 3);
		for (int y = 0; y < fh; ++y)
			for (int x = 0; x < fw; ++x) {
				float* f = &framed[(std::size_t(y) * fw + std::size_t(x)) * 3];
				if (y >= 1 && y <= rh && x >= 1 && x <= rw) {
					std::copy_n(&crop[(std::size_t(y - 1) * rw + std::size_t(x - 1)) * 3], 3, f);
				} else {
					const int by = std::clamp(rig_.roiY0 + y - 1, 0, model_.height - 1), bx = std::clamp(rig_.roiX0 + x - 1, 0, W - 1);
					const std::uint8_t* b = model_.baseface.row(by) + std::size_t(bx) * 3;
					f[0] = b[0], f[1] = b[1], f[2] = b[2];
				}
			}
		prefilterForBilinear(framed.data(), fw, fh, 3, rig_.prefilter);
		const std::vector<float>& mask = rig_.prefilterMask;
		for (int y = 0; y < rh; ++y) {
			const float* f = &framed[(std::size_t(y + 1) * fw + 1) * 3];
			float* c = &crop[std::size_t(y) * rw * 3];
			if (mask.empty()) {
				std::copy_n(f, std::size_t(rw) * 3, c);
			} else {
				const float* m = &mask[std::size_t(rig_.roiY0 + y) * std::size_t(W) + std::size_t(rig_.roiX0)];
				for (std::size_t i = 0; i < std::size_t(rw) * 3; ++i) c[i] = c[i] + m[i / 3] * (f[i] - c[i]);
			}
		}
	}
	for (std::size_t i = 0; i < crop.size(); ++i) {
		const float v = crop[i] + 0.5f;
		k.rgb[i] = std::uint8_t(v <= 0.f ? 0.f : (v >= 255.f ? 255.f : v));
	}
	const int cw = (rw + 1) / 2, ch = (rh + 1) / 2;
	k.y.resize(std::size_t(rw) * rh);
	k.uv.resize(std::size_t(cw) * ch * 2);
	if (rw > 0 && rh > 0)
		rgbToYuv420(k.rgb.data(), std::size_t(rw) * 3, rw, rh, o_.yuvRange, k.y.data(), std::size_t(rw), k.uv.data(), k.uv.data() + 1,
		            std::size_t(cw) * 2, 2);
	if (rig_.prefilter > 0 && o_.dissolveDetail) {  // for the dissolves (issue 47)
		k.detail = fineDetail(k.y.data(), rw, rh);
		k.detailEnergy = detailEnergy(k.detail.data(), rw, rh);
	}
	return k;
}

// One keypose image (a worker of prepare): its samples' appearances, from the cache or `synthesized`
// (columns in the order of `samples`), mixed toward neutral or moved by action units as `key` says.
std::unique_ptr<KeyposeImage> KeyposeCache::makeImage(const ImageKey& key, const std::vector<Eigen::MatrixXf>& synthesized, const std::vector<long>& samples) const {
	auto column = [&](long sample) { return Eigen::Index(std::find(samples.begin(), samples.end(), sample) - samples.begin()); };
	const std::size_t nr = model_.regions.size();
	auto load = [&](long sample, std::vector<std::vector<std::uint8_t>>& bytes, std::vector<const std::uint8_t*>& cached8,
	                std::vector<Eigen::VectorXf>& synth) {
		bytes.resize(nr), cached8.assign(nr, nullptr), synth.resize(nr);
		for (std::size_t r = 0; r < nr; ++r) {
			const RegionModel& reg = model_.regions[r];
			if (reg.hasAppearanceCache()) {
				bytes[r].resize(std::size_t(reg.appearanceSize()));
				reg.readCachedAppearance(std::size_t(sample), bytes[r].data());
				cached8[r] = bytes[r].data();
			} else {
				synth[r] = synthesized[r].col(column(sample));
			}
		}
	};
	std::vector<std::vector<std::uint8_t>> bytes, baseBytes;
	std::vector<const std::uint8_t*> cached8, baseCached8;
	std::vector<Eigen::VectorXf> synth, baseSynth;
	const auto& [sample, base, intensity, auEmotion, look, lipsShut, closeLips, openTo] = key;
	const bool shut = closeLips;  // (C++17 lambdas cannot capture a structured binding: clang refuses it)
	const double opening = key.opening();
	const auto drawn = [this, shut, opening](Points shape, bool opened = false) {
		if (opening >= 0 && !opened) drawOpening(scheme_, shape, opening);
		if (shut) shutLips(scheme_, shape);
		return shape;
	};
	load(sample, bytes, cached8, synth);
	if (look >= 0) {  // D71: the mouth's skin from the neutral sample whose mouth is nearest the shape's
		std::vector<std::vector<std::uint8_t>> lookBytes;
		std::vector<const std::uint8_t*> lookCached8;
		std::vector<Eigen::VectorXf> lookSynth;
		load(look, lookBytes, lookCached8, lookSynth);
		for (std::size_t r = 0; r < nr; ++r)
			if (mouths_->regions[r]) bytes[r] = std::move(lookBytes[r]), cached8[r] = bytes[r].empty() ? nullptr : bytes[r].data(), synth[r] = std::move(lookSynth[r]);
	}
	if (!auEmotion.empty()) {  // D48: the neutral sample, its shape moved by the emotion's action units
		const Points shape = drawn(actionUnitShape(sample, auEmotion, intensity, lipsShut, opening), true);
		static const std::vector<float> none;
		const auto gain = auGains_.find({auEmotion, intensity});  // made by prepare() before the workers start
		auto made = std::make_unique<KeyposeImage>(makeKeypose(sample, shape, cached8, synth, gain == auGains_.end() ? none : gain->second));
		made->usedEmotion = auEmotion + " (action units)";
		made->mouthSample = look;
		return made;
	}
	if (base < 0) {
		return std::make_unique<KeyposeImage>(makeKeypose(sample, drawn(model_.alignedShapes[std::size_t(sample)]), cached8, synth));
	}
	// D43: shape and appearance of neutral + intensity × (emotion − neutral), per region.
	load(base, baseBytes, baseCached8, baseSynth);
	std::vector<Eigen::VectorXf> mixed(nr);
	const float t = float(intensity);
	for (std::size_t r = 0; r < nr; ++r) {
		const Eigen::Index n = model_.regions[r].appearanceSize();
		auto value = [&](const std::vector<const std::uint8_t*>& c8, const std::vector<Eigen::VectorXf>& sy, Eigen::Index i) {
			return c8[r] ? float(c8[r][i]) : sy[r](i);
		};
		mixed[r].resize(n);
		for (Eigen::Index i = 0; i < n; ++i) {
			const float b = value(baseCached8, baseSynth, i);
			mixed[r](i) = b + t * (value(cached8, synth, i) - b);
		}
	}
	const Points& a = model_.alignedShapes[std::size_t(sample)];
	const Points& b = model_.alignedShapes[std::size_t(base)];
	const std::vector<const std::uint8_t*> none(nr, nullptr);
	return std::make_unique<KeyposeImage>(makeKeypose(sample, drawn(b + intensity * (a - b)), none, mixed));
}

long KeyposeCache::openingStep(const Keypose& key) {
	return key.drawnOpening && key.sample >= 0 ? std::lround(std::max(0.0, *key.drawnOpening) / kOpeningStep) : -1;
}

Points KeyposeCache::actionUnitShape(long sample, const std::string& emotion, double intensity, bool lipsShut, double opening) const {
	Points shape = model_.alignedShapes[std::size_t(sample)];
	if (opening >= 0 && lipScheme_) drawOpening(scheme_, shape, opening);
	AuProfile profile = defaultAuProfiles().at(emotion);
	if (lipsShut)  // a bilabial's closure overrides the units that part the lips (corpus-tools/data/expression-aus.tsv)
		profile.erase(std::remove_if(profile.begin(), profile.end(),
		                             [](const auto& u) { return u.first == "AU10" || u.first == "AU16" || u.first == "AU25" || u.first == "AU26"; }),
		              profile.end());
	applyActionUnits(shape, *rig_.auTemplates, profileWeights(*rig_.auTemplates, profile, intensity), rig_.auFrame);
	// D72: an emotion without a smile (no AU12) takes away the smile a face's own mouth brings: the
	// sample's corners lifted above the face's resting level (its shut mouths') come down by that much, the
	// mouth's points moved by (their distance from the centre / the half width)², so the centre stays and the
	// corners move most; what the emotion's units do to the corners (AU15, AU20) comes on top.
	const bool smiles = std::any_of(profile.begin(), profile.end(), [](const auto& u) { return u.first == "AU12" && u.second > 0; });
	if (!smiles && mouths_ && mouths_->usable) {
		const double excess = mouths_->size[std::size_t(sample)].lift - mouths_->restLift;
		const MouthFrame f = mouthFrame(mouths_->scheme, shape);
		if (excess > 0 && f.iod > 0) {
			const double half = 0.5 * std::abs((shape.row(mouths_->scheme.mouth.corner1) - shape.row(mouths_->scheme.mouth.corner0)).dot(f.across));
			const double amount = excess * f.iod * std::min(1.0, intensity);
			for (Eigen::Index i = 0; i < shape.rows() && half > 0; ++i) {
				const Eigen::RowVector2d v = shape.row(i) - f.centre;
				const double u = std::abs(v.dot(f.across)) / half, w = v.dot(f.down) / half;
				if (u <= 1.15 && std::abs(w) <= 0.7) shape.row(i) += amount * std::min(1.0, u * u) * f.down;
			}
		}
	}
	return shape;
}

std::vector<bool> KeyposeCache::mouthRegions() const {
	// A region shows the mouth alone when none of its pixels lies in an eye's box (corners and lids on the
	// mean shape, a tenth of the eye distance around): another sample's eyes (a half-shut lid) never come in.
	std::vector<bool> out(model_.regions.size(), false);
	if (rig_.eyes.size() != 2) return out;
	const Points& m = model_.meanShape;
	const double margin = 0.1 * rig_.eyeDistance;
	struct Box {
		double x0, y0, x1, y1;
	};
	std::vector<Box> boxes;
	for (const EyeSpec& e : rig_.eyes) {
		Box b{1e300, 1e300, -1e300, -1e300};
		std::vector<int> pts = e.upper;
		pts.insert(pts.end(), e.lower.begin(), e.lower.end());
		pts.push_back(e.corner0), pts.push_back(e.corner1);
		for (int i : pts)
			if (i >= 0) b = {std::min(b.x0, m(i, 0)), std::min(b.y0, m(i, 1)), std::max(b.x1, m(i, 0)), std::max(b.y1, m(i, 1))};
		boxes.push_back({b.x0 - margin, b.y0 - margin, b.x1 + margin, b.y1 + margin});
	}
	Scheme scheme;
	if (!mouthScheme(model_, scheme)) return out;
	const double mouthY = m(scheme.mouth.corner0, 1);
	for (std::size_t r = 0; r < model_.regions.size(); ++r) {
		const RegionModel& reg = model_.regions[r];
		bool eye = false, mouth = false;
		for (std::int32_t idx : reg.pixels) {
			const double x = idx % model_.width, y = idx / model_.width;
			for (const Box& b : boxes) eye = eye || (x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1);
			mouth = mouth || std::abs(y - mouthY) < 0.05 * rig_.eyeDistance;
		}
		out[r] = mouth && !eye;
	}
	return out;
}

void KeyposeCache::measureNeutralMouths() {
	mouths_ = std::make_unique<NeutralMouths>();
	NeutralMouths& m = *mouths_;
	if (!mouthScheme(model_, m.scheme)) return;
	m.size = sampleMouths(model_, m.scheme);
	m.pool = mouthPool(model_, m.size, Emotion::neutralLabel());
	m.regions = mouthRegions();
	m.usable = m.pool.scale > 0 && std::find(m.regions.begin(), m.regions.end(), true) != m.regions.end();
	std::vector<double> shut;
	for (std::size_t i : m.pool.samples)
		if (model_.samples[i].cdv != "sil" && m.size[i].opening <= m.pool.closedLimit) shut.push_back(m.size[i].lift);
	std::sort(shut.begin(), shut.end());
	if (!shut.empty()) m.restLift = shut[shut.size() / 2];
}

long KeyposeCache::mouthLook(long sample, const Points& shape) const {
	if (!mouths_ || !mouths_->usable) return -1;
	const MouthSize want = mouthSize(mouths_->scheme, shape);
	// A warp can close and narrow a mouth, not open it: the teeth and the mouth's inside that the units
	// uncover come only from a sample that shows them. A mouth opened by less than a tenth of this face's
	// open range keeps its own skin.
	if (want.opening <= mouths_->size[std::size_t(sample)].opening + 0.1 * mouths_->pool.scale) return -1;
	const long best = nearestMouth(model_, mouths_->pool, mouths_->size, want.opening, want.width, sample);
	return best == sample ? -1 : best;
}

void KeyposeCache::prepareAuAppearance(const std::vector<std::string>& emotions) {
	if (!o_.auAppearance) return;
	std::vector<std::string> missing;
	for (const std::string& e : emotions)
		for (const auto& [au, w] : defaultAuProfiles().at(e))
			if (w != 0 && (!auAppearance_ || auAppearance_->find(au) < 0) && std::find(missing.begin(), missing.end(), au) == missing.end())
				missing.push_back(au);
	std::optional<MappedAuAppearance> mapped = face_.auSkin(missing, rig_.roiX0, rig_.roiY0, rig_.roiX1 - rig_.roiX0, rig_.roiY1 - rig_.roiY0, o_.auOwnSkin);
	if (!mapped) return;
	MappedAuAppearance& m = *mapped;
	if (!auAppearance_) {
		auAppearance_ = std::make_unique<MappedAuAppearance>(std::move(m));
		return;
	}
	for (std::size_t j = 0; j < m.names.size(); ++j) {
		auAppearance_->names.push_back(m.names[j]);
		auAppearance_->logRatio.push_back(std::move(m.logRatio[j]));
	}
}

void KeyposeCache::prepare(const std::vector<Keypose>& keys) {
	// The (CDV, context) pairs not seen yet, their (sample, neutral sample) pairs, the pairs without an
	// image yet, and the samples those need.
	using Pair = std::pair<long, long>;
	std::vector<std::pair<const Keypose*, ImageKey>> fresh;
	std::vector<ImageKey> pairs;
	std::vector<long> samples;
	{
		std::lock_guard<std::mutex> lock(mutex_);
		for (const auto& k : keys) {
			auto it = index_.find(indexKey(k));
			if (it != index_.end() && it->second.count(k.context)) continue;
			if (std::any_of(fresh.begin(), fresh.end(), [&](const auto& f) { return indexKey(*f.first) == indexKey(k) && f.first->context == k.context; }))
				continue;
			const Pair pair = resolvePair(k);
			const bool au = fromActionUnits(k);
			ImageKey key{pair.first, pair.second, pair.second < 0 && !au ? 1.0 : intensityOf(k), au ? emotionOf(k).label() : std::string()};
			key.closeLips = lipScheme_ && k.sample >= 0 && bilabial(k.cdv.label());
			if (lipScheme_) key.openTo = openingStep(k);
			if (au) {
				if (!mouths_) measureNeutralMouths();
				key.lipsShut = bilabial(k.cdv.label());
				// Lips parted (AU25) or the jaw dropped (AU26) open the mouth as speech does, so a speech sample
				// shows it; AU10's bared upper teeth behind lips still together are not a speech mouth.
				const AuProfile& profile = defaultAuProfiles().at(key.auEmotion);
				const bool parts = std::any_of(profile.begin(), profile.end(), [](const auto& u) { return (u.first == "AU25" || u.first == "AU26") && u.second > 0; });
				if (!key.lipsShut && parts)
					key.look = mouthLook(key.sample, actionUnitShape(key.sample, key.auEmotion, key.intensity, false, key.opening()));
			}
			fresh.push_back({&k, key});
			if (images_.count(key) || std::find(pairs.begin(), pairs.end(), key) != pairs.end()) continue;
			pairs.push_back(key);
			for (long sample : {pair.first, pair.second, key.look})
				if (sample >= 0 && std::find(samples.begin(), samples.end(), sample) == samples.end()) samples.push_back(sample);
		}
	}
	if (fresh.empty()) return;
	// Appearances: each sample's 8-bit reconstruction from the model's cache (read from disk on demand),
	// or, for a model without one, one GEMM per region for all the keyposes (the basis is read once).
	std::vector<Eigen::MatrixXf> synthesized(model_.regions.size());
	for (std::size_t r = 0; r < model_.regions.size(); ++r) {
		const RegionModel& reg = model_.regions[r];
		if (reg.hasAppearanceCache()) continue;
		Eigen::MatrixXf c(reg.pca.components(), Eigen::Index(samples.size()));
		for (std::size_t j = 0; j < samples.size(); ++j) c.col(Eigen::Index(j)) = sampleCoefficients(reg, std::size_t(samples[j]));
		synthesized[r] = synthesizeAppearances(reg, c);
	}
	std::vector<std::unique_ptr<KeyposeImage>> made(pairs.size());
	std::vector<std::string> auEmotions;
	for (const ImageKey& k : pairs)
		if (!k.auEmotion.empty() && std::find(auEmotions.begin(), auEmotions.end(), k.auEmotion) == auEmotions.end()) auEmotions.push_back(k.auEmotion);
	if (!auEmotions.empty()) prepareAuAppearance(auEmotions);
	for (const ImageKey& k : pairs) {
		if (k.auEmotion.empty() || !auAppearance_ || auGains_.count({k.auEmotion, k.intensity})) continue;
		AuProfile scaled = defaultAuProfiles().at(k.auEmotion);
		for (auto& [au, w] : scaled) w *= k.intensity;
		auGains_[{k.auEmotion, k.intensity}] = appearanceGain(*auAppearance_, scaled);
	}
	parallelFor(pairs.size(), 0, [&](std::size_t j) { made[j] = makeImage(pairs[j], synthesized, samples); });
	std::lock_guard<std::mutex> lock(mutex_);
	for (std::size_t j = 0; j < pairs.size(); ++j) images_.emplace(pairs[j], std::move(made[j]));
	for (const auto& [k, key] : fresh) {
		const KeyposeImage* image = images_.at(key).get();
		index_[indexKey(*k)][k->context] = image;
		const std::string& emotion = emotionOf(*k).label();
		std::string line;
		if (image->usedEmotion == emotion + " (action units)") {
			if (o_.emotionSource == EmotionSource::ActionUnits) continue;  // asked for
			line = hasEmotion(emotion) ? actionUnitLine(emotion, k->cdv.label()) : actionUnitLine(emotion);
		} else if ((image->usedEmotion != emotion || image->usedCdv != k->cdv.label()) && !(k->mouthOpening && k->sample >= 0)) {
			line = emotion + " " + k->cdv.label() + " -> " + image->usedEmotion + " " + image->usedCdv;
		} else {
			continue;
		}
		if (std::find(substitutions_.begin(), substitutions_.end(), line) == substitutions_.end()) substitutions_.push_back(line);
	}
}

}  // namespace talkhead
