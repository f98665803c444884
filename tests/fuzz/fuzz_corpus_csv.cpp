// SPDX-License-Identifier: GPL-3.0-or-later
// The CH-Unicamp CSV corpus reader (src/corpus/corpus.cpp readChUnicampCsv; it takes a path).
#include <cmath>
#include <string>

#include "corpus/corpus.h"
#include "fuzz_support.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string path = fuzz::writeInput(data, size, "corpus.csv");
	fuzz::expectOnlyErrors([&] {
		const Corpus c = readChUnicampCsv(path);
		TALKHEAD_FUZZ_CHECK(!c.entries.empty() && !c.schemeName.empty(), c.schemeName);
		for (const CorpusEntry& e : c.entries) {
			TALKHEAD_FUZZ_CHECK(e.points.rows() == c.entries.front().points.rows() && e.points.cols() == 2, e.source);
			TALKHEAD_FUZZ_CHECK(e.points.allFinite(), e.source);
			// A labelled row has both labels (typed), an unlabelled one neither, and its name.
			TALKHEAD_FUZZ_CHECK(e.emotion.has_value() == e.cdv.has_value() && (e.labelled() || !e.name.empty()), e.source);
		}
	});
	return 0;
}
