// SPDX-License-Identifier: GPL-3.0-or-later
// Control tracks (src/perform/controls.cpp): parsed, then applied to a 5-s performance (times past its end
// are errors, never wrong keyposes); and the same bytes as a TextGrid control tier.
#include <string>

#include "fuzz_support.h"
#include "perform/controls.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	fuzz::expectOnlyErrors([&] {
		const ControlTrack t = parseControls(text, "fuzz.json");
		Performance p;
		p.rate = FrameRate{30, 1};
		p.duration = Ticks(5 * kTicksPerSecond);
		for (int i = 0; i < 10; ++i) p.timeline.keys.push_back(Keypose{Ticks(i * kTicksPerSecond / 2), "a", 0, 0});
		applyControls(p, t);
		for (const auto& k : p.timeline.keys) TALKHEAD_FUZZ_CHECK(k.intensity <= 1.5, "intensity above 1.5");
	});
	fuzz::expectOnlyErrors([&] {
		const ControlTrack t = parseControlTier(text, "fuzz.TextGrid", "controls");
		for (const auto& a : t.actionUnits) TALKHEAD_FUZZ_CHECK(a.intensity >= 0 && a.intensity <= 1.5, "action-unit intensity out of range");
	});
	return 0;
}
