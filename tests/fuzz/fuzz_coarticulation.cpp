// SPDX-License-Identifier: GPL-3.0-or-later
// Coarticulation models (src/synth/coarticulation.cpp, `render --coarticulation F.tsv`): every problem an
// Error naming the file; what loads has this build's features, finite weights, and predicts a finite,
// non-negative opening for every phone keypose of a small sentence.
#include <cmath>
#include <string>

#include "fuzz_support.h"
#include "synth/coarticulation.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string path = fuzz::writeInput(data, size, "coarticulation.tsv");
	fuzz::expectOnlyErrors([&] {
		const CoarticulationModel m = loadCoarticulation(path);
		TALKHEAD_FUZZ_CHECK(m.features == coarticulationFeatureNames(), "features");
		TALKHEAD_FUZZ_CHECK(m.weights.allFinite() && m.widthWeights.allFinite(), "weights");
		const Ticks p(kTicksPerSecond / 10);
		const std::vector<PhoneSegment> phones = {{Ticks(0), p * 4, "_", "_", "sil", 0}, {p * 4, p * 5, "p", "p", "p1", 0}, {p * 5, p * 6, "a", "a", "a", 0},
		                                          {p * 6, p * 7, "u", "u", "u", 0}, {p * 7, p * 12, "_", "_", "sil", 0}};
		auto keys = keyposes(phones, Ticks(kTicksPerSecond / 25));
		predictMouthOpenings(m, phones, keys);
		for (const Keypose& k : keys)
			if (k.mouthOpening) TALKHEAD_FUZZ_CHECK(std::isfinite(*k.mouthOpening) && *k.mouthOpening >= 0 && std::isfinite(*k.mouthWidth), "prediction");
	});
	return 0;
}
