// SPDX-License-Identifier: GPL-3.0-or-later
// The landmark scheme file (src/geometry/scheme.cpp, models/schemes/*.scheme), from memory.
#include <string>

#include "fuzz_support.h"
#include "geometry/scheme.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	fuzz::expectOnlyErrors([&] {
		const Scheme s = parseScheme(text, "fuzz.scheme");
		// What the model builder relies on: one class and weight per point, boundaries of known points.
		TALKHEAD_FUZZ_CHECK(s.pointCount() >= 3, "");
		TALKHEAD_FUZZ_CHECK(s.pointClasses.size() == s.pointNames.size() && s.weights.size() == s.pointCount(), "");
		for (const RegionSpec& r : s.regions) {
			TALKHEAD_FUZZ_CHECK(r.boundary.size() >= 3, r.name);
			for (int i : r.boundary) TALKHEAD_FUZZ_CHECK(i >= 0 && i < s.pointCount(), r.name);
		}
	});
	return 0;
}
