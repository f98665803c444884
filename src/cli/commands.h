// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

namespace talkhead::cli {

// Each returns the process exit code; errors are thrown (Error → 1, UsageError → 2).
int runBuild(const std::vector<std::string>& args);
int runInspect(const std::vector<std::string>& args);
int runCorpus(const std::vector<std::string>& args);
int runVisemes(const std::vector<std::string>& args);
int runRender(const std::vector<std::string>& args);
int runSay(const std::vector<std::string>& args);
int runAlign(const std::vector<std::string>& args);
int runCompare(const std::vector<std::string>& args);
int runTrack(const std::vector<std::string>& args);
int runCorpusLandmarks(const std::vector<std::string>& args);
int runCorpusFromVideo(const std::vector<std::string>& args);
int runBatch(const std::vector<std::string>& args);
int runServe(const std::vector<std::string>& args);
int runLive(const std::vector<std::string>& args);

// The one command table: name, one-line summary (talkhead --help), entry point, in the order of the help.
struct Command {
	const char* name;
	const char* summary;
	int (*run)(const std::vector<std::string>& args);
};
const std::vector<Command>& commands();
// The command of that name, or nullptr.
const Command* findCommand(const std::string& name);

}  // namespace talkhead::cli
