// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead: command-line entry point. One catch ladder: usage errors exit 2, all other failures 1.
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/interrupt.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"

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
	const std::string command = args[0];
	std::vector<std::string> rest(args.begin() + 1, args.end());
	try {
		if (const cli::Command* c = cli::findCommand(command)) return c->run(rest);
		throw cli::UsageError("unknown command '" + command + "'");
	} catch (const cli::UsageError& e) {
		std::fprintf(stderr, "talkhead: %s (see 'talkhead %s--help')\n", safeLine(e.what()).c_str(), cli::findCommand(command) ? (command + " ").c_str() : "");
		return 2;
	} catch (const std::bad_alloc&) {
		std::fprintf(stderr, "talkhead: error: out of memory\n");
		return 1;
	} catch (const std::exception& e) {
		// One line, valid UTF-8 and bounded, whatever the message quotes (a label with a newline, raw bytes,
		// a 200 KB line): base/text.h safeLine.
		const std::string message = safeLine(describeException(e));
		std::fprintf(stderr, "talkhead: error: %s\n", message.c_str());
		return 1;
	}
}
