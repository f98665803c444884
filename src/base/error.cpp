// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/error.h"

namespace talkhead {

static std::string located(const std::string& file, long line, const std::string& message) {
	std::string s = file;
	if (line > 0) s += ":" + std::to_string(line);
	return s + ": " + message;
}

Error::Error(const std::string& file, long line, const std::string& message)
    : std::runtime_error(located(file, line, message)) {}

std::string wordFields(std::string m, const std::function<std::optional<std::string>(const std::string& field)>& word) {
	for (std::size_t from = 0;;) {
		const std::size_t p = m.find("{{", from);
		if (p == std::string::npos) return m;
		const std::size_t q = m.find("}}", p + 2);
		if (q == std::string::npos) return m;
		const std::string field = m.substr(p + 2, q - p - 2);
		// A field's name is lower-case letters, digits, '-' and '_' (a quoted label with braces is not one).
		bool name = !field.empty() && field[0] >= 'a' && field[0] <= 'z';
		for (char c : field) name = name && ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_');
		if (!name) {
			from = p + 2;
			continue;
		}
		if (const std::optional<std::string> w = word(field)) {
			m.replace(p, q + 2 - p, *w);
			from = p + w->size();
			continue;
		}
		// The clause that suggests the field: from the unmatched '(' or ';' before it to the ')' or ';' after it.
		std::size_t left = std::string::npos;
		int depth = 0;
		for (std::size_t i = p; i-- > 0;) {
			if (m[i] == ')') ++depth;
			else if (m[i] == '(' && depth-- == 0) { left = i; break; }
			else if (m[i] == ';' && depth == 0) { left = i; break; }
		}
		std::size_t right = m.size();
		depth = 0;
		for (std::size_t i = q + 2; i < m.size(); ++i) {
			if (m[i] == '(') ++depth;
			else if (m[i] == ')' && depth-- == 0) { right = i; break; }
			else if (m[i] == ';' && depth == 0) { right = i; break; }
		}
		if (left == std::string::npos) {  // the whole message is about the field: its bare name
			m.replace(p, q + 2 - p, field);
			from = p + field.size();
		} else if (m[left] == '(' && right < m.size() && m[right] == ')') {  // "(…)" whole, with the space before it
			const std::size_t start = left > 0 && m[left - 1] == ' ' ? left - 1 : left;
			m.erase(start, right + 1 - start);
			from = start;
		} else {
			m.erase(left, right - left);
			from = left;
		}
	}
}

std::string describeException(const std::exception& e) {
	std::string s = e.what();
	try {
		std::rethrow_if_nested(e);
	} catch (const std::exception& inner) {
		s += ": " + describeException(inner);
	} catch (...) {
		s += ": unknown error";
	}
	return s;
}

}  // namespace talkhead
