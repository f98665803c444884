// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "base/ticks.h"
#include "phonetics/language.h"
#include "synth/modulator.h"

namespace talkhead {

// A timeline (issue 46): the keyposes of a performance, an utterance or a live stream, what is asked for
// at times (blinks, gestures, brows, action units and curves: TimedEvents) and the marks reported when
// reached — one value that is shifted, spliced and cut as a whole. Emotion changes (controls, SSML) live
// on the keyposes: each key carries the emotion and intensity it is drawn in (Keypose::emotion).
struct TimelineMark {
	std::string name;
	Ticks time{0};
};

struct Timeline {
	std::vector<Keypose> keys;          // in time order
	TimedEvents events;
	std::vector<TimelineMark> marks;    // reported, not performed (SSML marks)

	// Everything `by` later (a lead-in; the curves' start too).
	void shift(Ticks by);
	// The first key after `drawn` (keys.size() when none): the keys before it and it are what a frame drawn
	// at `drawn` depended on.
	std::size_t firstAfter(Ticks drawn) const;
	// `later` (times from its start) spliced in at `at`, frames up to `drawn` already drawn: the keys they
	// depend on stay (those before `at`, and the first after `drawn`), the rest go; when the face was
	// holding (no key after `drawn`), the pose held fills the gap until `at`; then `later`'s keys after the
	// last kept, its events after this one's, its marks.
	void splice(const Timeline& later, Ticks at, Ticks drawn);
	// A barge-in at `t`: the events and marks from `t` on go (the curves stay; the keys are the caller's).
	void cut(Ticks t);
	// What lies behind `t`: the keys but the last before it, the events over and the marks before it.
	void dropBefore(Ticks t);
};

}  // namespace talkhead
