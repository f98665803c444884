// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace talkhead {

std::string_view trim(std::string_view s);
std::vector<std::string> splitWhitespace(std::string_view s);
// Splits on `sep`; no quoting.
std::vector<std::string> split(std::string_view s, char sep);
// The items with `sep` between them ("a, b, c").
std::string joined(const std::vector<std::string>& items, std::string_view sep = ", ");
// One CSV record split on commas, honouring double quotes ("a,b" and "" escapes).
std::vector<std::string> splitCsvRecord(const std::string& line);
// Whole file as UTF-8 text (decodeText: UTF-16 with or without a BOM converted, a UTF-8 BOM dropped);
// throws Error("PATH: cannot read file: reason").
std::string readTextFile(const std::string& path);
// UTF-16 (LE/BE, with a BOM, or without one when most code units of the first 512 bytes have a NUL high
// byte) → UTF-8; a UTF-8 BOM stripped; anything else unchanged.
std::string decodeText(const std::string& bytes);
// Input quoted in a message (issue 15): valid UTF-8 kept; control characters escaped (\n, \t, \r,
// \xNN, C1 as \u0085), invalid UTF-8 bytes as \xNN; at most maxBytes, cut between characters, "…" when
// cut. So a message is one line, valid UTF-8 and bounded whatever the input held.
std::string safeQuote(std::string_view s, std::size_t maxBytes = 60);
// A whole message line made safe the same way, cut in the middle (" … ") past maxBytes.
std::string safeLine(std::string_view s, std::size_t maxBytes = 1000);
// Strict number parsing of the whole (trimmed) string; false on garbage, NaN or infinity.
bool parseDouble(std::string_view s, double& out);
bool parseInt(std::string_view s, long long& out);
bool startsWith(std::string_view s, std::string_view prefix);
bool endsWith(std::string_view s, std::string_view suffix);
std::string toLower(std::string_view s);
// Appends the UTF-8 encoding of a code point.
void appendUtf8(unsigned codePoint, std::string& out);

}  // namespace talkhead
