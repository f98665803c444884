// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace talkhead {

// Folders searched, in order, for the project's data files (schemes, later phonetics tables and the
// default model): $TALKHEAD_DATA_DIR, <executable>/../share/talkhead (installed tree), the install
// prefix's share/talkhead (compiled in: a program linking the installed library), and the source tree's
// own folders (compiled in, for running from the build directory).
std::vector<std::string> dataDirs();

// First existing "<dir>/<relative>" over dataDirs(), or nullopt.
std::optional<std::string> findDataFile(const std::string& relative);

// The default face model: $TALKHEAD_MODEL, else models/default.thm beside the executable (build tree),
// in <executable>/../share/talkhead/models (installed tree), or in the build tree this was compiled in.
// nullopt when none exists.
std::optional<std::string> findDefaultModel();
// Where findDefaultModel() looks, for error messages.
std::vector<std::string> defaultModelCandidates();

// The user's cache folder for data made on first use (an installed package's default face, D64):
// $XDG_CACHE_HOME/talkhead, else ~/.cache/talkhead; empty when neither is known. The last place
// findDefaultModel() and findDataFile() look.
std::string userCacheDir();

}  // namespace talkhead
