// SPDX-License-Identifier: GPL-3.0-or-later
// landmarks.tsv (src/track/landmarks.cpp readLandmarksTsv; 'corpus from-video --landmarks F.tsv' reads
// it; it takes a path). What it accepts must write back (landmarksTsv) to text it reads the same way, and
// the points of a found frame must be numbers.
#include <string>

#include "fuzz_support.h"
#include "track/landmarks.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string path = fuzz::writeInput(data, size, "landmarks.tsv");
	fuzz::expectOnlyErrors([&] {
		const LandmarkTrack t = readLandmarksTsv(path);
		for (const FrameLandmarks& f : t.frames)
			if (f.found) TALKHEAD_FUZZ_CHECK(f.points.rows() == kIbugPoints && f.points.allFinite(), "frame " + std::to_string(f.frame));
		const std::string text = landmarksTsv(t);
		const std::string again = landmarksTsv(readLandmarksTsv(fuzz::writeInput(text, "written.tsv")));
		TALKHEAD_FUZZ_CHECK(again == text, "");
	});
	return 0;
}
