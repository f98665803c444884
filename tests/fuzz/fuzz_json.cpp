// SPDX-License-Identifier: GPL-3.0-or-later
// The JSON reader (src/base/json.cpp) behind Rhubarb JSON and speech marks. Besides surviving any input,
// every string it returns must come back unchanged through jsonQuote and parseJson (the writers' escaping).
#include <string>

#include "base/json.h"
#include "fuzz_support.h"

using namespace talkhead;

namespace {
void roundTripStrings(const JsonValue& v) {
	auto check = [](const std::string& s) {
		const JsonValue back = parseJson(jsonQuote(s), "quoted");
		TALKHEAD_FUZZ_CHECK(back.kind == JsonValue::Kind::String && back.string == s, jsonQuote(s));
	};
	if (v.kind == JsonValue::Kind::String) check(v.string);
	for (const auto& e : v.array) roundTripStrings(e);
	for (const auto& [k, e] : v.object) {
		check(k);
		roundTripStrings(e);
	}
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	JsonValue v;
	bool parsed = false;
	fuzz::expectOnlyErrors([&] {
		v = parseJson(text, "fuzz.json");
		parsed = true;
	});
	// Outside expectOnlyErrors: an Error from re-reading what jsonQuote wrote is a finding too.
	if (parsed) {
		try {
			roundTripStrings(v);
		} catch (const std::exception& e) {
			fuzz::violated("jsonQuote output reads back", e.what());
		}
	}
	return 0;
}
