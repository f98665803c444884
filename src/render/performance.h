// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "base/frame_rate.h"
#include "base/ticks.h"
#include "phonetics/language.h"
#include "synth/modulator.h"

namespace talkhead {

// What to render: a timeline of keyposes at a frame rate over a duration. Build one from phones with
// `keyposes()` (phonetics/language.h), or by hand. Frames are 0 … frameCount() − 1, frame n at
// rate.time(n); before the first keypose and after the last the face holds.
struct Performance {
	FrameRate rate;                  // output frames per second (exact fraction)
	Ticks duration{0};               // the video's length (the audio's, or the transcript's end)
	std::vector<Keypose> keys;       // keyposes in time order (CDV, instant, phone context)
	std::string emotion = "neutral"; // canonical emotion label (phonetics/labels.h) for every keypose
	double intensity = 1;            // of the emotion: 0 = neutral keyposes, 1 = the corpus's, up to 1.5 (D43)
	ModulatorOptions modulation;     // blinks and head motion (on by default; D42)
	// (The expressive-control issue adds per-keypose emotion and control tracks here.)

	std::int64_t frameCount() const { return rate.frameCount(duration); }
	Ticks frameTime(std::int64_t n) const { return rate.time(n); }
};

}  // namespace talkhead
