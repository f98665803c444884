// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

namespace talkhead {

// Integer time: the "flick" (1/705 600 000 s). Frame lengths at 24, 25, 30, 60 and 30000/1001 fps and
// sample lengths at 8–48 kHz are exact integers, so frame n sits at exactly n · ticksPerFrame and
// midpoints and comparisons are exact. Doubles appear only when parsing and printing.
using Ticks = std::chrono::duration<std::int64_t, std::ratio<1, 705600000>>;
constexpr std::int64_t kTicksPerSecond = 705600000;

// Readers bound their times (a day for transcripts); this conversion itself never overflows: beyond
// ±10⁹ s (±7·10¹⁷ ticks, well inside int64) it saturates, and NaN gives 0 — never undefined behaviour.
constexpr double kMaxTickSeconds = 1e9;
inline Ticks ticksFromSeconds(double s) {
	if (!(s == s)) return Ticks(0);
	s = s < -kMaxTickSeconds ? -kMaxTickSeconds : (s > kMaxTickSeconds ? kMaxTickSeconds : s);
	return Ticks(std::llround(s * double(kTicksPerSecond)));
}
inline double toSeconds(Ticks t) { return double(t.count()) / double(kTicksPerSecond); }

}  // namespace talkhead
