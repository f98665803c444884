// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead: command-line entry point. One catch ladder: usage errors exit 2, all other failures 1.
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/interrupt.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/run.h"

#ifndef TALKHEAD_VERSION
#define TALKHEAD_VERSION "0.0.0"
#endif

namespace {

std::string usage() {
	std::string u = "usage: talkhead <command> [options]\n\nRenders videos of a talking face (Costa 2015 expressive speech animation).\n\ncommands:\n";
	for (const auto& c : talkhead::cli::commands()) {
		char line[512];
		std::snprintf(line, sizeof line, "  %-9s %s\n", c.name, c.summary);
		u += line;
	}
	return u + "\n  talkhead <command> --help   options of one command\n  talkhead --version          version\n";
}

}  // namespace

int main(int argc, char** argv) {
	using namespace talkhead;
	// A reader that goes away (| head, a closed ffplay) is a write error with a message, not a silent kill.
	std::signal(SIGPIPE, SIG_IGN);
	installInterruptHandlers();  // a stop removes every temporary and exits at once (base/interrupt.h)
	std::vector<std::string> args(argv + 1, argv + argc);
	if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
		if (args.empty()) {
			std::fputs(usage().c_str(), stderr);
			return 2;
		}
		std::cout << usage();
		return 0;
	}
	if (args[0] == "--version" || args[0] == "-V") {
		std::cout << "talkhead " << TALKHEAD_VERSION << "\n";
		return 0;
	}
	std::string error;
	const int status = cli::runCommandLine(args, error);
	if (!error.empty()) std::fprintf(stderr, "%s\n", error.c_str());
	return status;
}
