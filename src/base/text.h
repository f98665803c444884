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
// One CSV record split on commas, honouring double quotes ("a,b" and "" escapes).
std::vector<std::string> splitCsvRecord(const std::string& line);
// Whole file as bytes; throws Error("PATH: cannot read file: reason").
std::string readTextFile(const std::string& path);
// Strict number parsing of the whole (trimmed) string; false on garbage, NaN or infinity.
bool parseDouble(std::string_view s, double& out);
bool parseInt(std::string_view s, long long& out);
bool startsWith(std::string_view s, std::string_view prefix);
bool endsWith(std::string_view s, std::string_view suffix);
std::string toLower(std::string_view s);
// Appends the UTF-8 encoding of a code point.
void appendUtf8(unsigned codePoint, std::string& out);

}  // namespace talkhead
