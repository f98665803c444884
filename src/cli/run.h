// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Running talkhead's commands in process: what `talkhead ARGS…` does, for the executable and for
// programs that embed the commands (the Python module, issue 33).
#include <string>
#include <vector>

namespace talkhead {
class FrameSink;
}

namespace talkhead::cli {

// Runs one command (`args[0]` is its name): returns the exit status (0, 2 for a usage error, 1 for any
// other failure); on failure `error` gets the one line the executable prints on stderr.
int runCommandLine(const std::vector<std::string>& args, std::string& error);

// A library field's flag ("output" → "-o", "tier" → "--tier"): how the command line words the fields
// library messages name ({{tier}}, base/error.h).
std::string cliField(const std::string& field);
// A library message as one line for the terminal: its fields worded as flags, then base/text.h safeLine.
std::string shownLine(const std::string& message);

// For in-process callers: while set (on this thread), every frame `render` and `say` draw also goes to
// this sink (RGB when it asks), after the command's own outputs.
void setExtraFrameSink(FrameSink* sink);
FrameSink* extraFrameSink();

// D64: when no default face is installed (a package leaves it out: 1.6 GB), makes it once in the user's
// cache folder — the same synthetic corpus and build as the build tree's, byte for byte — saying so on
// stderr unless `quiet`. Does nothing when one is found or no cache folder is known.
void ensureDefaultFace(bool quiet);

}  // namespace talkhead::cli
