// SPDX-License-Identifier: GPL-3.0-or-later
// Action-unit appearance files (src/synth/au_appearance.cpp, models/au-appearance.bin): every problem an
// Error naming the file; what loads has one finite map of the grid's size per AU, and reading only some
// AUs gives those.
#include <cmath>
#include <string>

#include "fuzz_support.h"
#include "synth/au_appearance.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string path = fuzz::writeInput(data, size, "au-appearance.bin");
	fuzz::expectOnlyErrors([&] {
		const AuAppearance a = loadAuAppearance(path);
		TALKHEAD_FUZZ_CHECK(a.names.size() == a.logRatio.size() && !a.names.empty(), "");
		for (const auto& m : a.logRatio) {
			TALKHEAD_FUZZ_CHECK(m.size() == std::size_t(a.width) * std::size_t(a.height), "map size");
			for (float v : m) TALKHEAD_FUZZ_CHECK(std::isfinite(v), "map value");
		}
		const std::vector<std::string> one{a.names.front()};
		TALKHEAD_FUZZ_CHECK(loadAuAppearance(path, &one).names.size() == 1, "one AU");
	});
	return 0;
}
