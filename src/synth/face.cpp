// SPDX-License-Identifier: GPL-3.0-or-later
#include "synth/face.h"

#include <Eigen/Core>

namespace talkhead {

Face::Face(const FaceModel& model, std::shared_ptr<const CoarticulationModel> coarticulation)
    : model_(model), coarticulation_(std::move(coarticulation)) {}

const AuTemplates* Face::auTemplates() const {
	std::call_once(templatesOnce_, [&] { templates_ = findAuTemplates(model_.scheme); });  // a throw: tried again next time
	return templates_ ? &*templates_ : nullptr;
}

std::optional<MappedAuAppearance> Face::auSkin(const std::vector<std::string>& aus, int x0, int y0, int width, int height, bool ownSkin) const {
	const Scheme& scheme = model_.scheme;  // a loaded model's eyes and brows are its shipped scheme's (completeSchemeParts)
	if (scheme.eyes.size() != 2 || scheme.brows.size() != 2 || aus.empty()) return std::nullopt;
	const std::optional<AuAppearance> a = installedAuAppearance(aus);
	if (!a || a->names.empty()) return std::nullopt;
	return mapAuAppearance(*a, scheme, model_.meanShape, x0, y0, width, height, nullptr, ownSkin ? &model_.baseface : nullptr);
}

const Image8& Face::closedEyes() const {
	std::call_once(closedOnce_, [&] {
		const FaceModel& model = model_;
		if (model.closedEyesIndex < 0 || std::size_t(model.closedEyesIndex) >= model.sampleCount()) return;
		std::vector<Eigen::VectorXf> a(model.regions.size());
		for (std::size_t r = 0; r < model.regions.size(); ++r) {
			const RegionModel& reg = model.regions[r];
			if (reg.hasAppearanceCache()) {
				a[r] = reg.cachedAppearance(std::size_t(model.closedEyesIndex));
			} else {
				Eigen::MatrixXf c(reg.pca.components(), 1);
				c.col(0) = sampleCoefficients(reg, std::size_t(model.closedEyesIndex));
				a[r] = synthesizeAppearances(reg, c).col(0);
			}
		}
		closed_ = toU8(compositeRegions(model, a));
	});
	return closed_;
}

}  // namespace talkhead
