// SPDX-License-Identifier: GPL-3.0-or-later
// The label tables (src/phonetics/labels.cpp): phonetics/emotions.tsv and phonetics/visemes.tsv, both
// readers on every input (they take a path).
#include <string>

#include "fuzz_support.h"
#include "phonetics/labels.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string path = fuzz::writeInput(data, size, "labels.tsv");
	fuzz::expectOnlyErrors([&] { TALKHEAD_FUZZ_CHECK(!loadEmotionLabels(path).empty(), ""); });
	fuzz::expectOnlyErrors([&] { TALKHEAD_FUZZ_CHECK(!loadVisemeLabels(path).empty(), ""); });
	return 0;
}
