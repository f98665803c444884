// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace talkhead::cli {

// A usage error: printed with a hint to --help, exit code 2.
class UsageError : public std::runtime_error {
public:
	using std::runtime_error::runtime_error;
};

// "1280x720" → width, height; throws UsageError naming the option unless both are in [minSide, max] and,
// when evenOnly, even (H.264's 4:2:0 needs even sizes).
void parseSize(const std::string& option, const std::string& value, int& width, int& height, int minSide = 16, bool evenOnly = true);

struct OptionSpec {
	std::string name;  // "--components"
	std::string value; // value placeholder ("N"); empty = flag
	std::string help;
	std::string shortName = "";  // "-o"
};

// Minimal GNU-style parser: --name VALUE, --name=VALUE, -o VALUE, flags, positionals, "--" ends options.
class Args {
public:
	Args(std::string command, std::string synopsis, std::vector<OptionSpec> options, std::string description = "");
	// Throws UsageError. Returns false when --help was asked for (help already printed).
	bool parse(const std::vector<std::string>& argv);
	std::string help() const;

	bool has(const std::string& name) const { return values_.count(name) > 0; }
	std::optional<std::string> get(const std::string& name) const;
	std::string get(const std::string& name, const std::string& fallback) const;
	// Every value of an option given more than once, in order (get() is the last).
	std::vector<std::string> all(const std::string& name) const;
	double number(const std::string& name, double fallback, double min, double max) const;
	const std::vector<std::string>& positionals() const { return positionals_; }
	// The one positional argument; UsageError("COMMAND: " + what) when there is not exactly one.
	const std::string& onePositional(const std::string& what) const;
	// The value of a required option; UsageError("COMMAND: " + what) when it is not given.
	std::string required(const std::string& name, const std::string& what) const;

private:
	const OptionSpec* find(const std::string& token) const;
	std::string command_, synopsis_, description_;
	std::vector<OptionSpec> options_;
	std::map<std::string, std::string> values_;
	std::map<std::string, std::vector<std::string>> every_;
	std::vector<std::string> positionals_;
};

}  // namespace talkhead::cli
