// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace talkhead {

// Folders searched, in order, for the project's data files (schemes, later phonetics tables and the
// default model): $TALKHEAD_DATA_DIR, <executable>/../share/talkhead (installed tree), and the source
// tree's own folders (compiled in, for running from the build directory).
std::vector<std::string> dataDirs();

// First existing "<dir>/<relative>" over dataDirs(), or nullopt.
std::optional<std::string> findDataFile(const std::string& relative);

}  // namespace talkhead
