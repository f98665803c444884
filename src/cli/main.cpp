// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead: command-line entry point. One catch ladder: usage errors exit 2, all other failures 1.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "base/cpu_floor.h"
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

// Before any other constructor of this program: a CPU below the build's floor (x86-64-v3 for the portable
// build) gets one line and exit 1, not an illegal instruction somewhere later (D74).
__attribute__((constructor(101), target("arch=x86-64"))) void refuseOlderCpu() {
	if (const char* missing = talkhead::cpuFloorMissing()) {
		std::fputs(missing, stderr);
		std::fputs("\n", stderr);
		std::_Exit(1);
	}
}

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
		const std::string floor = cpuFloor();
		std::cout << "talkhead " << TALKHEAD_VERSION << " (built for " << (floor.empty() ? "the compiler's default x86-64" : floor) << ")\n";
		return 0;
	}
	std::string error;
	const int status = cli::runCommandLine(args, error);
	if (!error.empty()) std::fprintf(stderr, "%s\n", error.c_str());
	return status;
}
