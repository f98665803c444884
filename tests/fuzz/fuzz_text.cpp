// SPDX-License-Identifier: GPL-3.0-or-later
// The message helpers of base/text.h (issue 15, "error lines that are safe to print") and the text
// decoder every reader goes through: whatever bytes come in, safeQuote and safeLine give one line of
// valid UTF-8 without control characters, within their bound; decodeText never throws.
#include <string>

#include "base/text.h"
#include "fuzz_support.h"

using namespace talkhead;

namespace {

// Valid UTF-8 (shortest forms, no surrogates, ≤ U+10FFFF) without C0, DEL or C1 control characters.
bool printable(const std::string& s) {
	for (std::size_t i = 0; i < s.size();) {
		const unsigned char c = static_cast<unsigned char>(s[i]);
		if (c < 0x20 || c == 0x7F) return false;
		if (c < 0x80) {
			++i;
			continue;
		}
		const std::size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
		if (n == 0 || i + n > s.size()) return false;
		unsigned cp = n == 2 ? (c & 0x1F) : n == 3 ? (c & 0x0F) : (c & 0x07);
		for (std::size_t k = 1; k < n; ++k) {
			const unsigned char d = static_cast<unsigned char>(s[i + k]);
			if ((d & 0xC0) != 0x80) return false;
			cp = (cp << 6) | (d & 0x3F);
		}
		if ((n == 3 && (cp < 0x800 || (cp >= 0xD800 && cp < 0xE000))) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF))) return false;
		if (cp >= 0x80 && cp < 0xA0) return false;
		i += n;
	}
	return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string in(reinterpret_cast<const char*>(data), size);
	const std::size_t bound = size ? data[0] % 64 + 4 : 10;
	const std::string q = safeQuote(in, bound), line = safeLine(in, 200), all = safeQuote(in, std::string::npos);
	TALKHEAD_FUZZ_CHECK(printable(q) && q.size() <= bound + 3, q);  // "…" is 3 bytes
	TALKHEAD_FUZZ_CHECK(printable(line) && line.size() <= 210, line);
	TALKHEAD_FUZZ_CHECK(printable(all), all);
	fuzz::expectOnlyErrors([&] {
		const std::string d = decodeText(in);
		TALKHEAD_FUZZ_CHECK(printable(safeQuote(d, std::string::npos)), d);
	});
	return 0;
}
