// SPDX-License-Identifier: GPL-3.0-or-later
// The SSML subset of `talkhead say` (src/phonetics/ssml.cpp). Besides surviving any input, every event must
// point inside its segment's text.
#include <string>

#include "fuzz_support.h"
#include "phonetics/ssml.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	(void)looksLikeSsml(text);
	fuzz::expectOnlyErrors([&] {
		const SsmlText t = parseSsml(text, "fuzz.ssml");
		TALKHEAD_FUZZ_CHECK(!t.segments.empty(), "no segment");
		for (const auto& e : t.events) {
			TALKHEAD_FUZZ_CHECK(e.segment < t.segments.size(), "event past the segments");
			TALKHEAD_FUZZ_CHECK(e.offset <= t.segments[e.segment].text.size(), "event past its text");
		}
	});
	return 0;
}
