// SPDX-License-Identifier: GPL-3.0-or-later
// Action-unit template files (src/synth/action_units.cpp, models/au-templates/*.tsv) for ch-unicamp-56:
// every problem an Error; what parses has a full, finite offset table for each AU.
#include <cmath>
#include <string>

#include "fuzz_support.h"
#include "synth/action_units.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	static const Scheme scheme = loadScheme("ch-unicamp-56");
	const std::string text(reinterpret_cast<const char*>(data), size);
	fuzz::expectOnlyErrors([&] {
		const AuTemplates t = parseAuTemplates(text, "fuzz.tsv", scheme);
		TALKHEAD_FUZZ_CHECK(t.names.size() == t.offsets.size() && !t.names.empty(), "");
		for (const Points& o : t.offsets) TALKHEAD_FUZZ_CHECK(o.rows() == scheme.pointCount() && o.allFinite(), "offsets");
	});
	return 0;
}
