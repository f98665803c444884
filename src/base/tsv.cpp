// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/tsv.h"

#include "base/error.h"
#include "base/text.h"

namespace talkhead {

std::size_t TsvTable::column(const std::string& name) const {
	for (std::size_t i = 0; i < header.size(); ++i)
		if (header[i] == name) return i;
	throw Error(path, 0, "missing column '" + name + "'");
}

double TsvTable::number(const Row& row, std::size_t col, double min, double max) const {
	double v;
	if (!parseDouble(row.fields.at(col), v) || v < min || v > max)
		throw Error(path, row.line, "column '" + header.at(col) + "': expected a number from " + std::to_string(min) + " to " +
		                                std::to_string(max) + ", found '" + row.fields.at(col) + "'");
	return v;
}

TsvTable parseTsv(const std::string& text, const std::string& path) {
	TsvTable t;
	t.path = path;
	long lineNo = 0;
	for (std::string line : split(text, '\n')) {
		++lineNo;
		if (!line.empty() && line.back() == '\r') line.pop_back();
		if (lineNo == 1 && startsWith(line, "\xEF\xBB\xBF")) line.erase(0, 3);
		if (trim(line).empty() || trim(line)[0] == '#') continue;
		auto fields = split(line, '\t');
		for (auto& f : fields) f = std::string(trim(f));
		if (t.header.empty()) {
			t.header = fields;
			continue;
		}
		if (fields.size() != t.header.size())
			throw Error(path, lineNo, "expected " + std::to_string(t.header.size()) + " tab-separated fields, found " + std::to_string(fields.size()));
		t.rows.push_back({lineNo, std::move(fields)});
	}
	if (t.header.empty()) throw Error(path, 0, "empty table (no header line)");
	return t;
}

TsvTable readTsv(const std::string& path) { return parseTsv(readTextFile(path), path); }

}  // namespace talkhead
