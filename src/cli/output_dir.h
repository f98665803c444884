// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

namespace talkhead::cli {

// An output folder written as a whole: files go into a hidden sibling folder, which replaces-in (moves each
// file into) the target only when commit() is called, so a failure or a signal leaves no partial output.
class OutputDir {
public:
	explicit OutputDir(const std::string& target);
	~OutputDir();  // removes the staging folder unless committed
	OutputDir(const OutputDir&) = delete;
	OutputDir& operator=(const OutputDir&) = delete;
	// Path of a file (or sub-folder) inside the staging folder.
	std::string path(const std::string& name) const;
	void commit();

private:
	std::string target_, staging_;
	bool committed_ = false;
};

// "12.5" (seconds) or "1:02.5" (minutes:seconds) → seconds; throws UsageError naming the option.
double parseTimeOption(const std::string& option, const std::string& value);

}  // namespace talkhead::cli
