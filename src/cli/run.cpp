// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/run.h"

#include <cstdio>
#include <new>

#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"

namespace talkhead::cli {

namespace {
thread_local FrameSink* extraSink = nullptr;
}

void setExtraFrameSink(FrameSink* sink) { extraSink = sink; }
FrameSink* extraFrameSink() { return extraSink; }

int runCommandLine(const std::vector<std::string>& args, std::string& error) {
	error.clear();
	const std::string command = args.empty() ? std::string() : args[0];
	const std::vector<std::string> rest(args.empty() ? args.end() : args.begin() + 1, args.end());
	try {
		if (const Command* c = findCommand(command)) return c->run(rest);
		throw UsageError("unknown command '" + command + "'");
	} catch (const UsageError& e) {
		error = "talkhead: " + safeLine(e.what()) + " (see 'talkhead " + (findCommand(command) ? command + " " : std::string()) + "--help')";
		return 2;
	} catch (const std::bad_alloc&) {
		error = "talkhead: error: out of memory";
		return 1;
	} catch (const std::exception& e) {
		// One line, valid UTF-8 and bounded, whatever the message quotes (a label with a newline, raw bytes,
		// a 200 KB line): base/text.h safeLine.
		error = "talkhead: error: " + safeLine(describeException(e));
		return 1;
	}
}

}  // namespace talkhead::cli
