// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead job FILE|-: a job written as JSON (perform/job.h) run as its command (issue 46).
#include <cstdio>
#include <iostream>
#include <iterator>

#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/run.h"
#include "perform/job.h"

namespace talkhead::cli {

namespace {

// The field a command takes as its positional argument (say's text, visemes' transcript, …), if any.
const char* positionalField(const std::string& command) {
	if (command == "say") return "text";
	if (command == "visemes") return "transcript";
	if (command == "build") return "corpus";
	if (command == "batch") return "manifest";
	return nullptr;
}

}  // namespace

std::vector<std::string> jobArguments(const Job& job) {
	std::vector<std::string> a{job.command}, positional;
	const char* p = positionalField(job.command);
	for (const JobField& f : job.fields) {
		if (p && f.field == p) {
			positional.push_back(f.value.value_or(""));
			continue;
		}
		a.push_back(cliField(f.field));
		if (f.value) a.push_back(*f.value);
	}
	if (!positional.empty()) a.push_back("--");  // a text starting with '-' is still the text
	a.insert(a.end(), positional.begin(), positional.end());
	return a;
}

std::vector<std::string> jobCommandLine(const std::string& json, const std::string& name) {
	const Job job = parseJob(json, name);
	if (!findCommand(job.command) || job.command == "job") throw Error(name + ": 'command' is '" + job.command + "', not a talkhead command");
	return jobArguments(job);
}

int runJob(const std::vector<std::string>& argv) {
	Args args("job", "talkhead job FILE.json|-", {},
	          "Runs a job written as JSON: {\"command\": \"render\", \"fields\": {\"transcript\": \"s.TextGrid\", \"audio\": \"s.wav\",\n"
	          "\"emotion\": \"joy:0.6\", \"output\": \"out.mp4\"}}. Fields are the command's long options without the\n"
	          "dashes (a switch is true, a repeated option an array); say's text, visemes' transcript, build's\n"
	          "corpus and batch's manifest are fields of those names. batch hands each stimulus to its child this\n"
	          "way; Python's keywords become one; any program can write one.");
	if (!args.parse(argv)) return 0;
	const std::string& path = args.onePositional("name the job file (- for standard input)");
	std::string text;
	if (path == "-") text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
	else text = readTextFile(path);
	const std::vector<std::string> a = jobCommandLine(text, path == "-" ? "standard input" : path);
	return findCommand(a[0])->run(std::vector<std::string>(a.begin() + 1, a.end()));
}

}  // namespace talkhead::cli
