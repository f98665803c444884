// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/args.h"

#include <iostream>
#include <sstream>

#include "base/text.h"

namespace talkhead::cli {

void parseSize(const std::string& option, const std::string& value, int& width, int& height, int minSide, bool evenOnly) {
	const auto x = value.find('x');
	long long w, h;
	if (x == std::string::npos || !parseInt(value.substr(0, x), w) || !parseInt(value.substr(x + 1), h) || w < minSide || h < minSide || w > 7680 ||
	    h > 4320 || (evenOnly && (w % 2 || h % 2)))
		throw UsageError(option + " must be " + (evenOnly ? "an even " : "") + "WIDTHxHEIGHT from " + std::to_string(minSide) + "x" +
		                 std::to_string(minSide) + " to 7680x4320, got '" + value + "'");
	width = int(w);
	height = int(h);
}

Args::Args(std::string command, std::string synopsis, std::vector<OptionSpec> options, std::string description)
    : command_(std::move(command)), synopsis_(std::move(synopsis)), description_(std::move(description)), options_(std::move(options)) {
	options_.push_back({"--help", "", "show this help and exit", "-h"});
}

const OptionSpec* Args::find(const std::string& token) const {
	for (const auto& o : options_)
		if (o.name == token || (!o.shortName.empty() && o.shortName == token)) return &o;
	return nullptr;
}

bool Args::parse(const std::vector<std::string>& argv) {
	bool optionsDone = false;
	for (std::size_t i = 0; i < argv.size(); ++i) {
		const std::string& a = argv[i];
		if (optionsDone || a == "-" || a.size() < 2 || a[0] != '-') {
			positionals_.push_back(a);
			continue;
		}
		if (a == "--") {
			optionsDone = true;
			continue;
		}
		std::string name = a, value;
		bool inlineValue = false;
		if (auto eq = a.find('='); startsWith(a, "--") && eq != std::string::npos) {
			name = a.substr(0, eq);
			value = a.substr(eq + 1);
			inlineValue = true;
		}
		const OptionSpec* o = find(name);
		if (!o) throw UsageError(command_ + ": unknown option '" + name + "'");
		if (o->name == "--help") {
			std::cout << help();
			return false;
		}
		if (o->value.empty()) {
			if (inlineValue) throw UsageError(command_ + ": option " + o->name + " takes no value");
			values_[o->name] = "1";
			continue;
		}
		if (!inlineValue) {
			if (i + 1 >= argv.size()) throw UsageError(command_ + ": option " + o->name + " needs a value (" + o->value + ")");
			value = argv[++i];
		}
		values_[o->name] = value;
		every_[o->name].push_back(value);
	}
	return true;
}

std::vector<std::string> Args::all(const std::string& name) const {
	auto it = every_.find(name);
	return it == every_.end() ? std::vector<std::string>{} : it->second;
}

std::string Args::help() const {
	std::ostringstream s;
	s << "usage: " << synopsis_ << "\n";
	if (!description_.empty()) s << "\n" << description_ << "\n";
	s << "\noptions:\n";
	for (const auto& o : options_) {
		std::string left = "  " + (o.shortName.empty() ? std::string() : o.shortName + ", ") + o.name + (o.value.empty() ? "" : " " + o.value);
		if (left.size() < 30) left += std::string(30 - left.size(), ' ');
		else left += "\n" + std::string(30, ' ');
		s << left << o.help << "\n";
	}
	return s.str();
}

std::optional<std::string> Args::get(const std::string& name) const {
	auto it = values_.find(name);
	if (it == values_.end()) return std::nullopt;
	return it->second;
}

const std::string& Args::onePositional(const std::string& what) const {
	if (positionals_.size() != 1) throw UsageError(command_ + ": " + what);
	return positionals_[0];
}

std::string Args::required(const std::string& name, const std::string& what) const {
	auto v = get(name);
	if (!v) throw UsageError(command_ + ": " + what);
	return *v;
}

std::string Args::get(const std::string& name, const std::string& fallback) const { return get(name).value_or(fallback); }

double Args::number(const std::string& name, double fallback, double min, double max) const {
	auto v = get(name);
	if (!v) return fallback;
	double d;
	if (!parseDouble(*v, d) || d < min || d > max) {
		std::ostringstream s;
		s << command_ << ": " << name << " must be a number from " << min << " to " << max << ", got '" << *v << "'";
		throw UsageError(s.str());
	}
	return d;
}

}  // namespace talkhead::cli
