// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/args.h"
#include "cli/commands.h"

namespace talkhead::cli {

int runCorpusFromVideo(const std::vector<std::string>&) { throw UsageError("corpus from-video: not implemented yet"); }

}  // namespace talkhead::cli
