// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead align AUDIO_OR_VIDEO (--text "…" | --text-file F) [--lang L] -o out.TextGrid
#include "cli/args.h"
#include "cli/commands.h"

namespace talkhead::cli {

int runAlign(const std::vector<std::string>&) { throw UsageError("align: not implemented yet"); }

}  // namespace talkhead::cli
