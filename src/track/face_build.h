// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A face model from videos of a person (issue 48): each take tracked, its frames chosen by its phones (a
// transcript, or its text aligned to its audio) or by mouth shape, the takes written as one corpus and
// built — what `corpus from-video --takes` and `build` do, as one library call; and the shipped faces
// (model/faces.h) built on first use with it.
#include <optional>
#include <string>
#include <vector>

#include "base/progress.h"
#include "model/face_model.h"
#include "model/faces.h"
#include "track/from_video.h"

namespace talkhead {

// What planning a take found out beside its plan: the alignment's confidence and warnings (text aligned
// to audio), for the caller to print.
struct TakeSpeechNote {
	std::optional<double> alignConfidence;  // set when the take's text was aligned
	std::string alignedAudio;               // the file it was aligned to
	std::vector<std::string> warnings;
};

// One take: its speech (transcript, or text aligned to the video's audio or the take's audio; none when
// byShape), its face tracked (or read from `landmarksTsv` when given) and its frames chosen.
TakePlan planVideoTake(const VideoTake& take, const Language& lang, const FromVideoOptions& options, bool byShape, const std::string& landmarksTsv,
                       ProgressSink& progress, TakeSpeechNote* note = nullptr);

// The take whose frame is the baseface: the first neutral one, else the first.
std::size_t basefaceTake(const std::vector<TakePlan>& plans);

// A shipped face's model, built into the cache on first use (and again when its recipe changed): the
// takes of its list planned as `corpus from-video --takes LIST --lang LANG` plans them (default
// selection), written as one corpus in a scratch folder, built with `build`'s defaults, saved with its
// recipe stamp. Concurrent callers wait for one build (a lock file beside the model). Returns the
// model's path. Throws Error when no cache folder is known or a take cannot be read.
std::string ensureShippedFace(const ShippedFace& face, ProgressSink& progress);

}  // namespace talkhead
