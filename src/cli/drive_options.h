// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What `track` and `render --drive` share (issue 17): the non-verbal tracking options and the tracking itself.
#include <string>
#include <vector>

#include "cli/args.h"
#include "perform/controls.h"
#include "track/nonverbal.h"

namespace talkhead::cli {

// --parts LIST, --neutral-frames, --neutral-seconds, --max-turn.
NonVerbalOptions parseNonVerbalOptions(const Args& args, const std::string& command, const std::string& defaultParts);
std::vector<OptionSpec> nonVerbalOptionSpecs();
// Tracks a video (or reads a landmarks.tsv) and analyses it; warnings go to stderr.
// `landmarks`: where to keep the landmark track too (render --drive-mouth).
NonVerbalTrack trackNonVerbal(const std::string& input, const NonVerbalOptions& options, const std::string& dlibModel, bool quiet,
                              LandmarkTrack* landmarks = nullptr);

}  // namespace talkhead::cli
