// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

#include "base/ticks.h"
#include "perform/performance.h"

namespace talkhead {

// Timed controls (issue 13 §4; decision D44): a JSON control track of events that change the emotion
// mid-utterance, force blinks, and nod or shake the head. The schema (README "Timed controls"):
//   {"events": [
//     {"type": "emotion", "time": 1.2, "emotion": "anger", "intensity": 0.8, "ramp": 0.4},
//     {"type": "blink", "time": 2.0},
//     {"type": "nod", "time": 3.0, "duration": 0.6, "amount": 1},
//     {"type": "shake", "time": 4.0, "duration": 0.8, "amount": 0.5},
//     {"type": "turn", "time": 4.5, "duration": 1.5, "direction": "left", "amount": 1},
//     {"type": "brows", "time": 5.0, "duration": 0.8, "raise": 0.8},   (or "frown": 0.5)
//     {"type": "au", "time": 6.0, "au": "AU12", "intensity": 0.7, "side": "left", "onset": 0.2, "apex": 0.5, "offset": 0.3}],
//    "drawn_blinks": false,                     (optional: the events' blinks are all; default true)
//    "curves": {"rate": 25, "start": 0,          (optional, D55: sampled controls, e.g. from talkhead track)
//      "head": {"roll": [deg…], "x": [IOD…], "y": [IOD…], "scale": […], "yaw": [deg…] (informational)},
//      "au": [{"au": "AU1", "side": "right", "weight": […]}, …]}}
// Times in seconds from the start of the video. A bare array of events is read the same way.
struct ControlTrack {
	struct EmotionChange {
		Ticks time{0}, ramp{0};
		Expression expression;
	};
	std::string path;  // for messages
	std::vector<EmotionChange> emotions;
	std::vector<Ticks> blinks;
	std::vector<HeadGesture> gestures;
	std::vector<BrowEvent> brows;
	std::vector<AuEvent> actionUnits;
	// Continuous head pose and action units ("curves", D55: written by talkhead track).
	ControlCurves curves;
	// "drawn_blinks": false — the track's blinks are all there are (a tracked face): no drawn blinks.
	bool drawnBlinks = true;
	bool empty() const {
		return emotions.empty() && blinks.empty() && gestures.empty() && brows.empty() && actionUnits.empty() && curves.empty() && drawnBlinks;
	}
};

// Parses a control track; throws Error naming the file and the line/column (malformed JSON) or the event
// (its number, 1-based, and what is wrong: unknown type, missing or bad field, unknown emotion).
ControlTrack parseControls(const std::string& text, const std::string& path);
ControlTrack loadControls(const std::string& path);

// The JSON form of a track, as parseControls reads it (events first, then the curves; numbers to 4
// decimals, roll in degrees). `source` and `note` are written as informational fields when not empty.
std::string controlTrackJson(const ControlTrack& track, const std::string& source = "", const std::string& note = "");

// A TextGrid tier as a control track: each non-empty label (interval or point) is one event at its start,
//   TYPE [values in order] [key=value …]
// with the JSON fields in order per type: emotion LABEL [intensity] [ramp]; blink; nod|shake [amount];
// turn left|right|up|down [amount]; brows raise|frown [amount]; au AU [intensity] [left|right|both].
// An interval's length is its duration (an au's onset, apex and offset). Errors name the file and line.
ControlTrack parseControlTier(const std::string& text, const std::string& path, const std::string& tier);
ControlTrack loadControlTier(const std::string& path, const std::string& tier);

// Applies a track to a performance: each keypose takes the emotion and intensity in effect at its time
// (a change ramps through neutral: the old emotion fades out over the first half of the ramp, the new
// one in over the second); blinks and gestures go to the shape modulator. Throws Error naming the file and
// the event when an event lies past the performance's end.
void applyControls(Performance& perf, const ControlTrack& track);

}  // namespace talkhead
