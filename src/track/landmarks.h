// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Face landmarks from images and video (issue 10 §1): dlib's face detector and 68-point predictor
// (ibug-68 order) through the dlib plugin, tracking from frame to frame, and one-euro smoothing.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "base/progress.h"
#include "base/ticks.h"
#include "geometry/shape.h"
#include "image/image.h"
#include "media/video_reader.h"
#include "track/dlib_module.h"

namespace talkhead {

constexpr int kIbugPoints = 68;

// dlib's model: $TALKHEAD_DLIB_MODEL, else /usr/share/dlib/shape_predictor_68_face_landmarks.dat.
std::string defaultDlibModelPath();

// Detector + predictor (the dlib plugin, loaded on first use). Not thread-safe: one per thread.
class FaceLandmarker {
public:
	explicit FaceLandmarker(const std::string& modelPath = defaultDlibModelPath());
	~FaceLandmarker();
	FaceLandmarker(const FaceLandmarker&) = delete;
	FaceLandmarker& operator=(const FaceLandmarker&) = delete;

	// Faces in a grey image (best first). upsample: 0 = as is, 1 = twice the size (finds faces ≥ 40 px).
	std::vector<FaceBox> detect(const Image8& grey, int upsample = 0);
	// 68 points inside `box`. The face is cropped and scaled so that the box is 240 px wide before the
	// predictor runs (its points are integers in the image it sees), so small faces get sub-pixel points.
	Points fit(const Image8& grey, const FaceBox& box);

private:
	void* handle_ = nullptr;
	Image8 crop_;
};

// RGB → grey (BT.601 luma).
Image8 toGrey(const Image8& rgb);

// The one-euro filter (Casiez, Roussel & Vogel, CHI 2012) on one value: a low-pass filter whose cutoff
// rises with the value's speed, so slow jitter is removed and fast motion is followed without lag.
class OneEuroFilter {
public:
	OneEuroFilter(double minCutoffHz = 1.0, double beta = 0.0, double derivativeCutoffHz = 1.0)
	    : minCutoff_(minCutoffHz), beta_(beta), dCutoff_(derivativeCutoffHz) {}
	double operator()(double x, double dtSeconds);
	void reset() { started_ = false; }

private:
	double minCutoff_, beta_, dCutoff_;
	bool started_ = false;
	double x_ = 0, dx_ = 0;
};

struct SmoothingOptions {
	bool enabled = true;
	// Speeds are measured in eye distances per second, so the same settings suit any face size.
	// Rigid and slow points (outline, brows, nose, eyes): cutoff at rest, removing the predictor's jitter,
	// and how fast the cutoff rises with speed.
	double minCutoffHz = 1.5;
	double beta = 4.0;
	// The lips (48–67) move fast in speech: a higher cutoff and a steeper rise keep their lag to a few ms.
	double mouthMinCutoffHz = 3.0;
	double mouthBeta = 40.0;
	double derivativeCutoffHz = 2.0;
};

struct TrackOptions {
	int every = 1;                   // keep every Nth frame (1 = all)
	Ticks start{0};                  // first frame time
	Ticks duration{-1};              // −1 = to the end
	double redetectSeconds = 2.0;    // run the detector again this often while tracking
	double minConfidence = 0.5;      // a fit less consistent than this re-detects (and is lost if none)
	SmoothingOptions smoothing;
	std::string modelPath = defaultDlibModelPath();
	// A model already loaded (used by one thread at a time), so that tracking several videos loads dlib's
	// 100-MB predictor once; null: `modelPath` is loaded for the call.
	FaceLandmarker* landmarker = nullptr;
};

// One frame's landmarks.
struct FrameLandmarks {
	std::int64_t frame = 0;  // 0-based frame index in the video (or image index in a folder)
	Ticks time{0};
	bool found = false;      // false: the face was lost in this frame (no points)
	bool detected = false;   // the detector ran and found the face in this frame
	double confidence = 0;   // 0–1: agreement of two predictor fits from slightly different boxes
	int faces = -1;          // faces the detector found when it ran on this frame (−1: it did not run)
	Points points;           // 68 × 2 (smoothed when smoothing is on), pixels; empty when !found
	Points raw;              // the unsmoothed fit
	std::string name;        // folder input: the image's file name
};

struct LandmarkTrack {
	std::string source;
	VideoInfo info;
	std::vector<FrameLandmarks> frames;
	std::size_t foundCount() const;
};

// Called for each kept frame with its RGB pixels (e.g. to keep thumbnails or write the frame).
using FrameCallback = std::function<void(const FrameLandmarks&, const Image8& rgb)>;

// Tracks the face through a video: detect, then fit from the previous frame's points, re-detecting every
// redetectSeconds or when a fit is inconsistent; lost frames are marked, never invented. Throws Error
// naming the file when no frame has a face.
LandmarkTrack trackVideo(const std::string& path, const TrackOptions& options, ProgressSink& progress, const FrameCallback& onFrame = {});

// Landmarks of every image in a folder (sorted by name; .jpg .jpeg .png .bmp .tif .tiff), or of one image.
LandmarkTrack landmarkImages(const std::string& path, const TrackOptions& options, ProgressSink& progress, const FrameCallback& onFrame = {});

// A video or an image folder/file, by what `path` is.
LandmarkTrack landmarkInput(const std::string& path, const TrackOptions& options, ProgressSink& progress, const FrameCallback& onFrame = {});

// iBUG .pts (version 1, 1-based pixel coordinates, 3 decimals): the text, and a file written atomically.
std::string ptsText(const Points& points);
void writePts(const std::string& path, const Points& points);

// landmarks.tsv (corpus/landmarks_tsv.h, the one dialect): a header, then one row per frame: frame, time
// (s), status (detected|tracked|lost), confidence, and x y of the 68 iBUG points named as ibug-68.scheme
// names them (JAW0_x JAW0_y … IM7_y; empty for lost frames). The reader takes that, the older x0 y0 …
// columns, and a render's --landmarks-out of an ibug-68 face.
std::string landmarksTsv(const LandmarkTrack& track);
LandmarkTrack readLandmarksTsv(const std::string& path);

// Measures of a track (issue 10 §1's report): mean frame-to-frame acceleration of the rigid points (eye
// corners, nose) in eye distances, and the inner-lip opening per frame (MouthMeasures::opening, in eye
// distances; NaN when lost).
double rigidJitter(const LandmarkTrack& track, bool raw);
std::vector<double> innerLipOpening(const LandmarkTrack& track, bool raw);
// A frame's unsmoothed fit (its smoothed points when the track has no raw ones, e.g. read from a .tsv).
const Points& unsmoothedPoints(const FrameLandmarks& f);
// Outer eye-corner distance (points 36, 45).
double eyeDistance(const Points& p);

// Writes a contact sheet: up to `count` frames sampled evenly, the points drawn, lost frames marked.
struct Thumbnail {
	FrameLandmarks landmarks;
	Image8 image;  // the frame (RGB)
};
Image8 contactSheet(const std::vector<Thumbnail>& thumbs, int columns = 6, int cellWidth = 240);

// Draws 68 points (and their contours) onto an RGB image.
void drawLandmarks(Image8& rgb, const Points& points, bool ok = true);

}  // namespace talkhead
