// SPDX-License-Identifier: GPL-3.0-or-later
// A say request all the way into libespeak-ng (issue 28 item 1: "en-us+" and 37 characters aborted the
// server inside libespeak-ng): any bytes are parsed as a live request (src/serve/requests.cpp), and a say
// is spoken with the server's limits (prepareUtterance → speakText → espeak-ng: voice and variant checked
// against espeak-ng's own lists, SSML, breaks bounded). Only an Error may come back, never a crash; the
// sound is never longer than the limit. Kept fast: texts of at most 120 bytes, 4 s of speech at most.
#include <string>

#include "fuzz_support.h"
#include "serve/server.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	LiveRequest r;
	bool parsed = false;
	fuzz::expectOnlyErrors([&] {
		r = parseLiveRequest(text);
		parsed = true;
	});
	if (!parsed || r.kind != LiveRequest::Kind::Say || r.text.size() > 120) return 0;
	SpeechLimits limits;
	limits.maxSeconds = 4;
	limits.maxBreakSeconds = 2;
	fuzz::expectOnlyErrors([&] {
		const Utterance u = prepareUtterance(r, "en-US", 22050, limits);
		TALKHEAD_FUZZ_CHECK(toSeconds(u.audio.duration()) <= limits.maxSeconds + 0.5, "speech longer than its limit");
		TALKHEAD_FUZZ_CHECK(!u.phones.empty(), "a spoken say without phones");
	});
	return 0;
}
