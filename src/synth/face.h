// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "model/face_model.h"
#include "synth/action_units.h"
#include "synth/au_appearance.h"
#include "synth/coarticulation.h"

namespace talkhead {

// A face (issue 46): the model with the parts that are drawn with it — its scheme's action-unit templates
// (D48), the action units' skin (D61), the closed-eye composite of its blink sample (D50) and the
// coarticulation model that chooses its mouths (D62) — each loaded or made once, on first use, and shared
// read-only by every synthesizer that draws the face (a render; each live session of a server). Thread-safe.
// The model must outlive the face.
class Face {
public:
	explicit Face(const FaceModel& model, std::shared_ptr<const CoarticulationModel> coarticulation = {});
	Face(const Face&) = delete;
	Face& operator=(const Face&) = delete;

	const FaceModel& model() const { return model_; }
	// D62: predicts each phone's mouth opening from its context; null: the thesis's one sample per CDV.
	const std::shared_ptr<const CoarticulationModel>& coarticulation() const { return coarticulation_; }
	// D48: the scheme's action-unit templates (models/au-templates/<scheme>.tsv in the data folders), read
	// on first use; null when none are installed. Throws Error for a malformed file.
	const AuTemplates* auTemplates() const;
	// D61: the skin of the action units `aus` (models/au-appearance.bin), mapped into the box (x0, y0,
	// width × height) of the model frame over its mean shape; nullopt when none is installed, it has none
	// of them, or the scheme has not two eyes and two brows.
	// ownSkin: a face other than the maps' own keeps its skin (D85, mapAuAppearance).
	std::optional<MappedAuAppearance> auSkin(const std::vector<std::string>& aus, int x0, int y0, int width, int height, bool ownSkin = true) const;
	// D50: the model's closed-eyes sample composited in the model frame (RGB); empty when it has none.
	const Image8& closedEyes() const;

private:
	const FaceModel& model_;
	std::shared_ptr<const CoarticulationModel> coarticulation_;
	mutable std::once_flag templatesOnce_, closedOnce_;
	mutable std::optional<AuTemplates> templates_;
	mutable Image8 closed_;
};

}  // namespace talkhead
