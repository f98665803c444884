// SPDX-License-Identifier: GPL-3.0-or-later
// A streamed speak's pieces (issue 49, src/perform/stream.cpp): any 16-bit PCM, cut into pieces of any size,
// with a text or without, gives an Error or parts that are the audio exactly — the first opens the
// utterance, only the last closes it, each part's phones lie within its sound, in order.
// Input: byte 0 chooses text (odd) or recognition, byte 1 the piece length (×40 samples), the rest 16 kHz PCM.
#include <string>
#include <vector>

#include "fuzz_support.h"
#include "perform/stream.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	if (size < 4) return 0;
	const bool withText = data[0] & 1;
	const std::size_t step = 40 * (std::size_t(data[1]) + 1);
	std::vector<float> pcm;
	for (std::size_t i = 2; i + 1 < size; i += 2) pcm.push_back(float(std::int16_t(std::uint16_t(data[i] | (data[i + 1] << 8)))) / 32768.f);
	fuzz::expectOnlyErrors([&] {
		SpeechStream s("1", withText ? "bin green in m eight soon" : "", Language::get("en-US"), 16000, 16000);
		std::vector<Utterance> parts;
		const auto emit = [&](Utterance u) { parts.push_back(std::move(u)); };
		for (std::size_t at = 0; at < pcm.size() || at == 0; at += step) {
			const bool last = at + step >= pcm.size();
			const std::vector<float> piece(pcm.begin() + std::ptrdiff_t(std::min(at, pcm.size())), pcm.begin() + std::ptrdiff_t(std::min(pcm.size(), at + step)));
			s.feed(piece, last, emit);
			if (last) break;
		}
		TALKHEAD_FUZZ_CHECK(s.closed() && !parts.empty(), "the last piece closes the stream with a part");
		std::size_t samples = 0;
		for (std::size_t k = 0; k < parts.size(); ++k) {
			TALKHEAD_FUZZ_CHECK(parts[k].opens == (k == 0) && parts[k].closes == (k + 1 == parts.size()), "opens/closes");
			samples += parts[k].audio.samples.size();
			Ticks at{0};
			for (const PhoneSegment& p : parts[k].phones) {
				TALKHEAD_FUZZ_CHECK(p.start >= at && p.end > p.start && p.end <= parts[k].audio.duration(), "a phone outside its part");
				at = p.end;
			}
		}
		TALKHEAD_FUZZ_CHECK(samples == pcm.size(), "the parts are not the audio");
	});
	return 0;
}
