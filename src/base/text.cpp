// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/text.h"

#include <algorithm>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "base/error.h"

namespace talkhead {

std::string_view trim(std::string_view s) {
	while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
	while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
	return s;
}

std::vector<std::string> splitWhitespace(std::string_view s) {
	std::vector<std::string> out;
	std::size_t i = 0;
	while (i < s.size()) {
		while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
		std::size_t j = i;
		while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
		if (j > i) out.emplace_back(s.substr(i, j - i));
		i = j;
	}
	return out;
}

std::vector<std::string> split(std::string_view s, char sep) {
	std::vector<std::string> out;
	std::size_t start = 0;
	for (;;) {
		std::size_t p = s.find(sep, start);
		if (p == std::string_view::npos) {
			out.emplace_back(s.substr(start));
			return out;
		}
		out.emplace_back(s.substr(start, p - start));
		start = p + 1;
	}
}

std::string readTextFile(const std::string& path) {
	std::ifstream in(path, std::ios::binary);
	if (!in) throw Error(path, 0, std::string("cannot read file: ") + std::strerror(errno));
	std::ostringstream ss;
	ss << in.rdbuf();
	if (in.bad()) throw Error(path, 0, "read error");
	return decodeText(ss.str());
}

std::string decodeText(const std::string& in) {
	if (in.size() >= 3 && (unsigned char)in[0] == 0xEF && (unsigned char)in[1] == 0xBB && (unsigned char)in[2] == 0xBF) return in.substr(3);
	if (in.size() < 2) return in;
	const unsigned char b0 = in[0], b1 = in[1];
	bool le = b0 == 0xFF && b1 == 0xFE, be = b0 == 0xFE && b1 == 0xFF;
	std::size_t first = 2;
	if (!le && !be) {
		// No BOM: UTF-16 when, in the first 512 bytes, most code units have a NUL high byte (ASCII text:
		// headers, times) and the other byte is (almost) never NUL; LE has the NUL second, BE first.
		const std::size_t n = std::min<std::size_t>(in.size(), 512) & ~std::size_t(1), units = n / 2;
		std::size_t nulFirst = 0, nulSecond = 0;
		for (std::size_t i = 0; i < n; i += 2) {
			nulFirst += in[i] == '\0';
			nulSecond += in[i + 1] == '\0';
		}
		le = units >= 2 && nulSecond * 10 >= units * 6 && nulFirst * 20 <= units;
		be = units >= 2 && nulFirst * 10 >= units * 6 && nulSecond * 20 <= units;
		if (!le && !be) return in;
		first = 0;
	}
	std::string out;
	auto unit = [&](std::size_t i) -> unsigned {
		const unsigned char a = in[i], b = in[i + 1];
		return le ? unsigned(a | (b << 8)) : unsigned((a << 8) | b);
	};
	for (std::size_t i = first; i + 1 < in.size(); i += 2) {
		unsigned cp = unit(i);
		if (cp >= 0xD800 && cp < 0xDC00 && i + 3 < in.size()) {
			unsigned lo = unit(i + 2);
			if (lo >= 0xDC00 && lo < 0xE000) {
				cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
				i += 2;
			}
		}
		if (cp >= 0xD800 && cp < 0xE000) cp = 0xFFFD;  // a lone surrogate
		appendUtf8(cp, out);
	}
	return out;
}

namespace {

// The next character of s at i as it should appear in a message: its bytes (valid UTF-8, not a control
// character) or an escape; *len = the bytes it takes in s.
std::string safeChar(std::string_view s, std::size_t i, std::size_t* len) {
	const unsigned char c = static_cast<unsigned char>(s[i]);
	char b[12];
	*len = 1;
	if (c < 0x80) {
		if (c == '\n') return "\\n";
		if (c == '\r') return "\\r";
		if (c == '\t') return "\\t";
		if (c < 0x20 || c == 0x7F) {
			std::snprintf(b, sizeof b, "\\x%02x", c);
			return b;
		}
		return std::string(1, char(c));
	}
	// A UTF-8 sequence: its length from the lead byte, every continuation byte checked, no overlong form,
	// no surrogate, nothing past U+10FFFF.
	std::size_t n = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c <= 0xDF ? 2 : 0;
	if (c >= 0xF5) n = 0;
	unsigned cp = n == 2 ? (c & 0x1F) : n == 3 ? (c & 0x0F) : (c & 0x07);
	bool ok = n > 0 && i + n <= s.size();
	for (std::size_t k = 1; ok && k < n; ++k) {
		const unsigned char d = static_cast<unsigned char>(s[i + k]);
		ok = (d & 0xC0) == 0x80;
		cp = (cp << 6) | (d & 0x3F);
	}
	if (ok && ((n == 3 && (cp < 0x800 || (cp >= 0xD800 && cp < 0xE000))) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)))) ok = false;
	if (!ok) {
		std::snprintf(b, sizeof b, "\\x%02x", c);
		return b;
	}
	*len = n;
	if (cp >= 0x80 && cp < 0xA0) {  // C1 control characters
		std::snprintf(b, sizeof b, "\\u%04x", cp);
		return b;
	}
	return std::string(s.substr(i, n));
}

}  // namespace

std::string safeQuote(std::string_view s, std::size_t maxBytes) {
	std::string out;
	for (std::size_t i = 0, len = 0; i < s.size(); i += len) {
		const std::string c = safeChar(s, i, &len);
		if (out.size() + c.size() > maxBytes) return out + "…";
		out += c;
	}
	return out;
}

std::string safeLine(std::string_view s, std::size_t maxBytes) {
	std::string out = safeQuote(s, std::string::npos);
	if (out.size() <= maxBytes) return out;
	// Keep the start (what and where) and the end (often the reason), cut between characters.
	auto back = [&](std::size_t at) {
		while (at > 0 && (static_cast<unsigned char>(out[at]) & 0xC0) == 0x80) --at;
		return at;
	};
	const std::size_t head = back(maxBytes * 2 / 3), tail = back(out.size() - maxBytes / 3 + 5);
	return out.substr(0, head) + " … " + out.substr(tail);
}

bool parseDouble(std::string_view s, double& out) {
	s = trim(s);
	if (s.empty() || s.size() > 64) return false;
	std::string tmp(s);
	char* end = nullptr;
	errno = 0;
	double v = std::strtod(tmp.c_str(), &end);
	if (end != tmp.c_str() + tmp.size() || errno == ERANGE || !std::isfinite(v)) return false;
	out = v;
	return true;
}

bool parseInt(std::string_view s, long long& out) {
	s = trim(s);
	if (s.empty() || s.size() > 32) return false;
	std::string tmp(s);
	char* end = nullptr;
	errno = 0;
	long long v = std::strtoll(tmp.c_str(), &end, 10);
	if (end != tmp.c_str() + tmp.size() || errno == ERANGE) return false;
	out = v;
	return true;
}

bool startsWith(std::string_view s, std::string_view p) { return s.substr(0, p.size()) == p; }
bool endsWith(std::string_view s, std::string_view p) { return s.size() >= p.size() && s.substr(s.size() - p.size()) == p; }

void appendUtf8(unsigned cp, std::string& out) {
	if (cp < 0x80) {
		out += char(cp);
	} else if (cp < 0x800) {
		out += char(0xC0 | (cp >> 6));
		out += char(0x80 | (cp & 0x3F));
	} else if (cp < 0x10000) {
		out += char(0xE0 | (cp >> 12));
		out += char(0x80 | ((cp >> 6) & 0x3F));
		out += char(0x80 | (cp & 0x3F));
	} else {
		out += char(0xF0 | (cp >> 18));
		out += char(0x80 | ((cp >> 12) & 0x3F));
		out += char(0x80 | ((cp >> 6) & 0x3F));
		out += char(0x80 | (cp & 0x3F));
	}
}

std::string toLower(std::string_view s) {
	std::string r(s);
	for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
	return r;
}

// Splits one CSV record on commas, honouring double quotes ("a,b" and "" escapes).
std::vector<std::string> splitCsvRecord(const std::string& line) {
	std::vector<std::string> out;
	std::string cur;
	bool quoted = false;
	for (std::size_t i = 0; i < line.size(); ++i) {
		char c = line[i];
		if (quoted) {
			if (c == '"') {
				if (i + 1 < line.size() && line[i + 1] == '"') {
					cur += '"';
					++i;
				} else {
					quoted = false;
				}
			} else {
				cur += c;
			}
		} else if (c == '"') {
			quoted = true;
		} else if (c == ',') {
			out.push_back(cur);
			cur.clear();
		} else {
			cur += c;
		}
	}
	out.push_back(cur);
	return out;
}

std::string joined(const std::vector<std::string>& items, std::string_view sep) {
	std::string s;
	for (std::size_t i = 0; i < items.size(); ++i) {
		if (i) s += sep;
		s += items[i];
	}
	return s;
}

}  // namespace talkhead
