// SPDX-License-Identifier: GPL-3.0-or-later
// phonetics/cdv-mouth-targets.tsv (src/track/from_video.cpp loadCdvMouthTargets; it takes a path).
#include <string>

#include "fuzz_support.h"
#include "track/from_video.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string path = fuzz::writeInput(data, size, "cdv-mouth-targets.tsv");
	fuzz::expectOnlyErrors([&] {
		const auto targets = loadCdvMouthTargets(path);
		TALKHEAD_FUZZ_CHECK(!targets.empty(), "");
	});
	return 0;
}
