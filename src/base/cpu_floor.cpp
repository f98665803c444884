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
	// Feature by feature (clang 14 knows no "x86-64-v3" here): each level's vector and bit features.
	const bool v2 = __builtin_cpu_supports("ssse3") && __builtin_cpu_supports("sse4.1") && __builtin_cpu_supports("sse4.2") &&
	                __builtin_cpu_supports("popcnt");
	const bool v3 = v2 && __builtin_cpu_supports("avx") && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
	                __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
	const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd") &&
	                __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
	bool ok = true;
	if (std::strcmp(floor, "x86-64-v2") == 0) ok = v2;
	else if (std::strcmp(floor, "x86-64-v3") == 0) ok = v3;
	else if (std::strcmp(floor, "x86-64-v4") == 0) ok = v4;
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
