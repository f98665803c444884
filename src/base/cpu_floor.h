// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The instruction-set floor a build was compiled for (issue 44, D74): the portable build's x86-64-v3.

namespace talkhead {

// The -march level this build needs ("x86-64-v3"; "native" for a build made for its own machine only;
// "" for the compiler's default).
const char* cpuFloor();

// Nullptr when this CPU runs what the build was compiled for; otherwise one line saying what is missing.
// Itself compiled for plain x86-64, so a caller may ask before anything else runs (the CLI does, in a
// constructor, so an older CPU gets that line, not an illegal instruction).
const char* cpuFloorMissing();

}  // namespace talkhead
