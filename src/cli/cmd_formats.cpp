// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead formats [--format table|tsv|markdown]: the timing formats talkhead reads, from the registry
// (issue 50, D96).
#include <cstdio>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/run.h"
#include "phonetics/timing_registry.h"

namespace talkhead::cli {

int runFormats(const std::vector<std::string>& argv) {
	Args args("formats", "talkhead formats [--format table|tsv|markdown]",
	          {{"--format", "FORMAT", "table (default: one block per format), tsv (tab-separated, with a header) or markdown (the README's table)"}},
	          "Lists every timing format talkhead reads (render --transcript, visemes, batch, serve): the name --format\n"
	          "takes, what writes it, its extensions, its level (phones, words, sentences, visemes) and what is taken\n"
	          "from the file (units, language, speakers, duration). Formats named but not read say what to export\n"
	          "instead. Detection runs every format's signature; a file no signature matches, or that two match, is\n"
	          "an error naming what it looks like.");
	if (!args.parse(argv)) return 0;
	if (!args.positionals().empty()) throw UsageError("formats: takes no arguments");
	const std::string format = args.get("--format", "table");
	if (format == "tsv" || format == "markdown") {
		// Each line worded for the command line (a message's fields as flags); the table keeps its lines.
		// Tabs kept (shownLine would escape them); the fields still worded as flags.
		const auto flag = [](const std::string& f) { return std::optional<std::string>(cliField(f)); };
		std::fputs(wordFields(formatsTable(format == "markdown"), flag).c_str(), stdout);
		return 0;
	}
	if (format != "table") throw UsageError("formats: --format is table, tsv or markdown, not '" + format + "'");
	for (const TimingFormat& f : timingFormats()) {
		std::printf("%-18s %s\n", f.name.c_str(), shownLine(f.title).c_str());
		if (!f.extensions.empty()) std::printf("%-18s extensions: %s\n", "", joined(f.extensions, " ").c_str());
		if (f.read) {
			std::printf("%-18s level: %s\n", "", f.level.c_str());
			if (!f.takes.empty()) std::printf("%-18s from the file: %s\n", "", shownLine(f.takes).c_str());
		} else {
			std::printf("%-18s not read: %s\n", "", shownLine(f.refusal).c_str());
		}
	}
	return 0;
}

}  // namespace talkhead::cli
