// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A viseme corpus from a video (issue 10 §3): for each phone, or for each CDV by mouth shape, the frame
// that represents it, with its tracked 68 points, written in the project's CSV format (ibug-68).
#include <array>
#include <optional>
#include <cstdint>
#include <string>
#include <vector>

#include "phonetics/emotion.h"
#include "phonetics/language.h"
#include "track/landmarks.h"

namespace talkhead {

// Four articulatory measures of a mouth in eye distances (outer eye corners), the eye line horizontal:
// inner-lip gap (mean of the three inner pairs), mouth-corner distance, outer lip height at the midline,
// and jaw opening (subnasale to chin).
struct MouthMeasures {
	double opening = 0, width = 0, height = 0, jaw = 0;
	double operator[](int i) const { return i == 0 ? opening : i == 1 ? width : i == 2 ? height : jaw; }
	double& operator[](int i) { return i == 0 ? opening : i == 1 ? width : i == 2 ? height : jaw; }
};
MouthMeasures mouthMeasures(const Points& ibug68);
// The q-quantile (0–1) of the values, interpolated linearly; 0 when there are none.
double percentile(std::vector<double> values, double q);

// Head pose proxies of a 68-point shape: roll (radians, the eye line's angle) and yaw (nose tip's horizontal
// offset from the eyes' midpoint, in eye distances).
double headRoll(const Points& ibug68);
double headYaw(const Points& ibug68);
// The eye's aspect (lid gap over corner distance) of a 68-point shape, both eyes' mean; NaN if degenerate.
double eyeAspect(const Points& ibug68);
// The mouth corners' height above the inner lips' centre (up > 0), eye distances: a smile lifts it (D73).
double cornerLift(const Points& ibug68);
// A person's usual corner lift at each mouth opening (D73): the median lift of the frames whose opening is
// among the nearest (the larger of 25 frames and 5 % of them), so a frame can be told a smile caught in a
// pause from the way this person's corners always move with the jaw.
class UsualLift {
public:
	UsualLift(std::vector<double> openings, std::vector<double> lifts);
	double at(double opening) const;
	double spread() const { return spread_; }  // half the 5th–95th percentile range of lift − at(opening) (≥ 1e-4)

private:
	std::vector<std::pair<double, double>> byOpening_;  // (opening, lift), sorted
	double spread_ = 1e-4;
};

// The mouth points (48–67) centred, derotated by the eye line and scaled by the eye distance.
Points normalisedMouth(const Points& ibug68);

// Each CDV's mouth target relative to the rest shape (phonetics/cdv-mouth-targets.tsv: the synthetic face's
// neutral CDV shapes, in eye distances).
struct CdvMouthTarget {
	std::string cdv;
	MouthMeasures delta;
};
std::vector<CdvMouthTarget> loadCdvMouthTargets(const std::string& path = "");

struct FromVideoOptions {
	std::string emotion = Emotion::neutralLabel();   // CH-Unicamp label of every entry
	int perCdv = 1;                     // frames kept per (emotion, CDV)
	std::int64_t baseface = -1;         // frame index of the baseface; −1 = the most neutral frame found
	double minConfidence = 0.6;         // tracked frames less consistent than this are not chosen
	double maxRollDegrees = 12;         // nor frames with the head this tilted
	double maxYaw = 0.12;               // or turned (nose offset in eye distances)
	double duplicateFraction = 0.05;    // Braun: mouths closer than this × the mouth-corner distance are redundant
	// D71: nor frames whose eyes are less open than this × the track's median (a blink or a lid on its
	// way down: a still mouth in a pause is where people blink, so a still-frame preference chose them).
	double minEyeOpening = 0.7;
	// Issue 47: the person's own shut eyes for blinks — a frame whose eyes are open at most this × the
	// track's median (closedEyesFrame); 0: none kept (blinks draw the lid, D42).
	double maxShutEyes = 0.4;
};

// A chosen frame and its labels.
struct ChosenFrame {
	std::int64_t frame = 0;
	Ticks time{0};
	std::string emotion, cdv, word;
	std::array<std::string, 5> context{"_", "_", "_", "_", "_"};
	Points points;        // 68 × 2, pixels
	double cost = 0;      // how far from the target (select by shape) or 0
	std::string phone;    // select by phones: the phone (IPA)
};

struct VideoCorpusPlan {
	std::vector<ChosenFrame> entries;     // sorted by CDV order of phonetics/visemes.tsv, then cost
	std::int64_t basefaceFrame = -1;      // also one of the entries (labelled sil when chosen by shape)
	std::string method;                   // "shape" or "phones"
	std::vector<std::string> missing;     // CDVs with no frame (phones: CDVs the speech never used)
	MouthMeasures rest, scale;            // select by shape: the speaker's rest measures and target scale
	// Issue 47: a frame with the person's eyes shut (closedEyesFrame), written as the corpus's unlabelled
	// `# closed-eyes:` row, so that blinks take the person's own lids (D50); none when the video has none.
	std::optional<ChosenFrame> closedEyes;
};

// The frame a blink of this person is drawn from (issue 47): the eyes shut (open at most
// options.maxShutEyes × the track's median), the head frontal and turned as in `basefaceFrame`, the mouth
// at rest and still, the face tracked confidently; the most shut of those that qualify. nullopt when no
// frame does (a video without a blink, or blinks only with the head turned or the mouth moving).
std::optional<ChosenFrame> closedEyesFrame(const LandmarkTrack& track, std::int64_t basefaceFrame, const FromVideoOptions& options);

// The most neutral frame: lips closed and relaxed (opening near its 5th percentile, width and jaw near
// their medians), the head frontal and still.
std::int64_t mostNeutralFrame(const LandmarkTrack& track, const FromVideoOptions& options);

// Without audio: for each CDV of phonetics/cdv-mouth-targets.tsv the frames whose mouth measures best match
// the target, scaled to this speaker (rest = the baseface's measures; each measure's target offsets scaled
// by the ratio of the speaker's 2–98 % range to the targets' range). Near-duplicates are dropped.
VideoCorpusPlan selectByShape(const LandmarkTrack& track, const std::vector<CdvMouthTarget>& targets, const FromVideoOptions& options);

// With timed phones (and optionally words): for each phone the frame at the articulators' inflection
// point — the extremum of the lip opening (or, when the opening is flat, of the width) inside the phone's
// interval; the frame nearest the midpoint when there is none. Up to perCdv per (emotion, CDV), the most
// typical of each CDV first. Pauses give `sil` frames.
VideoCorpusPlan selectByPhones(const LandmarkTrack& track, const std::vector<PhoneSegment>& phones, const std::vector<Interval>& words,
                               const FromVideoOptions& options);

// Writes the corpus: frames/frame_NNNNNN.png (decoded again from the video), corpus.csv (CH-Unicamp CSV with
// 68 points, "# baseface:" naming the baseface's image) and contact.png (the chosen mouths per CDV).
void writeVideoCorpus(const std::string& video, const LandmarkTrack& track, const VideoCorpusPlan& plan, const std::string& dir);

// Issue 31, route 1: several takes of one person, each in one emotion, make one corpus (the thesis's way:
// a model of every recorded emotion).
struct VideoTake {
	std::string video;
	std::string emotion = Emotion::neutralLabel();  // canonical label
	Ticks start{0}, duration{0};      // the part of the video used (duration 0: to its end)
	std::string transcript, text, audio;  // its speech: a timed transcript, or words to align to the audio
	                                      // (the video's own, or `audio`); neither: frames chosen by shape
	std::string where;                // for messages: "takes.tsv:3" or "{{take}} VIDEO:EMOTION"
};
// "VIDEO:EMOTION" (split at the last colon; an emotion label or alias). Throws Error saying what is wrong.
VideoTake parseTakeSpec(const std::string& spec);
// A take list: TSV with a header; columns video and emotion, and optionally start and duration (seconds),
// transcript, text and audio. Relative paths are relative to the list's folder. Every take's video (and
// transcript, audio) must exist. Throws Error("LIST:LINE: …").
std::vector<VideoTake> readTakeList(const std::string& path);

// One take's tracked face and chosen frames.
struct TakePlan {
	VideoTake take;
	LandmarkTrack track;
	VideoCorpusPlan plan;
};
// A colour map per channel (R, G, B): out = gain × in + offset; writeTakesCorpus's, per take, with the range of its
// frames' gains (the take's times each frame's own).
struct ColourMatch {
	double gain[3] = {1, 1, 1}, offset[3] = {0, 0, 0};
	double low[3] = {1, 1, 1}, high[3] = {1, 1, 1};
	bool identity() const;
};
// Writes one corpus of the takes (as writeVideoCorpus; every take's frames the same size) whose baseface is
// takes[baseTake]'s. With more than one take, images are frames/takeK_frame_NNNNNN.png. Colours (D73): each
// chosen frame's gain per channel brings the mean of its face (inside its landmarks' hull, without the mouth
// and the eyes) to its take's median, so lighting that drifted within a recording does not flicker between
// exemplars; then each take's map (mean and spread over its faces) brings it to the base take's (D61), so
// lighting that drifted between recordings does not flash at an emotion change. Gains kept within
// 0.8–1.25. Returns each take's map, with the range of its frames' gains.
// `pngCompression` (0–9) only trades the images' size for the time to write them: a scratch corpus read once
// is written at 1.
std::vector<ColourMatch> writeTakesCorpus(const std::vector<TakePlan>& takes, std::size_t baseTake, const std::string& dir, int pngCompression = 6);

}  // namespace talkhead
