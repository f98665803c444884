// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <array>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

#include "model/face_model.h"
#include "phonetics/language.h"
#include "synth/au_appearance.h"
#include "synth/synthesizer.h"

namespace talkhead {

struct FaceRig;

// The keypose cache (issue 30: the second of the synthesizer's three parts): which model sample a keypose
// uses — its emotion's for its CDV and phone context, with the fallbacks (neutral, the homorganic group,
// the emotion's silence; each substitution said once) — and that sample's appearance composited once
// (coarse to fine, in the face box; or, on the thesis's path, warped to its shape), mixed toward neutral
// by the intensity (D43) or moved by the emotion's action units (D48). Thread-safe.
class KeyposeCache {
public:
	KeyposeCache(const Face& face, const SynthOptions& options, const FaceRig& rig);
	~KeyposeCache();
	// The keypose of a CDV in the options' emotion (see Synthesizer::keypose).
	const KeyposeImage& keypose(Cdv cdv);
	// Computes every keypose of a timeline that is not there yet.
	void prepare(const std::vector<Keypose>& keys);
	// A prepared keypose's image.
	const KeyposeImage& cached(const Keypose& key) const;
	std::vector<std::string> substitutions() const;
	std::vector<std::string> substitutionsFor(const std::vector<Keypose>& keys) const;
	// Where a keypose comes from, without drawing it (Synthesizer::keyposeSource).
	KeyposeSource sourceOf(const Keypose& key) const;

private:
	const Face& face_;
	const FaceModel& model_;
	SynthOptions o_;
	const FaceRig& rig_;
	mutable std::mutex mutex_;
	// Keypose images by (sample, neutral sample or −1, intensity), and which one each (CDV, emotion,
	// intensity; phone context) uses. A non-empty auEmotion: the sample is neutral and its shape takes
	// that emotion's action units (D48); its skin then comes from `look`, the neutral sample whose mouth is
	// nearest that shape's (D71; −1: the sample's own), and a bilabial's lips stay shut (`lipsShut`: the
	// units that part them are left out).
	struct ImageKey {
		long sample = -1, base = -1;
		double intensity = 1;
		std::string auEmotion;
		long look = -1;
		bool lipsShut = false;
		// A bilabial whose exemplar the learned mouth chose (Keypose::sample): its inner lips drawn shut
		// (shutLips, D99) — the exemplar may be a frame caught just before or after the closure.
		bool closeLips = false;
		// The opening the learned mouth predicted (Keypose::drawnOpening, D100), in steps of kOpeningStep eye
		// distances; −1: the exemplar's own.
		long openTo = -1;
		double opening() const { return openTo >= 0 ? double(openTo) * kOpeningStep : -1.0; }  // eye distances; −1: none
		bool operator<(const ImageKey& o) const {
			return std::tie(sample, base, intensity, auEmotion, look, lipsShut, closeLips, openTo) <
			       std::tie(o.sample, o.base, o.intensity, o.auEmotion, o.look, o.lipsShut, o.closeLips, o.openTo);
		}
		bool operator==(const ImageKey& o) const { return !(*this < o) && !(o < *this); }
	};
	Scheme scheme_;          // the model's scheme with its eyes and mouth (mouthScheme), for shutLips
	bool lipScheme_ = false;  // it has them
	std::map<ImageKey, std::unique_ptr<KeyposeImage>> images_;
	std::map<std::string, std::map<std::array<std::string, 5>, const KeyposeImage*>> index_;
	std::vector<std::string> substitutions_;
	bool fromActionUnits(const Keypose& key) const;  // whether this keypose's emotion comes from action units
	bool hasEmotion(const std::string& emotion) const;  // a sample of the emotion
	bool ownsMouth(const std::string& emotion, const std::string& cdv) const;  // a sample of the emotion in the CDV's group
	long resolve(const Keypose& key) const;          // the model sample used for a keypose (CDV, context)
	long resolve(const Keypose& key, const std::string& emotion) const;
	// The sample and, when the intensity mixes it in, the neutral sample of the same CDV and context (else −1).
	std::pair<long, long> resolvePair(const Keypose& key) const;
	Emotion emotionOf(const Keypose& key) const;  // the keypose's emotion, else the options'
	double intensityOf(const Keypose& key) const;
	std::string indexKey(const Keypose& key) const;  // CDV, emotion and intensity
	std::unique_ptr<KeyposeImage> makeImage(const ImageKey& key, const std::vector<Eigen::MatrixXf>& synthesized, const std::vector<long>& samples) const;
	// `gain`: the skin's luminance gain over the face box (action-unit appearance, issue 31), or empty.
	KeyposeImage makeKeypose(long sample, const Points& shape, const std::vector<const std::uint8_t*>& cached8,
	                         const std::vector<Eigen::VectorXf>& synthesized, const std::vector<float>& gain = {}) const;
	// Action-unit appearance (issue 31 route 2) mapped into the model's mean frame once, when the first
	// keypose from action units is made (nullptr: none installed, or the scheme has no eyes and brows).
	std::unique_ptr<MappedAuAppearance> auAppearance_;
	std::map<std::pair<std::string, double>, std::vector<float>> auGains_;  // per (emotion, intensity): the skin's gain
	void prepareAuAppearance(const std::vector<std::string>& emotions);  // maps the AUs these use, once each
	// D71: the emotion's action units on a sample's shape (without those that part the lips when they
	// stay shut), and the neutral sample whose mouth is nearest the result (−1: the sample's own).
	// The neutral sample's shape, drawn at `opening` (eye distances, drawOpening; < 0: its own), moved by the emotion's units.
	Points actionUnitShape(long sample, const std::string& emotion, double intensity, bool lipsShut, double opening = -1) const;
	static long openingStep(const Keypose& key);  // ImageKey::openTo of a keypose
	static constexpr double kOpeningStep = 0.004;
	long mouthLook(long sample, const Points& shape) const;
	std::vector<bool> mouthRegions() const;
	struct NeutralMouths;
	std::unique_ptr<NeutralMouths> mouths_;  // made with the first keypose from action units
	void measureNeutralMouths();             // makes mouths_
};

}  // namespace talkhead
