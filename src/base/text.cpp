// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/text.h"

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
	return ss.str();
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

}  // namespace talkhead
