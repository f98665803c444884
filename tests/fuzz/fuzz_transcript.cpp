// SPDX-License-Identifier: GPL-3.0-or-later
// Timed-transcript readers (src/phonetics/transcript.cpp), from memory: parseTranscript with the format
// TALKHEAD_FUZZ_FORMAT ("textgrid", "pho", "htk", …), or detected from the content when it is "".
// One source, one binary per format (tests/fuzz/CMakeLists.txt), so each gets its own corpus and coverage.
#include <string>

#include "base/ticks.h"
#include "fuzz_support.h"
#include "phonetics/transcript.h"

#ifndef TALKHEAD_FUZZ_FORMAT
#error "define TALKHEAD_FUZZ_FORMAT (a transcript format, or \"\" to detect it)"
#endif

using namespace talkhead;

namespace {

// What parseTranscript promises (transcript.h): at least one interval, sorted, non-overlapping, no
// zero-length intervals, gaps filled (so each starts where the one before ends), times ≥ 0 and bounded.
void checkTranscript(const Transcript& t) {
	constexpr std::int64_t kLimit = (86400 + 60) * kTicksPerSecond;  // a day (the readers' limit) + slack for a last mark
	TALKHEAD_FUZZ_CHECK(!t.intervals.empty(), "");
	// "srt" reads WebVTT too (json_timing detects among every format, as transcript_detect does, from JSON seeds).
	const std::string want = TALKHEAD_FUZZ_FORMAT;
	if (!want.empty() && want != "json" && want != "srt") TALKHEAD_FUZZ_CHECK(t.format == want, t.format);
	for (std::size_t i = 0; i < t.intervals.size(); ++i) {
		const Interval& iv = t.intervals[i];
		const std::string at = "interval " + std::to_string(i) + " [" + std::to_string(iv.start.count()) + ", " + std::to_string(iv.end.count()) + ")";
		TALKHEAD_FUZZ_CHECK(iv.start.count() >= 0, at);
		TALKHEAD_FUZZ_CHECK(iv.end > iv.start, at);
		TALKHEAD_FUZZ_CHECK(iv.end.count() <= kLimit, at);
		if (i) TALKHEAD_FUZZ_CHECK(iv.start == t.intervals[i - 1].end, at);
	}
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string bytes(reinterpret_cast<const char*>(data), size);
	ReadOptions o;
	o.format = TALKHEAD_FUZZ_FORMAT;
	fuzz::expectOnlyErrors([&] { checkTranscript(parseTranscript(bytes, "fuzz-input", o)); });
	return 0;
}
