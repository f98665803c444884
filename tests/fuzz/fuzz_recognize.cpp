// SPDX-License-Identifier: GPL-3.0-or-later
// Audio → recognised phones (issue 49, src/align/recognize.cpp): any bytes as a WAV (or whatever libav
// makes of them) give an Error or phones contiguous over the audio's length with confidences in [0, 1].
#include <string>

#include "align/recognize.h"
#include "fuzz_support.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string path = fuzz::writeInput(data, size, "speech.wav");
	fuzz::expectOnlyErrors([&] {
		const Recognition r = recognizePhonesFile(path);
		TALKHEAD_FUZZ_CHECK(!r.phones.intervals.empty(), "intervals");
		TALKHEAD_FUZZ_CHECK(r.phones.intervals.front().start == Ticks(0), "start");
		TALKHEAD_FUZZ_CHECK(r.phones.intervals.back().end == r.duration, "end");
		TALKHEAD_FUZZ_CHECK(r.confidence.size() == r.phones.intervals.size(), "confidences");
		for (std::size_t k = 0; k < r.phones.intervals.size(); ++k) {
			TALKHEAD_FUZZ_CHECK(r.phones.intervals[k].end > r.phones.intervals[k].start, "empty interval");
			TALKHEAD_FUZZ_CHECK(k == 0 || r.phones.intervals[k].start == r.phones.intervals[k - 1].end, "gap");
			TALKHEAD_FUZZ_CHECK(r.confidence[k] >= 0 && r.confidence[k] <= 1, "confidence");
		}
	});
	return 0;
}
