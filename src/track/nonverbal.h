// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Non-verbal tracks from a tracked face (issue 17 §1, decision D55): the head's pose, the brows' and eyes'
// action units and the blinks of a person in a video, as controls that drive another face
// (talkhead track, render --drive). 2D, from dlib's 68 iBUG points (track/landmarks.h).
#include <string>
#include <vector>

#include "base/ticks.h"
#include "image/image.h"
#include "perform/controls.h"
#include "synth/action_units.h"
#include "synth/modulator.h"
#include "track/landmarks.h"

namespace talkhead {

struct NonVerbalOptions {
	bool head = true, brows = true, eyes = true;
	bool mouth = false;          // mouth action units (they add to speech: off unless asked for)
	double neutralSeconds = 1.0; // neutral = per-point median over the found frames of the first second …
	int neutralFrames = 0;       // … or over the first N found frames when > 0
	double maxTurnDegrees = 30;  // frames whose head turns further (yaw) are dropped and bridged
	double minConfidence = 0.5;  // frames whose fit is less consistent are dropped and bridged
};

// One video frame's measures (NaN where dropped, before bridging).
struct NonVerbalFrame {
	Ticks time{0};
	bool valid = false;   // face found, confident, head turned less than maxTurnDegrees
	double roll = 0;      // radians, positive clockwise on screen
	double x = 0, y = 0;  // translation of the face's centre, in the neutral face's inter-ocular distances
	double scale = 1;     // size against the neutral face
	double yaw = 0;       // degrees (an estimate from the nose tip against the eye corners), + toward image right
	double eyeOpening = 0;  // eye aspect ratio (mean of both eyes, raw points)
	std::vector<double> au;  // per NonVerbalTrack::channels
};

struct NonVerbalTrack {
	std::string source;
	double rate = 25;  // frames per second of the video
	Ticks start{0};
	std::vector<NonVerbalFrame> frames;  // one per video frame, after bridging
	struct Channel {
		std::string au;  // canonical
		int side = 0;    // −1 the subject's right (image left), +1 the subject's left, 0 both
		std::string part;  // "brow", "eye", "mouth"
	};
	std::vector<Channel> channels;
	std::vector<Ticks> blinks;  // blink starts (the modulator's 250-ms blink, its shut moment on the driver's)
	std::vector<std::pair<Ticks, Ticks>> bridged;  // spans of dropped frames, filled by Hermite interpolation
	std::size_t neutralCount = 0;
	double neutralEyeOpening = 0;
	std::vector<std::string> warnings;
	NonVerbalOptions options;

	// As controls: the head and action-unit curves (at the video's rate) and the blinks.
	ControlCurves curves() const;
};

// Analyses a track. Throws Error naming the source when too few frames have a usable face.
NonVerbalTrack analyseNonVerbal(const LandmarkTrack& track, const NonVerbalOptions& options = {});

// The tracks over time: head roll and yaw, translation and scale, each action unit, the eye opening with
// the blinks marked, dropped spans shaded.
Image8 plotNonVerbal(const NonVerbalTrack& track, int width = 1400);

// The analysis as a control track (what `track` writes and `render --drive` applies): the curves, and the
// blinks (with drawn blinks off) when the eyes are tracked.
ControlTrack controlsOf(const NonVerbalTrack& track);

}  // namespace talkhead
