// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/cpu_floor.h"

#include <cstring>

#ifndef TALKHEAD_CPU_FLOOR
#define TALKHEAD_CPU_FLOOR ""
#endif

namespace talkhead {

const char* cpuFloor() { return TALKHEAD_CPU_FLOOR; }

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target("arch=x86-64"))) const char* cpuFloorMissing() {
	__builtin_cpu_init();  // may run before libgcc's own constructor
	const char* floor = TALKHEAD_CPU_FLOOR;
	bool ok = true;
	if (std::strcmp(floor, "x86-64-v2") == 0) ok = __builtin_cpu_supports("x86-64-v2");
	else if (std::strcmp(floor, "x86-64-v3") == 0) ok = __builtin_cpu_supports("x86-64-v3");
	else if (std::strcmp(floor, "x86-64-v4") == 0) ok = __builtin_cpu_supports("x86-64-v4");
	if (ok) return nullptr;
	if (std::strcmp(floor, "x86-64-v2") == 0) return "talkhead: this build needs an x86-64-v2 CPU (SSE4.2, POPCNT); this one lacks them";
	if (std::strcmp(floor, "x86-64-v3") == 0)
		return "talkhead: this build needs an x86-64-v3 CPU (AVX2, FMA, BMI2: Intel Haswell or AMD Excavator and later); this one lacks them";
	return "talkhead: this build needs an x86-64-v4 CPU (AVX-512); this one lacks it";
}
#else
const char* cpuFloorMissing() { return nullptr; }
#endif

}  // namespace talkhead
