// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/scheme.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/text.h"

namespace talkhead {

int Scheme::indexOf(const std::string& n) const {
	for (std::size_t i = 0; i < pointNames.size(); ++i)
		if (pointNames[i] == n) return int(i);
	return -1;
}

namespace {

// region NAME [grow=X] [feather=X] : POINT POINT …   (a point, or A>B@T)
RegionSpec parseRegion(const Scheme& s, const std::vector<std::string>& f, const std::string& file, long ln) {
	RegionSpec r;
	if (f.size() < 2) throw Error(file, ln, "expected 'region NAME [grow=X] [feather=X] : POINT POINT …'");
	r.name = f[1];
	std::size_t i = 2;
	for (; i < f.size() && f[i] != ":"; ++i) {
		auto eq = f[i].find('=');
		double v;
		if (eq == std::string::npos || !parseDouble(f[i].substr(eq + 1), v))
			throw Error(file, ln, "bad region option '" + f[i] + "' (expected grow=X or feather=X)");
		std::string key = f[i].substr(0, eq);
		if (key == "grow") r.grow = v;
		else if (key == "feather") r.feather = v;
		else throw Error(file, ln, "unknown region option '" + key + "'");
	}
	if (i == f.size()) throw Error(file, ln, "region '" + r.name + "': missing ':' before the boundary points");
	std::set<std::pair<int, int>> seen;
	for (++i; i < f.size(); ++i) {
		// A point, or A>B@T: the point T of the way from A to B (T < 0: beyond A, away from B).
		std::string a = f[i], b;
		double t = 0;
		if (auto gt = f[i].find('>'); gt != std::string::npos) {
			auto at = f[i].find('@', gt);
			a = f[i].substr(0, gt);
			b = f[i].substr(gt + 1, at == std::string::npos ? std::string::npos : at - gt - 1);
			if (at == std::string::npos || !parseDouble(f[i].substr(at + 1), t) || !(t >= -3 && t <= 3) || t == 0 || t == 1)
				throw Error(file, ln, "region '" + r.name + "': bad boundary point '" + f[i] + "' (expected A>B@T with −3 ≤ T ≤ 3, T not 0 or 1)");
		}
		int idx = s.indexOf(a), other = b.empty() ? -1 : s.indexOf(b);
		if (idx < 0) throw Error(file, ln, "region '" + r.name + "': unknown point '" + a + "'");
		if (!b.empty() && (other < 0 || other == idx)) throw Error(file, ln, "region '" + r.name + "': bad second point '" + b + "' in '" + f[i] + "'");
		if (!seen.insert({idx, other}).second) throw Error(file, ln, "region '" + r.name + "': point '" + f[i] + "' repeated");
		r.boundary.push_back(idx);
		r.towards.push_back(other);
		r.fraction.push_back(t);
	}
	if (r.boundary.size() < 3) throw Error(file, ln, "region '" + r.name + "' needs at least 3 boundary points");
	if (r.grow <= -1 || r.feather < 0) throw Error(file, ln, "region '" + r.name + "': grow must be > −1 and feather ≥ 0");
	return r;
}

// eye NAME corners A B upper P … lower Q …  (lid points ordered from corner A to corner B)
EyeSpec parseEye(const Scheme& s, const std::vector<std::string>& f, const std::string& file, long ln) {
	const std::string usage = "expected 'eye NAME corners A B upper P … lower Q …'";
	if (f.size() < 2) throw Error(file, ln, usage);
	EyeSpec e;
	e.name = f[1];
	std::vector<int>* list = nullptr;
	std::vector<int> corners;
	for (std::size_t i = 2; i < f.size(); ++i) {
		if (f[i] == "corners") list = &corners;
		else if (f[i] == "upper") list = &e.upper;
		else if (f[i] == "lower") list = &e.lower;
		else if (!list) throw Error(file, ln, usage);
		else {
			const int idx = s.indexOf(f[i]);
			if (idx < 0) throw Error(file, ln, "eye '" + e.name + "': unknown point '" + f[i] + "'");
			list->push_back(idx);
		}
	}
	if (corners.size() != 2 || e.upper.empty() || e.lower.empty())
		throw Error(file, ln, "eye '" + e.name + "': needs 2 corners and at least one upper and one lower lid point");
	e.corner0 = corners[0], e.corner1 = corners[1];
	return e;
}

// mouth inner U:L … corners A B  (facing inner-lip points, upper then lower)
MouthSpec parseMouth(const Scheme& s, const std::vector<std::string>& f, const std::string& file, long ln) {
	const std::string usage = "expected 'mouth inner UPPER:LOWER … corners A B'";
	MouthSpec m;
	std::vector<int> corners;
	int list = 0;  // 1 inner, 2 corners
	for (std::size_t i = 1; i < f.size(); ++i) {
		if (f[i] == "inner") list = 1;
		else if (f[i] == "corners") list = 2;
		else if (list == 0) throw Error(file, ln, usage);
		else if (list == 2) {
			const int idx = s.indexOf(f[i]);
			if (idx < 0) throw Error(file, ln, "mouth: unknown point '" + f[i] + "'");
			corners.push_back(idx);
		} else {
			const auto colon = f[i].find(':');
			const int a = colon == std::string::npos ? -1 : s.indexOf(f[i].substr(0, colon));
			const int b = colon == std::string::npos ? -1 : s.indexOf(f[i].substr(colon + 1));
			if (a < 0 || b < 0 || a == b) throw Error(file, ln, "mouth: bad inner pair '" + f[i] + "' (expected UPPER:LOWER, two points of the scheme)");
			m.inner.emplace_back(a, b);
		}
	}
	if (m.inner.empty() || corners.size() != 2) throw Error(file, ln, "mouth: needs at least one inner pair and 2 corners");
	m.corner0 = corners[0], m.corner1 = corners[1];
	return m;
}

}  // namespace

Scheme parseScheme(const std::string& text, const std::string& file) {
	Scheme s;
	std::map<std::string, double> classes;
	std::vector<std::pair<long, std::vector<std::string>>> regionLines, eyeLines;
	std::vector<double> weights;
	long lineNo = 0;
	for (const std::string& raw : split(text, '\n')) {
		++lineNo;
		std::string line = raw.substr(0, raw.find('#'));
		auto f = splitWhitespace(line);
		if (f.empty()) continue;
		const std::string& kw = f[0];
		if (kw == "scheme") {
			if (f.size() != 2) throw Error(file, lineNo, "expected 'scheme NAME'");
			s.name = f[1];
		} else if (kw == "class") {
			double w;
			if (f.size() != 3 || !parseDouble(f[2], w) || w < 0) throw Error(file, lineNo, "expected 'class NAME WEIGHT' with WEIGHT ≥ 0");
			classes[f[1]] = w;
		} else if (kw == "point") {
			if (f.size() != 3) throw Error(file, lineNo, "expected 'point NAME CLASS'");
			auto c = classes.find(f[2]);
			if (c == classes.end()) throw Error(file, lineNo, "unknown weight class '" + f[2] + "' (declare it with 'class' first)");
			if (s.indexOf(f[1]) >= 0) throw Error(file, lineNo, "duplicate point name '" + f[1] + "'");
			s.pointNames.push_back(f[1]);
			s.pointClasses.push_back(f[2]);
			weights.push_back(c->second);
		} else if (kw == "region") {
			regionLines.emplace_back(lineNo, f);
		} else if (kw == "eye") {
			eyeLines.emplace_back(lineNo, f);
		} else if (kw == "brow") {
			if (f.size() < 4 || f[2] != ":") throw Error(file, lineNo, "expected 'brow NAME : INNER … OUTER'");
			BrowSpec b;
			b.name = f[1];
			for (std::size_t i = 3; i < f.size(); ++i) {
				const int idx = s.indexOf(f[i]);
				if (idx < 0) throw Error(file, lineNo, "brow '" + b.name + "': unknown point '" + f[i] + "'");
				b.points.push_back(idx);
			}
			if (b.points.size() < 2) throw Error(file, lineNo, "brow '" + b.name + "': needs at least 2 points");
			s.brows.push_back(std::move(b));
		} else if (kw == "mouth") {
			if (!s.mouth.empty()) throw Error(file, lineNo, "a second 'mouth' line");
			s.mouth = parseMouth(s, f, file, lineNo);
		} else {
			throw Error(file, lineNo, "unknown keyword '" + kw + "' (expected scheme, class, point, region, eye, brow or mouth)");
		}
	}
	if (s.name.empty()) throw Error(file, 0, "missing 'scheme NAME' line");
	if (s.pointNames.size() < 3) throw Error(file, 0, "a scheme needs at least 3 points");
	for (const auto& [ln, f] : regionLines) s.regions.push_back(parseRegion(s, f, file, ln));
	if (s.regions.empty()) throw Error(file, 0, "a scheme needs at least one region");
	for (const auto& [ln, f] : eyeLines) s.eyes.push_back(parseEye(s, f, file, ln));
	s.weights = Eigen::Map<Eigen::VectorXd>(weights.data(), Eigen::Index(weights.size()));
	if (!(s.weights.sum() > 0)) throw Error(file, 0, "all alignment weights are zero");
	return s;
}

Scheme loadSchemeFile(const std::string& path) { return parseScheme(readTextFile(path), path); }

Scheme loadScheme(const std::string& nameOrPath) {
	if (endsWith(nameOrPath, ".scheme") || nameOrPath.find('/') != std::string::npos) return loadSchemeFile(nameOrPath);
	if (auto p = findDataFile("schemes/" + nameOrPath + ".scheme")) return loadSchemeFile(*p);
	std::string known;
	for (const auto& n : availableSchemes()) known += (known.empty() ? "" : ", ") + n;
	throw Error("unknown landmark scheme '" + nameOrPath + "' (known: " + (known.empty() ? "none found" : known) + ")");
}

void completeSchemeParts(Scheme& s) {
	if (!s.eyes.empty() || !s.brows.empty() || !s.mouth.empty() || s.name.empty()) return;
	// Only a shipped scheme's plain name: a model file never names another file to read.
	if (!std::all_of(s.name.begin(), s.name.end(), [](char c) { return std::isalnum((unsigned char)c) || c == '-' || c == '_'; })) return;
	const auto path = findDataFile("schemes/" + s.name + ".scheme");
	if (!path) return;
	try {
		const Scheme shipped = loadSchemeFile(*path);
		if (shipped.pointNames != s.pointNames) return;
		s.eyes = shipped.eyes, s.brows = shipped.brows, s.mouth = shipped.mouth;
	} catch (const Error&) {
	}
}

std::vector<std::string> availableSchemes() {
	namespace fs = std::filesystem;
	for (const auto& d : dataDirs()) {
		std::error_code ec;
		fs::path dir = fs::path(d) / "schemes";
		if (!fs::is_directory(dir, ec)) continue;
		std::set<std::string> names;
		for (const auto& e : fs::directory_iterator(dir, ec))
			if (e.path().extension() == ".scheme") names.insert(e.path().stem().string());
		if (!names.empty()) return {names.begin(), names.end()};
	}
	return {};
}

Points regionBoundary(const RegionSpec& region, const Points& shape) {
	Points b(Eigen::Index(region.boundary.size()), 2);
	for (std::size_t i = 0; i < region.boundary.size(); ++i) {
		b.row(Eigen::Index(i)) = shape.row(region.boundary[i]);
		if (i < region.towards.size() && region.towards[i] >= 0)
			b.row(Eigen::Index(i)) += region.fraction[i] * (shape.row(region.towards[i]) - shape.row(region.boundary[i]));
	}
	return b;
}

}  // namespace talkhead
