// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "base/ticks.h"

namespace talkhead {

// A frame rate as an exact fraction num/den frames per second (30/1, 25/1, 30000/1001). It owns the two
// rules wherever frames and times meet: frame n is at exactly n·den/num s (in ticks, rounded down), and a
// duration holds round(duration × num/den) frames (at least 1).
struct FrameRate {
	int num = 30, den = 1;

	// The instant of frame n.
	Ticks time(std::int64_t n) const { return Ticks(n * (kTicksPerSecond * den) / num); }
	// How many frames a duration holds: round(duration × fps), at least 1. Saturates instead of
	// overflowing (a duration of 10⁹ s still gives a count, which callers bound).
	std::int64_t frameCount(Ticks duration) const;
	// The frame at or just before t (floor(t × fps)).
	std::int64_t frameAt(Ticks t) const;
	// One frame's length, rounded down (for spacing rules such as "keyposes closer than a frame").
	Ticks frameLength() const { return Ticks(kTicksPerSecond * den / num); }
	double fps() const { return double(num) / double(den); }
	// "30", "30/1", "30000/1001" or "25.00".
	std::string str() const;

	// Parses "30", "30.0", "29.97", "12.5", "30000/1001" or "2997/100". The NTSC decimals 23.976, 29.97,
	// 47.952, 59.94 and 119.88 mean the exact x000/1001 rates their spelling abbreviates; any other
	// decimal is taken exactly (12.5 → 25/2). nullopt unless 1 ≤ fps ≤ 240 with num, den ≤ 1 000 000.
	static std::optional<FrameRate> parse(const std::string& text);
};

inline bool operator==(const FrameRate& a, const FrameRate& b) { return std::int64_t(a.num) * b.den == std::int64_t(b.num) * a.den; }

}  // namespace talkhead
