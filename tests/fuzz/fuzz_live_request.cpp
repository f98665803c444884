// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead serve's requests (src/serve/requests.cpp): any bytes a client sends are parsed into a request
// or refused with an Error; Azure viseme and ElevenLabs character timings become sorted, non-overlapping
// intervals.
#include <string>

#include "fuzz_support.h"
#include "serve/server.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	fuzz::expectOnlyErrors([&] {
		const LiveRequest r = parseLiveRequest(text);
		TALKHEAD_FUZZ_CHECK(!r.expression || (r.expression->intensity() >= 0 && r.expression->intensity() <= 1.5), "intensity out of range");
		// The id is kept as JSON text: a string of at most 200 bytes, quoted, each byte escaped at most as \u00XX.
		TALKHEAD_FUZZ_CHECK(r.id.size() <= 2 + 6 * 200, "id longer than 200 bytes");
		// A streamed speak (issue 49): its pieces carry audio only, whole 16-bit frames; its first is PCM.
		if (r.continues) {
			TALKHEAD_FUZZ_CHECK(!r.timing && r.transcript.empty() && r.text.empty() && !r.expression, "a continuing piece with a timing");
			TALKHEAD_FUZZ_CHECK(r.audio.size() % 2 == 0, "a piece of half a sample");
		} else if (r.more) {
			TALKHEAD_FUZZ_CHECK(r.pcmRate >= 8000 && !r.timing && r.transcript.empty(), "a streamed speak that is not PCM, or timed");
		}
		if (r.timing) {
			const auto& iv = r.timing->intervals;
			TALKHEAD_FUZZ_CHECK(!iv.empty(), "empty timing");
			for (std::size_t i = 0; i < iv.size(); ++i) {
				TALKHEAD_FUZZ_CHECK(iv[i].start <= iv[i].end, "interval ends before it starts");
				if (i) TALKHEAD_FUZZ_CHECK(iv[i].start >= iv[i - 1].end, "intervals overlap");
			}
		}
	});
	return 0;
}
