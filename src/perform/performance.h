// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "base/frame_rate.h"
#include "base/ticks.h"
#include "phonetics/language.h"
#include "perform/timeline.h"
#include "synth/modulator.h"

namespace talkhead {

// What to render: a timeline (perform/timeline.h) at a frame rate over a duration, in an expression. Build
// one with planPerformance (perform/plan.h), or its keyposes from phones with `keyposes()`
// (phonetics/language.h), or by hand. Frames are 0 … frameCount() − 1, frame n at
// rate.time(n); before the first keypose and after the last the face holds.
struct Performance {
	FrameRate rate;                  // output frames per second (exact fraction)
	Ticks duration{0};               // the video's length (the audio's, or the transcript's end)
	Timeline timeline;               // keyposes in time order (CDV, instant, phone context, emotion), and what
	                                 // is asked for at times: blinks, gestures, brows, action units, curves
	Expression expression;           // for every keypose without its own (default neutral; intensity: D43)
	ModulatorOptions modulation;     // blinks and head motion drawn (on by default; D42): the knobs

	std::int64_t frameCount() const { return rate.frameCount(duration); }
	Ticks frameTime(std::int64_t n) const { return rate.time(n); }
};

// Still face before and after (issue 14: experiment software drifts at a clip's start): every keypose and
// timed event moves `leadIn` later, and the video grows by leadIn + tail. The face holds its first and
// last keypose there (blinks and head motion go on unless switched off).
void addLeadInAndTail(Performance& p, Ticks leadIn, Ticks tail);

// The sidecar of a stimulus (JSON): frame rate, frames, duration, lead-in, tail, audio-visual offset, the
// speech's onset and offset, every word (start, end, word; when the words are known), phone (start, end,
// phone, CDV) and keypose (time, CDV, emotion), times in seconds of the video. `phones` and `words` are
// the transcript's (before the lead-in); pauses among the words (empty, "sil", "sp", "_") are left out.
std::string timelineJson(const Performance& p, const std::vector<PhoneSegment>& phones, Ticks leadIn, Ticks tail, Ticks avOffset,
                         const std::vector<Interval>& words = {});

}  // namespace talkhead
