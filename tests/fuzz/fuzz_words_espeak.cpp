// SPDX-License-Identifier: GPL-3.0-or-later
// Word-level transcript → phones through libespeak-ng (src/phonetics/espeak.cpp expandWords): the input is
// read as a word-level transcript (format detected), then each word is phonemised (en-US for inputs of
// even length, pt-BR for odd) and its phones spread over the word's interval. Kept fast: at most 12
// words of at most 48 bytes (scripts/fuzz also caps the input at 1 KiB); espeak-ng does the rest.
#include <string>

#include "fuzz_support.h"
#include "phonetics/espeak.h"
#include "phonetics/transcript.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string bytes(reinterpret_cast<const char*>(data), size);
	ReadOptions o;
	o.level = LabelLevel::Word;
	Transcript words;
	bool parsed = false;
	fuzz::expectOnlyErrors([&] {
		words = parseTranscript(bytes, "words", o);
		parsed = true;
	});
	if (!parsed || words.level != LabelLevel::Word || words.intervals.size() > 12) return 0;
	for (const Interval& w : words.intervals)
		if (w.label.size() > 48) return 0;
	fuzz::expectOnlyErrors([&] {
		const std::vector<Interval> phones = expandWords(words, size % 2 ? "pt-BR" : "en-US");
		// Each word's phones share its interval in order: inside the transcript's span, never backwards.
		const Ticks first = words.intervals.front().start, last = words.intervals.back().end;
		for (std::size_t i = 0; i < phones.size(); ++i) {
			const Interval& p = phones[i];
			const std::string at = "phone " + std::to_string(i) + " '" + p.label + "' [" + std::to_string(p.start.count()) + ", " + std::to_string(p.end.count()) + ")";
			TALKHEAD_FUZZ_CHECK(p.start <= p.end && p.start >= first && p.end <= last, at);
			if (i) TALKHEAD_FUZZ_CHECK(p.start >= phones[i - 1].end, at);
		}
	});
	return 0;
}
