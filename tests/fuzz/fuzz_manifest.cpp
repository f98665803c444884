// SPDX-License-Identifier: GPL-3.0-or-later
// Batch manifests (src/stimuli/batch.cpp), CSV or JSON: every problem an Error, never a crash; what parses
// has a command and arguments for every row.
#include <string>

#include "fuzz_support.h"
#include "stimuli/batch.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	fuzz::expectOnlyErrors([&] {
		const Manifest m = parseManifest(text, "fuzz.csv");
		for (const auto& r : m.rows) TALKHEAD_FUZZ_CHECK((r.command == "say" || r.command == "render") && !r.job.empty(), "row without a command");
		const auto ids = blindIds(m.rows.size(), 1);
		TALKHEAD_FUZZ_CHECK(ids.size() == m.rows.size(), "");
	});
	return 0;
}
