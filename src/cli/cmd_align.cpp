// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead align AUDIO_OR_VIDEO (--text "…" | --text-file F) [--lang L] -o out.TextGrid
#include <cstdio>

#include "align/align.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/run.h"
#include "cli/args.h"
#include "cli/commands.h"

namespace talkhead::cli {

int runAlign(const std::vector<std::string>& argv) {
	Args args("align", "talkhead align AUDIO_OR_VIDEO (--text \"…\" | --text-file F) [--lang pt-BR] -o out.TextGrid",
	          {{"--text", "TEXT", "what the audio says"},
	           {"--text-file", "F", "read the text from a file (UTF-8)"},
	           {"--lang", "LANG", "pt-BR (default) or en-US (the languages with a viseme table)"},
	           {"--voices", "V1,V2,…", "espeak-ng voices of the reference renditions (default: the language's voice, +m3, +f2)"},
	           {"--force", "", "write the alignment even when the text does not seem to match the audio"},
	           {"--quiet", "", "no summary", "-q"},
	           {"--output", "OUT", "the TextGrid to write (- = standard output)", "-o"}},
	          "Forced alignment: finds when each word and phone of the text is spoken in the audio (any file libav\n"
	          "reads, the audio track of a video too) and writes a Praat TextGrid with 'words' and 'phones' tiers\n"
	          "that 'talkhead render --transcript' reads. Method: dynamic time warping of MFCC features against\n"
	          "espeak-ng renditions of the same text (docs/decisions.md D30).");
	if (!args.parse(argv)) return 0;
	args.onePositional("give one audio or video file");
	const std::string input = args.positionals()[0];
	const std::string output = args.required("--output", "-o OUT.TextGrid is required");
	std::string text;
	if (auto f = args.get("--text-file")) {
		if (args.has("--text")) throw UsageError("align: give --text or --text-file, not both");
		text = readTextFile(*f);
	} else if (auto t = args.get("--text")) {
		text = *t;
	} else {
		throw UsageError("align: --text \"…\" or --text-file F is required");
	}
	AlignOptions options;
	options.languageTag = args.get("--lang", "pt-BR");
	if (auto v = args.get("--voices"))
		for (const std::string& s : split(*v, ','))
			if (!trim(s).empty()) options.voices.emplace_back(trim(s));
	if (args.has("--force")) options.mismatchBelow = 0;
	const Alignment al = alignSpeechFile(input, text, options);
	const std::string grid = alignmentTextGrid(al, al.phones.intervals.empty() ? Ticks(0) : al.phones.intervals.back().end);
	if (output == "-") std::fwrite(grid.data(), 1, grid.size(), stdout);
	else writeFileAtomically(output, grid);
	for (const std::string& w : al.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", shownLine(input + ": " + w).c_str());
	if (!args.has("--quiet")) std::fprintf(stderr, "%s: %s\n", input.c_str(), alignmentSummary(al).c_str());
	return 0;
}

}  // namespace talkhead::cli
