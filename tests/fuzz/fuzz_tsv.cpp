// SPDX-License-Identifier: GPL-3.0-or-later
// The data-table reader (src/base/tsv.cpp: phonetics tables, corpus-tools data), from memory, and its
// column and number accessors on whatever it accepts.
#include <string>

#include "base/tsv.h"
#include "fuzz_support.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	fuzz::expectOnlyErrors([&] {
		const TsvTable t = parseTsv(text, "fuzz.tsv");
		for (const auto& row : t.rows) TALKHEAD_FUZZ_CHECK(row.fields.size() == t.header.size(), "line " + std::to_string(row.line));
		for (const std::string& name : t.header) TALKHEAD_FUZZ_CHECK(t.header[t.column(name)] == name, name);
		for (const auto& row : t.rows)
			for (std::size_t c = 0; c < t.header.size(); ++c) fuzz::expectOnlyErrors([&] {
				const double v = t.number(row, c, -1e6, 1e6);
				TALKHEAD_FUZZ_CHECK(v >= -1e6 && v <= 1e6, std::to_string(v));
			});
	});
	return 0;
}
