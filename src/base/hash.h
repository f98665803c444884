// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>

namespace talkhead {

// SplitMix64 (Steele, Lea & Flood 2014): a well-mixed 64-bit hash of x, and the step of the generator
// whose state advances by 0x9E3779B97F4A7C15 per draw. Seeds and blind IDs derive from it.
inline std::uint64_t splitmix64(std::uint64_t x) {
	x += 0x9E3779B97F4A7C15ull;
	x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
	x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
	return x ^ (x >> 31);
}

}  // namespace talkhead
