// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Running talkhead's commands in process: what `talkhead ARGS…` does, for the executable and for
// programs that embed the commands (the Python module, issue 33).
#include <optional>
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

// Issue 48: the face a command's `--face NAME` names, as a model path — "synthetic" is the default face
// ("" after ensureDefaultFace), a shipped face (model/faces.h) is built on first use into the cache with a
// progress bar and a line saying so unless `quiet`. Throws Error for an unknown name.
std::string shippedFaceModel(const std::string& name, bool quiet);
// A command's --face and --model: the model path ("" = the default face, made if need be). UsageError
// when both are given.
std::string faceOrModel(const std::optional<std::string>& face, const std::optional<std::string>& model, const std::string& command, bool quiet);
// The name `--face` takes for the synthetic default face.
extern const char* const kSyntheticFace;

}  // namespace talkhead::cli
