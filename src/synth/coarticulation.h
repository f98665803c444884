// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Issue 32 (decision D62): coarticulation — each keypose's mouth opening predicted from its phone context
// and durations by a sliding-window ridge regression (the idea of Taylor et al. 2017, done linearly),
// learned from real speakers; the face then shows its corpus exemplar nearest that opening.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "geometry/scheme.h"
#include "geometry/shape.h"
#include "model/face_model.h"
#include "phonetics/language.h"

namespace talkhead {

// The regression: weights over coarticulationFeatureNames() and an intercept. Its output is the inner-lip
// opening at a phone's keypose in units of the speaker's own 90th percentile of opening during speech, so
// one model serves every face.
struct CoarticulationModel {
	std::vector<std::string> features;
	Eigen::VectorXd weights;  // one per feature
	double intercept = 0;
	// The mouth's width (corner to corner) the same way, in units of the speaker's median width in speech:
	// rounding spreads to the phones around a rounded vowel.
	Eigen::VectorXd widthWeights;
	double widthIntercept = 0;
	// The lips held before the first words (PauseStyle::Still, Keypose::hold): the real speakers' mean
	// opening and width there, in the same units (D70); unset in a version-1 file (the rest mouth then).
	std::optional<double> leadOpening, leadWidth;
	std::size_t leadClips = 0;  // clips it is the mean of
	// The lips at rest after speech (D107): the real speakers' mean opening and width from kRestAfter after
	// their last words to the clip's end, in the same units. A pause's rest keypose shows the face's own rest
	// mouth drawn no more open than this (chooseMouthExemplars). Unset in files before version 5.
	std::optional<double> restOpening, restWidth;
	std::size_t restClips = 0;
	// /p b m/ shut before their keypose (D71): the real speakers' mean time from a bilabial's keypose (its
	// phone run's midpoint) to their closure (the least opening within 40 ms of the run), seconds, < 0 =
	// earlier; the keypose moves by it. Unset in version-1 and -2 files (the keypose stays at the midpoint).
	std::optional<double> bilabialLead;
	std::size_t bilabialCount = 0;  // closures it is the mean of
	// The visual lead (D104): every keypose of phones timed by talkhead's aligner moved by this (seconds,
	// < 0 = earlier) once the openings are set — the aligner's times come late against the mouth. Measured
	// on rendered pixels against the real speakers (corpus-tools/visual-lead.sh); unset in files before
	// version 4 (the keyposes stay). PerformanceSpec::timing says when it applies.
	std::optional<double> visualLead;
	// D106: the model to plan recognised phones with (PhoneTiming::Recognised), learned from the same clips'
	// recognised phones: a recogniser's phones are not an alignment's (a /b/ heard as /d/ still shuts the
	// lips more often than a true /d/). The shipped model carries its own; null: this model for every timing.
	std::shared_ptr<const CoarticulationModel> recognised;
	double lambda = 0;
	std::size_t samples = 0;  // keyposes it was fitted on
	std::string source;       // what it was learned from
};

// The features, in order: for the keypose's phone run and two phone runs each side (offsets −2 … +2):
// its CDV's opening and width targets (phonetics/cdv-mouth-targets.tsv, ×10), whether it is bilabial,
// labiodental or a pause, and the log of its duration (s); and for offsets −1, 0, +1 one indicator per CDV
// of that table.
const std::vector<std::string>& coarticulationFeatureNames();
// One row of features per phone keypose (not pauses, not the in-breath); `rows` gets each row's keypose index.
Eigen::MatrixXd coarticulationFeatures(const std::vector<PhoneSegment>& phones, const std::vector<Keypose>& keys, std::vector<std::size_t>& rows);
// Whether a keypose is a phone's (the model predicts only those; pauses keep the rest mouth).
bool isPhoneKeypose(const std::vector<PhoneSegment>& phones, const Keypose& key);

// A speaker's clip for learning: its phones and its real inner-lip opening per frame (NaN where lost).
struct CoarticulationClip {
	std::string name;
	std::vector<PhoneSegment> phones;
	std::vector<double> times, openings, widths;  // seconds, any unit (each clip is normalised by its own)
};
// A clip's phone keyposes (at `frame`): their features and the real opening at each, in units of the
// clip's 90th percentile in speech. Throws Error (naming the clip) when its face is lost or its lips never part.
// `y` has two columns: the opening and the width (in units of the clip's median width in speech).
void coarticulationExamples(const CoarticulationClip& clip, Ticks frame, Eigen::MatrixXd& X, Eigen::MatrixXd& y);
// Ridge least squares (intercept unpenalised) over the examples of several clips.
CoarticulationModel fitCoarticulation(const std::vector<Eigen::MatrixXd>& X, const std::vector<Eigen::MatrixXd>& y, double lambda);
// A clip's mean opening and width before its first words, up to kStillLead before them (its units as
// coarticulationExamples'); nullopt when it has no speech or no frame there.
std::optional<std::pair<double, double>> leadingPauseMouth(const CoarticulationClip& clip);
// Sets the model's lead (the mean of its clips' leadingPauseMouth; left unset when none has one).
void learnLeadingPause(CoarticulationModel& m, const std::vector<CoarticulationClip>& clips);
// A clip's mean opening and width from kRestAfter after its last words to its end (units as above); nullopt
// when it has no speech or no frame there (D107).
std::optional<std::pair<double, double>> trailingPauseMouth(const CoarticulationClip& clip);
// Sets the model's rest (the mean of its clips' trailingPauseMouth; left unset when none has one).
void learnTrailingPause(CoarticulationModel& m, const std::vector<CoarticulationClip>& clips);
// Each bilabial keypose's time to the clip's real closure (seconds; closures more than 0.1 s away, another
// phone's, left out).
std::vector<double> bilabialClosureOffsets(const CoarticulationClip& clip, Ticks frame);
// Sets the model's bilabialLead (the mean of its clips' offsets; left unset when none has a bilabial).
void learnBilabialLead(CoarticulationModel& m, const std::vector<CoarticulationClip>& clips, Ticks frame);
// Moves each bilabial phone keypose by the model's bilabialLead, kept at least a frame from the keyposes
// either side (unmoved when there is no room); nothing without a lead.
void applyBilabialLead(const CoarticulationModel& m, const std::vector<PhoneSegment>& phones, std::vector<Keypose>& keys, Ticks frame);
// Holds each /p b m/ phone keypose shut for a frame (D90): two copies, half a frame before and after it, where
// both stay at least half a frame from the keyposes either side — so a video frame, wherever it falls, shows
// the lips shut (the curve passes a single shut keypose between two frames). Real lips stay shut 60–100 ms.
void holdBilabials(const std::vector<PhoneSegment>& phones, std::vector<Keypose>& keys, Ticks frame);
// Moves every keypose by the model's visualLead (none without one), keeping the gaps between them: a keypose
// the lead would take before 0 stays at 0, and those after it keep at least their gap to it, up to a frame.
inline constexpr double kMaxVisualLead = 0.2;  // seconds either way: what a file may say
void applyVisualLead(const CoarticulationModel& m, std::vector<Keypose>& keys, Ticks frame);
CoarticulationModel trainCoarticulation(const std::vector<CoarticulationClip>& clips, Ticks frame, double lambda = 10);

// Sets each phone keypose's mouthOpening and mouthWidth from the model (keys made from these phones), the
// held keyposes' before the first words (Keypose::hold) from its lead, and a pause's rest keyposes (silence,
// neither held nor the in-breath) from its rest (D107).
void predictMouthOpenings(const CoarticulationModel& m, const std::vector<PhoneSegment>& phones, std::vector<Keypose>& keys);

// Text file "talkhead-coarticulation 5" (the rest line; the visual line optional), 4 (the visual line, no rest),
// 3 (without the visual line; 2: without the bilabial line either; 1: without the lead line either) — written as
// 5 when the model has a rest, else 4 or 3; reading checks every line and the features, naming the file.
void saveCoarticulation(const CoarticulationModel& m, const std::string& path);
CoarticulationModel loadCoarticulation(const std::string& path);

// The model that ships with talkhead (issue 48, D90): models/coarticulation/grid.tsv in the data folders,
// learned from 95 GRID clips of 6 speakers (CC BY 4.0: NOTICE; corpus-tools/coarticulation-grid.sh
// rebuilds it), with its companion for recognised phones (D106: grid-recognised.tsv, learned from the same
// clips' recognised phones; `--recognised` rebuilds it). Read once, on first use, and shared; Error when
// no data folder has them.
inline constexpr const char* kShippedCoarticulation = "models/coarticulation/grid.tsv";
inline constexpr const char* kShippedRecognisedCoarticulation = "models/coarticulation/grid-recognised.tsv";
std::shared_ptr<const CoarticulationModel> shippedCoarticulation();
// What a `coarticulation` option names: "on" (the shipped model), "off" (none: the thesis's path, one
// target per phone) or a model file's path.
std::shared_ptr<const CoarticulationModel> coarticulationOption(const std::string& value);

// The inner-lip opening and mouth width of a shape in eye distances (between the eyes' centres; the
// scheme needs two eyes and a mouth line).
// `lift`: the corners' height above the inner lips' centre line (up > 0): a smile lifts it (D72).
struct MouthSize {
	double opening = 0, width = 0, lift = 0;
};
MouthSize mouthSize(const Scheme& scheme, const Points& shape);
// A bilabial's closure drawn shut (D99): each inner-lip pair apart along the face's vertical meets at its
// middle, so the warp takes the gap an exemplar caught mid-closure shows out of the picture. Pairs already
// together or crossed are left as they are.
void shutLips(const Scheme& scheme, Points& shape);
// A predicted opening drawn on the exemplar chosen for it (D100): each inner-lip pair's gap along the face's
// vertical scaled so the mean opening is `opening` (eye distances); the lower lip, the chin and the jaw below
// the mouth move with the lower inner lip nearest them across the face (nothing beyond the corners, fading out
// between 1.5 and 2.5 eye distances below the mouth), the upper lip and the corners stay. A warp can close a
// mouth and open one a little wider, not show an inside a sample lacks: the opening is at most kMaxLipStretch
// × the exemplar's, and a mouth under kMinStretchOpening eye distances is not opened.
inline constexpr double kMaxLipStretch = 1.5, kMinStretchOpening = 0.03;
void drawOpening(const Scheme& scheme, Points& shape, double opening);
// The frame those are measured in: the eye distance (between the eyes' centres; 0 when degenerate), the
// unit vectors along the eye line toward the image-right eye and down the face, and the inner lips' centre.
struct MouthFrame {
	double iod = 0;
	Eigen::RowVector2d across{1, 0}, down{0, 1}, centre{0, 0};
};
MouthFrame mouthFrame(const Scheme& scheme, const Points& shape);
// The model's scheme when it has two eyes and a mouth line; false if not.
bool mouthScheme(const FaceModel& model, Scheme& out);

// The mouths of a model's samples (mouthSize of each aligned shape).
std::vector<MouthSize> sampleMouths(const FaceModel& model, const Scheme& scheme);
// One emotion's samples and this face's measures of them (silences left out): the 90th percentile of the
// openings (the scale), the median width and the spread of widths, and the limit of a shut mouth (10 % of
// the open range above the most closed).
struct MouthPool {
	std::vector<std::size_t> samples;
	double scale = 0, width = 0, widthSpread = 0, closedLimit = 0;
	// The face's usual width at an opening (least squares over the same samples, eye distances): a face
	// whose open mouths are wide is judged against its own open mouths, not its median (D90).
	double widthAtShut = 0, widthPerOpening = 0;
	double widest = 0;  // the widest opening (the unit of a predicted opening, D90)
	double usualWidth(double opening) const { return widthAtShut + widthPerOpening * opening; }
};
MouthPool mouthPool(const FaceModel& model, const std::vector<MouthSize>& size, const std::string& emotion);
// The GRID speakers' 90th percentile of the inner-lip opening in speech, eye distances (median over the 95
// clips the shipped model learned from; the speakers' own medians 0.10–0.18): the most a face's unit may be
// (D105). A face whose widest sample is a posed extreme (the synthetic face's drawn /a/ opens 0.29; a take
// with the mouth wide open, as `face create` advises) would otherwise speak with that extreme as its norm.
inline constexpr double kSpeakersOpening = 0.148;
// The unit of a predicted opening on a face, eye distances: the pool's widest × 0.87 (the speakers' 90th
// percentile over their widest, D90), scaled down as much as the face's neutral pool needs to stay within
// kSpeakersOpening — an emotion keeps its mouth's size against the face's neutral one.
double openingUnit(const MouthPool& pool, const MouthPool& neutral);
// The pool's sample (silences left out) whose mouth is nearest (opening, width), eye distances:
// (Δopening / scale)² + 0.15 (Δwidth / spread)² (D62); `prefer` (≥ 0) is kept unless another is strictly
// nearer. −1 when the pool has none.
long nearestMouth(const FaceModel& model, const MouthPool& pool, const std::vector<MouthSize>& size, double opening, double width, long prefer = -1);

// For every keypose with a mouthOpening and no sample yet, the model's exemplar to show (Keypose::sample):
// a pause's rest keypose (a silence CDV, neither held nor the in-breath) keeps the emotion's own rest sample,
// drawn less open by what the face's neutral rest opens beyond the predicted opening (D107: a face whose rest
// was caught with the lips apart closes them as speakers do after speaking, and an emotion's rest keeps what
// the expression adds; a shut neutral rest leaves every rest as it is); otherwise
// among the samples of its emotion (else neutral's), the one whose opening and width are nearest the
// targets (scaled to this face's own 90th percentile of opening and median width); a bilabial closes
// (its CDV's sample when that is shut, else the most closed bilabial exemplar, else the most closed one).
// A CDV the emotion has no sample of (a face from short takes) is chosen the same way from the whole pool.
// A keypose left without an exemplar (a pool with no mouth to choose) loses its prediction and keeps the
// synthesizer's fallbacks. Returns the number of keyposes given an exemplar; 0 when the scheme cannot
// measure the mouth.
std::size_t chooseMouthExemplars(const FaceModel& model, const Emotion& emotion, std::vector<Keypose>& keys);

}  // namespace talkhead
