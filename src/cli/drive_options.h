// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What `track` and `render --drive` share (issue 17): the non-verbal tracking options and the tracking itself.
#include <optional>
#include <string>
#include <vector>

#include "cli/args.h"
#include "model/face_model.h"
#include "perform/plan.h"
#include "track/nonverbal.h"

namespace talkhead::cli {

// --parts LIST, --neutral-frames, --neutral-seconds, --max-turn.
NonVerbalOptions parseNonVerbalOptions(const Args& args, const std::string& command, const std::string& defaultParts);
std::vector<OptionSpec> nonVerbalOptionSpecs();
// Tracks a video (or reads a landmarks.tsv) and analyses it; warnings go to stderr.
// `landmarks`: where to keep the landmark track too (render --drive-mouth).
NonVerbalTrack trackNonVerbal(const std::string& input, const NonVerbalOptions& options, const std::string& dlibModel, bool quiet,
                              LandmarkTrack* landmarks = nullptr);

// render --drive VIDEO [--drive-mouth] (D55): the options checked, the video tracked, what is said of it.
struct Driving {
	std::optional<std::string> video;
	bool mouth = false;          // --drive-mouth: the mouth from the video too
	NonVerbalOptions options;
	std::string model;           // --drive-model
	NonVerbalTrack nv;           // once tracked
	LandmarkTrack landmarks;     // with `mouth`
	Ticks end{0};                // the video's end
	bool hasAudio() const;
	void track(bool quiet);
	std::size_t exemplarChoices = 0;  // with `mouth`
	// --drive-mouth: the keyposes from the driver's mouth (the model actor's exemplars), over the video.
	void mouthKeys(PerformanceSpec& spec, const FaceModel& model, Emotion emotion);
	// A video shorter than the render (a warning); what drove the face (unless quiet).
	void report(const Performance& perf, bool quiet) const;
};
Driving parseDriving(const Args& args, const std::string& command);

}  // namespace talkhead::cli
