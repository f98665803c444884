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
                       ProgressSink& progress, TakeSpeechNote* note = nullptr, const FrameCallback& onFrame = {},
                       FaceLandmarker* landmarker = nullptr);

// The take whose frame is the baseface: the first neutral one, else the first.
std::size_t basefaceTake(const std::vector<TakePlan>& plans);

// A shipped face's model, built into the cache on first use (and again when its recipe changed): the
// takes of its list planned as `corpus from-video --takes LIST --lang LANG` plans them (default
// selection), written as one corpus in a scratch folder, built with `build`'s defaults, saved with its
// recipe stamp. Concurrent callers wait for one build (a lock file beside the model). Returns the
// model's path. Throws Error when no cache folder is known or a take cannot be read.
std::string ensureShippedFace(const ShippedFace& face, ProgressSink& progress);

// Issue 48 part 3: your own face from videos, in one call.
// How a frame's face looks: its mean luma (0–255) and its fine detail — the RMS of the Laplacian of its grey
// levels at a fixed scale (64 px between the outer eye corners), over the face's outline.
struct FaceLook {
	double luma = 0, detail = 0;
};
FaceLook faceLook(const Image8& rgb, const Points& ibug68);

// One take's frames as material for a face, and why frames cannot be used.
struct TakeCensus {
	std::string video;
	double seconds = 0, faceSeconds = 0;  // of video read; with a face found
	std::size_t seen = 0, found = 0;      // frames read, frames with a face
	// Of the frames with a face (as the selection refuses them, FromVideoOptions): tracked without
	// confidence, the head turned or tilted, the eyes shut or closing, corners lifted by a smile the moment
	// brought (more than 2 spreads above the person's usual lift at that opening, D73); usable: none of these.
	std::size_t lowConfidence = 0, turned = 0, blinks = 0, smiles = 0, usable = 0;
	std::size_t detections = 0, severalFaces = 0;  // detector runs, and those that found more than one face
	double brightness = 0, brightnessDrift = 0;    // median face luma; its p5–p95 spread over the median
	double detail = 0;                             // median FaceLook::detail
	double openingRange = 0;                       // p95 − p5 of the inner-lip opening, eye distances
};
TakeCensus takeCensus(const LandmarkTrack& track, const std::vector<FaceLook>& looks, const FromVideoOptions& options);

// The thresholds below which a video is refused, decided from real clips (D92).
struct FaceCreateLimits {
	double minFaceSeconds = 1.2;      // too short: a take
	double minTotalFaceSeconds = 3.0; // too short: all takes together
	double maxSeveralFaces = 0.5;     // share of detections with more than one face
	double maxTurned = 0.5;           // share of found frames with the head turned or tilted
	double minBrightness = 40;        // too dark
	double minDetail = 2.8;           // too blurred
	std::size_t minCdvs = 8;          // too few visemes covered
};
// One line saying why the take cannot make a face (naming the video), or nullopt.
std::optional<std::string> takeRefusal(const TakeCensus& census, const FaceCreateLimits& limits = {});

struct FaceCreateOptions {
	std::string lang = "en-US";       // the speech's language (takes with a transcript or text)
	FromVideoOptions selection;
	FaceCreateLimits limits;
};
struct FaceCreateReport {
	std::vector<TakeCensus> takes;
	std::vector<std::string> methods;                  // per take: "phones" or "shape"
	std::vector<std::string> emotions;                 // per take
	std::vector<ColourMatch> colours;                  // per take, to the base take's
	std::size_t baseTake = 0;
	std::vector<std::pair<std::string, int>> cdvFrames;  // each CDV kept, with its frames (visemes.tsv order)
	std::vector<std::string> missing;                  // CDVs no take gave a frame
	std::size_t samples = 0;                           // the model's images
	bool ownBlink = false;                             // a frame with the eyes shut was kept for blinks
	std::vector<std::string> advice;                   // what would make the face better, one sentence each
};
// Tracks each take (its face's look measured on the way), refuses a take that cannot make a face
// (Error: the refusal's line; nothing written), chooses frames by phones (a take with a transcript or
// text) or by mouth shape, writes one corpus in a scratch folder beside `modelPath`, builds and saves the
// model there. Progress: tracking is most of it.
FaceCreateReport createFace(const std::vector<VideoTake>& takes, const FaceCreateOptions& options, const std::string& modelPath, ProgressSink& progress);

}  // namespace talkhead
