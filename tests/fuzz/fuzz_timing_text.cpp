// SPDX-License-Identifier: GPL-3.0-or-later
// Timing files read with the text they refer to (issue 29; ReadOptions::timingText): aeneas SMIL and TSV
// with XHTML, parsed or plain text; Google timepoints with their SSML. The input is the timing file, a form
// feed, and the text (no form feed: the text is empty); the format is detected from the content.
#include <string>

#include "fuzz_support.h"
#include "phonetics/transcript.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string bytes(reinterpret_cast<const char*>(data), size);
	const std::size_t ff = bytes.find('\f');
	ReadOptions o;
	o.timingText = fuzz::writeInput(ff == std::string::npos ? std::string() : bytes.substr(ff + 1), "text");
	fuzz::expectOnlyErrors([&] {
		const Transcript t = parseTranscript(bytes.substr(0, ff), "fuzz-input", o);
		TALKHEAD_FUZZ_CHECK(!t.intervals.empty(), "");
		for (std::size_t i = 1; i < t.intervals.size(); ++i) TALKHEAD_FUZZ_CHECK(t.intervals[i].start == t.intervals[i - 1].end, std::to_string(i));
	});
	return 0;
}
