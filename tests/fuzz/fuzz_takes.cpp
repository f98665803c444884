// SPDX-License-Identifier: GPL-3.0-or-later
// Take lists of `corpus from-video --takes` (src/track/from_video.cpp): every problem an Error; what reads
// has takes with an existing video and a canonical emotion.
#include <filesystem>
#include <string>

#include "fuzz_support.h"
#include "phonetics/labels.h"
#include "track/from_video.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	// A video the list may name, beside it.
	static const std::string video = fuzz::writeInput(std::string("not really a video"), "take.mp4");
	(void)video;
	const std::string path = fuzz::writeInput(data, size, "takes.tsv");
	fuzz::expectOnlyErrors([&] {
		for (const VideoTake& t : readTakeList(path)) {
			TALKHEAD_FUZZ_CHECK(std::filesystem::is_regular_file(t.video), "video");
			TALKHEAD_FUZZ_CHECK(canonicalEmotion(t.emotion) == t.emotion, "emotion");
			TALKHEAD_FUZZ_CHECK(t.transcript.empty() || t.text.empty(), "transcript and text");
		}
	});
	return 0;
}
