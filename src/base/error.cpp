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
