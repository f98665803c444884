// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

#include "perform/job.h"

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
int runJob(const std::vector<std::string>& args);
int runFaces(const std::vector<std::string>& args);
int runFormats(const std::vector<std::string>& args);
int runFace(const std::vector<std::string>& args);

// A job's command line (cmd_job.cpp): its command, each field as that command's long option (a switch
// alone), then the field the command takes as its positional argument (say's text, visemes' transcript,
// build's corpus, batch's manifest) after "--".
std::vector<std::string> jobArguments(const Job& job);
// The command line of a job written as JSON (perform/job.h parseJob), named `name` in errors; throws Error
// for a malformed job or one whose command talkhead does not have.
std::vector<std::string> jobCommandLine(const std::string& json, const std::string& name);

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
