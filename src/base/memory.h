// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstddef>

namespace talkhead {

// Asks the kernel for transparent huge pages on the 2 MiB-aligned interior of a large, not yet touched
// allocation. On VMs page faults dominate filling GB-sized model matrices; this cuts them ~500-fold.
// A hint only: does nothing for small ranges or where THP is unavailable.
void adviseHugePages(void* p, std::size_t bytes);

}  // namespace talkhead
