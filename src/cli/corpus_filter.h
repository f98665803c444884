// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

#include "cli/args.h"
#include "corpus/corpus.h"

namespace talkhead::cli {

// The --include / --exclude GLOB options (matched against each entry's image file name).
inline const OptionSpec kIncludeOption{"--include", "GLOB", "only images whose file name matches GLOB (e.g. '12_*')"};
inline const OptionSpec kExcludeOption{"--exclude", "GLOB", "skip images whose file name matches GLOB"};

// Loads a corpus and applies --include / --exclude; throws Error when nothing is left.
Corpus loadFilteredCorpus(const std::string& path, const Args& args);

}  // namespace talkhead::cli
