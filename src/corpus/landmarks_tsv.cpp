// SPDX-License-Identifier: GPL-3.0-or-later
// The landmarks TSV (corpus/landmarks_tsv.h): one dialect written, three read.
#include "corpus/landmarks_tsv.h"

#include <cstdio>

#include "base/error.h"
#include "base/text.h"

namespace talkhead {

std::string landmarksTsvHeader(const std::vector<std::string>& pointNames) {
	std::string h = "frame\ttime\tstatus\tconfidence";
	for (const std::string& n : pointNames) h += "\t" + n + "_x\t" + n + "_y";
	return h + "\n";
}

void appendLandmarksTsvRow(std::string& out, const LandmarkRow& row, std::size_t pointCount) {
	char buf[96];
	const bool lost = row.points.rows() == 0;
	out.append(buf, std::size_t(std::snprintf(buf, sizeof buf, "%lld\t%.6f\t%s\t%.3f", (long long)row.frame, toSeconds(row.time), row.status.c_str(),
	                                          lost ? 0.0 : row.confidence)));
	for (std::size_t i = 0; i < pointCount; ++i) {
		if (lost) {
			out += "\t\t";
			continue;
		}
		const Eigen::Index k = Eigen::Index(i);
		out.append(buf, std::size_t(std::snprintf(buf, sizeof buf, "\t%.3f\t%.3f", row.points(k, 0), row.points(k, 1))));
	}
	out += '\n';
}

namespace {

// The header's dialect: where the points start, and their names.
struct Header {
	bool status = false;  // status and confidence columns
	bool indices = false;  // x0 y0 …
	std::vector<std::string> names;
};

Header readHeader(const std::string& line, const std::string& path) {
	const std::vector<std::string> c = split(line, '\t');
	Header h;
	if (c.size() < 2 || c[0] != "frame" || c[1] != "time")
		throw Error(path, 1, "not a talkhead landmarks.tsv (header frame, time, status, confidence, then x and y per point)");
	h.status = c.size() >= 4 && c[2] == "status" && c[3] == "confidence";
	const std::size_t first = h.status ? 4 : 2;
	if ((c.size() - first) % 2 != 0 || c.size() == first) throw Error(path, 1, "not a talkhead landmarks.tsv: its point columns do not come in x, y pairs");
	h.indices = h.status && c[first] == "x0";
	for (std::size_t i = first; i < c.size(); i += 2) {
		const std::size_t k = (i - first) / 2;
		std::string name;
		if (h.indices) {
			if (c[i] != "x" + std::to_string(k) || c[i + 1] != "y" + std::to_string(k)) throw Error(path, 1, "column '" + safeQuote(c[i]) + "': expected x" + std::to_string(k));
			name = std::to_string(k);
		} else {
			if (!endsWith(c[i], "_x") || c[i + 1] != c[i].substr(0, c[i].size() - 2) + "_y")
				throw Error(path, 1, "columns '" + safeQuote(c[i]) + "', '" + safeQuote(c[i + 1]) + "': expected NAME_x, NAME_y");
			name = c[i].substr(0, c[i].size() - 2);
		}
		h.names.push_back(name);
	}
	return h;
}

}  // namespace

LandmarksTable parseLandmarksTsv(const std::string& text, const std::string& path) {
	LandmarksTable t;
	const std::vector<std::string> lines = split(text, '\n');
	if (lines.empty() || lines[0].empty()) throw Error(path, 1, "not a talkhead landmarks.tsv (header frame, time, status, confidence, then x and y per point)");
	const Header h = readHeader(lines[0], path);
	t.pointNames = h.names;
	t.iBugIndices = h.indices;
	const std::size_t first = h.status ? 4 : 2, columns = first + 2 * h.names.size();
	for (std::size_t n = 1; n < lines.size(); ++n) {
		const long line = long(n + 1);
		if (lines[n].empty()) continue;
		const std::vector<std::string> c = split(lines[n], '\t');
		if (c.size() != columns) throw Error(path, line, "expected " + std::to_string(columns) + " columns, found " + std::to_string(c.size()));
		// Whole fields, finite and in range (what the writer can write back: a coordinate of 1e100 pixels
		// overflowed a "%.3f" buffer once, and stod took "nan", "inf" and "12abc").
		auto number = [&](const std::string& s, double lo, double hi, const char* what) {
			double v;
			if (!parseDouble(s, v)) throw Error(path, line, "malformed number '" + s.substr(0, 40) + "' (" + what + ")");
			if (v < lo || v > hi) throw Error(path, line, "number out of range: " + s.substr(0, 40) + " (" + what + ")");
			return v;
		};
		LandmarkRow r;
		long long frame;
		if (!parseInt(c[0], frame) || frame < 0) throw Error(path, line, "malformed number '" + c[0].substr(0, 40) + "' (frame index)");
		r.frame = frame;
		r.time = ticksFromSeconds(number(c[1], -86400, 86400, "time: seconds, at most a day"));
		if (h.status) {
			r.status = c[2];
			if (r.status != "detected" && r.status != "tracked" && r.status != "lost" && r.status != "drawn")
				throw Error(path, line, "status '" + safeQuote(r.status) + "' is none of detected, tracked, lost, drawn");
			r.confidence = number(c[3], 0, 1, "confidence: 0 to 1");
		}
		if (r.status != "lost") {
			r.points.resize(Eigen::Index(h.names.size()), 2);
			for (std::size_t i = 0; i < h.names.size(); ++i)
				for (int d = 0; d < 2; ++d) r.points(Eigen::Index(i), d) = number(c[first + 2 * i + std::size_t(d)], -1e6, 1e6, "a coordinate: pixels, at most 10^6");
		}
		t.rows.push_back(std::move(r));
	}
	if (t.rows.empty()) throw Error(path, 0, "no frames");
	return t;
}

}  // namespace talkhead
