// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <functional>
#include <string>

#include "image/image.h"
#include "model/face_model.h"

namespace talkhead {

// Pictures of a face model for people to look at (talkhead inspect -o DIR).

// The baseface with the frame mesh (grey), the face mesh (green), region boundaries and points drawn.
Image8 drawBasefaceMesh(const FaceModel& model);
// Thesis Fig. 4.8: the first `modes` modes of one region at −2σ / mean / +2σ (appearance and shape),
// one row per mode, cropped to the face.
Image8 drawRegionModes(const FaceModel& model, int region, int modes = 3);
// Thesis Fig. 4.7: cumulative explained variance per region, with the 80 % and 90 % points marked.
Image8 drawVarianceCurves(const FaceModel& model);
// Every training sample's (emotion, CDV) keypose reconstructed from the model, as a labelled grid.
// label gives each thumbnail's caption (ASCII: the font has no IPA); default "emotion cdv".
Image8 drawContactSheet(const FaceModel& model, int thumbWidth = 160,
                        const std::function<std::string(const SampleInfo&)>& label = {});

}  // namespace talkhead
