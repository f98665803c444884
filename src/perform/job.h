// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace talkhead {

// A job as named fields (issue 46): what a front end asks a command to do, in the command's own words —
// the names render, say, visemes, build and batch read ("transcript", "emotion", "no-audio", "output").
// A batch row (stimuli/batch.h) becomes one, Python's keywords become one, and its JSON (jobJson) is what
// batch hands each child process and what `talkhead job FILE` runs: any program can write one. The library
// never spells a command-line flag; the command line reads the fields as its options.
struct JobField {
	std::string field;
	std::optional<std::string> value;  // nullopt: a switch ("no-audio")
	friend bool operator==(const JobField& a, const JobField& b) { return a.field == b.field && a.value == b.value; }
};

struct Job {
	std::string command;           // "render", "say", …
	std::vector<JobField> fields;  // in order; a field given more than once repeats ("components")
};

// The value of `field`, nullopt when absent (a switch's value is ""); the last when repeated.
std::optional<std::string> jobValue(const std::vector<JobField>& fields, const std::string& field);

// A job as JSON, one line: {"command": "render", "fields": {"transcript": "a.TextGrid", "no-audio": true,
// "components": ["mouth=4", "eyes=2"]}} — a switch is true, a repeated field an array of its values, in
// the order given.
std::string jobJson(const Job& job);

// Reads jobJson's form, named `name` in errors. Besides what jobJson writes, a value may be a number
// (written as given), false or null (the field left out); a field name is lower-case letters, digits and
// '-'. Throws Error("NAME: …") naming the member that is wrong.
Job parseJob(const std::string& text, const std::string& name);

}  // namespace talkhead
