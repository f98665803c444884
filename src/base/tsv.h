// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

namespace talkhead {

// A tab-separated data table (the project's language and corpus data files): '#' starts a comment
// line, blank lines are skipped, the first other line is the header. Every row must have the header's
// number of fields; errors name the file and line.
struct TsvTable {
	std::string path;
	std::vector<std::string> header;
	struct Row {
		long line;
		std::vector<std::string> fields;
	};
	std::vector<Row> rows;

	// Column index by name; throws Error naming the file when it is missing.
	std::size_t column(const std::string& name) const;
	// Field as a number in [min, max]; throws Error("file:line: …").
	double number(const Row& row, std::size_t column, double min, double max) const;
};

TsvTable readTsv(const std::string& path);
TsvTable parseTsv(const std::string& text, const std::string& path);

}  // namespace talkhead
