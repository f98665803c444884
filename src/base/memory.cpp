// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/memory.h"

#include <sys/mman.h>

#include <cstdint>

namespace talkhead {

void adviseHugePages(void* p, std::size_t bytes) {
	constexpr std::uintptr_t huge = std::uintptr_t(2) << 20;
	if (!p || bytes < 4 * huge) return;
	const std::uintptr_t a = (reinterpret_cast<std::uintptr_t>(p) + huge - 1) & ~(huge - 1);
	const std::uintptr_t b = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(huge - 1);
	if (b > a) ::madvise(reinterpret_cast<void*>(a), b - a, MADV_HUGEPAGE);
}

void prefault(void* p, std::size_t bytes) {
#ifndef MADV_POPULATE_WRITE
	constexpr int MADV_POPULATE_WRITE = 23;
#endif
	constexpr std::uintptr_t page = 4096;
	if (!p || bytes < (std::size_t(256) << 10)) return;
	const std::uintptr_t a = (reinterpret_cast<std::uintptr_t>(p) + page - 1) & ~(page - 1);
	const std::uintptr_t b = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(page - 1);
	if (b > a) ::madvise(reinterpret_cast<void*>(a), b - a, MADV_POPULATE_WRITE);
}

}  // namespace talkhead
