// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/timeline.h"

#include <algorithm>

namespace talkhead {

void Timeline::shift(Ticks by) {
	for (Keypose& k : keys) k.time += by;
	events.shift(by);
	for (TimelineMark& m : marks) m.time += by;
}

std::size_t Timeline::firstAfter(Ticks drawn) const {
	std::size_t c = 0;
	while (c < keys.size() && keys[c].time <= drawn) ++c;
	return c;
}

void Timeline::splice(const Timeline& later, Ticks at, Ticks drawn) {
	const std::size_t c = firstAfter(drawn);
	std::vector<Keypose> kept;
	for (std::size_t i = 0; i < keys.size(); ++i)
		if (keys[i].time < at || i == c) kept.push_back(keys[i]);
	if (c >= keys.size() && !kept.empty() && kept.back().time < at) {  // holding: the pose held until `at`
		Keypose hold = kept.back();
		hold.time = at;
		hold.breath = false;
		kept.push_back(hold);
	}
	for (Keypose k : later.keys) {
		k.time += at;
		if (kept.empty() || k.time > kept.back().time) kept.push_back(std::move(k));
	}
	keys = std::move(kept);
	events.splice(later.events, at);
	for (TimelineMark m : later.marks) {
		m.time += at;
		marks.push_back(std::move(m));
	}
	std::stable_sort(marks.begin(), marks.end(), [](const TimelineMark& a, const TimelineMark& b) { return a.time < b.time; });
}

void Timeline::cut(Ticks t) {
	events.cut(t);
	marks.erase(std::remove_if(marks.begin(), marks.end(), [t](const TimelineMark& m) { return m.time >= t; }), marks.end());
}

void Timeline::dropBefore(Ticks t) {
	std::size_t drop = 0;
	while (drop + 1 < keys.size() && keys[drop + 1].time <= t) ++drop;
	keys.erase(keys.begin(), keys.begin() + std::ptrdiff_t(drop));
	events.dropEndedBefore(t);
	marks.erase(std::remove_if(marks.begin(), marks.end(), [t](const TimelineMark& m) { return m.time < t; }), marks.end());
}

}  // namespace talkhead
