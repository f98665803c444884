// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <stdexcept>
#include <functional>
#include <optional>
#include <string>
#include <utility>

namespace talkhead {

// A fault in user input or data files: a missing or malformed file, an unknown label, a corrupt model.
// The CLI prints it as one line and exits 1. Programming errors use std::logic_error instead.
class Error : public std::runtime_error {
public:
	explicit Error(const std::string& message) : std::runtime_error(message) {}
	// "FILE:LINE: message" (line 0 = no line).
	Error(const std::string& file, long line, const std::string& message);
};

// A value that is wrong, named by its field (what the command line calls a flag and serve a JSON member:
// "crf", "background", "output"). The message does not spell the field the way a front end does: each
// front end words it for its users (the CLI with its flag, serve with its member).
class FieldError : public Error {
public:
	FieldError(std::string field, const std::string& message) : Error(message), field_(std::move(field)) {}
	const std::string& field() const { return field_; }

private:
	std::string field_;
};

// A field named inside a message ("give the tier with {{tier}}"): the library names the field, not a flag;
// each front end words it (wordFields) — the command line as its flag (--tier), serve as the request's
// member where the request has one, leaving out the clause that suggests it where it has none.
inline std::string fieldRef(const std::string& field) { return "{{" + field + "}}"; }
// `message` with every {{field}} (a name of lower-case letters, digits, '-', '_') worded by `word`: its wording, or nullopt for a field this front end does not
// have — then the clause around it goes (from the '(' or ';' before it to the ')' or ';' after it; a
// message that is only about the field keeps the field's bare name).
std::string wordFields(std::string message, const std::function<std::optional<std::string>(const std::string& field)>& word);

// Flattens a chain of nested exceptions (std::throw_with_nested) into "outer: inner: innermost".
std::string describeException(const std::exception& e);

}  // namespace talkhead
