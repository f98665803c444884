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

const char* kUsage =
    "usage: talkhead <command> [options]\n"
    "\n"
    "Renders videos of a talking face (Costa 2015 expressive speech animation).\n"
    "\n"
    "commands:\n"
    "  build     build a face model (.thm) from an annotated image corpus\n"
    "  inspect   summarise a face model, draw it (-o DIR), measure reconstruction (--recon)\n"
    "  corpus    corpus tools: 'synth' (synthetic corpus), 'landmarks' (track a video), 'from-video' (corpus from a video)\n"
    "  render    render a talking-head video from a transcript, audio and an emotion\n"
    "  say       text in, talking-head video with speech out (espeak-ng, in process)\n"
    "  align     forced alignment: speech audio (or video) + its text -> TextGrid of words and phones\n"
    "  compare   lip-sync measures of a synthesized video against a real speaker's video\n"
    "  track     a person's head motion, brows, eyes and blinks from a video, as a control track\n"
    "  visemes   map a timed transcript (TextGrid, .pho, HTK, GRID, speech marks, …) to visemes and keyposes\n"
    "  batch     perceptual-test stimuli from a manifest: blind IDs, key, balanced orders, resumable, shards\n"
    "  serve     live streams for chatbots and voice assistants: WebSocket in, fragmented MP4 + JSON events out\n"
    "  live      render a live session's script (serve --record) offline, frame for frame\n"
    "\n"
    "  talkhead <command> --help   options of one command\n"
    "  talkhead --version          version\n";

}  // namespace

int main(int argc, char** argv) {
	using namespace talkhead;
	// A reader that goes away (| head, a closed ffplay) is a write error with a message, not a silent kill.
	std::signal(SIGPIPE, SIG_IGN);
	installInterruptHandlers();  // a stop removes every temporary and exits at once (base/interrupt.h)
	std::vector<std::string> args(argv + 1, argv + argc);
	if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
		if (args.empty()) {
			std::fputs(kUsage, stderr);
			return 2;
		}
		std::cout << kUsage;
		return 0;
	}
	if (args[0] == "--version" || args[0] == "-V") {
		std::cout << "talkhead " << TALKHEAD_VERSION << "\n";
		return 0;
	}
	const std::string command = args[0];
	std::vector<std::string> rest(args.begin() + 1, args.end());
	try {
		if (command == "build") return cli::runBuild(rest);
		if (command == "inspect") return cli::runInspect(rest);
		if (command == "corpus") return cli::runCorpus(rest);
		if (command == "visemes") return cli::runVisemes(rest);
		if (command == "render") return cli::runRender(rest);
		if (command == "say") return cli::runSay(rest);
		if (command == "align") return cli::runAlign(rest);
		if (command == "compare") return cli::runCompare(rest);
		if (command == "track") return cli::runTrack(rest);
		if (command == "batch") return cli::runBatch(rest);
		if (command == "serve") return cli::runServe(rest);
		if (command == "live") return cli::runLive(rest);
		throw cli::UsageError("unknown command '" + command + "'");
	} catch (const cli::UsageError& e) {
		std::fprintf(stderr, "talkhead: %s (see 'talkhead %s--help')\n", safeLine(e.what()).c_str(), command == "build" || command == "inspect" || command == "corpus" || command == "visemes" || command == "render" || command == "say" || command == "align" || command == "compare" || command == "track" || command == "batch" || command == "serve" || command == "live" ? (command + " ").c_str() : "");
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
