// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <stdexcept>
#include <string>

namespace talkhead {

// A fault in user input or data files: a missing or malformed file, an unknown label, a corrupt model.
// The CLI prints it as one line and exits 1. Programming errors use std::logic_error instead.
class Error : public std::runtime_error {
public:
	explicit Error(const std::string& message) : std::runtime_error(message) {}
	// "FILE:LINE: message" (line 0 = no line).
	Error(const std::string& file, long line, const std::string& message);
};

// Flattens a chain of nested exceptions (std::throw_with_nested) into "outer: inner: innermost".
std::string describeException(const std::exception& e);

}  // namespace talkhead
