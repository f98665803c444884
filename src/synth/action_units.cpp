// SPDX-License-Identifier: GPL-3.0-or-later
#include "synth/action_units.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/text.h"
#include "base/tsv.h"
#include "phonetics/emotion.h"
#include "phonetics/labels.h"
#include "geometry/eigen_products.h"

namespace talkhead {

int AuTemplates::find(const std::string& au) const {
	for (std::size_t i = 0; i < names.size(); ++i)
		if (names[i] == au) return int(i);
	return -1;
}

const std::vector<std::string>& knownActionUnits() {
	static const std::vector<std::string> known = {"AU1",  "AU2",  "AU4",  "AU5",  "AU6",  "AU7",  "AU9",  "AU10", "AU12", "AU15",
	                                               "AU16", "AU17", "AU20", "AU23", "AU24", "AU25", "AU26", "AU43", "AU45"};
	return known;
}

std::optional<std::string> canonicalActionUnit(const std::string& name) {
	std::string digits = name;
	if (digits.size() > 2 && (digits[0] == 'A' || digits[0] == 'a') && (digits[1] == 'U' || digits[1] == 'u')) digits = digits.substr(2);
	if (digits.empty() || digits.size() > 2 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
		return std::nullopt;
	const std::string au = "AU" + std::to_string(std::stoi(digits));
	const auto& known = knownActionUnits();
	if (std::find(known.begin(), known.end(), au) == known.end()) return std::nullopt;
	return au;
}

std::map<std::string, AuProfile> loadAuProfiles(const std::string& path) {
	const TsvTable t = readTsv(path);
	const std::size_t ce = t.column("emotion");
	std::vector<std::pair<std::string, std::size_t>> columns;
	for (std::size_t c = 0; c < t.header.size(); ++c)
		if (t.header[c].rfind("AU", 0) == 0) {
			const auto au = canonicalActionUnit(t.header[c]);
			if (!au) throw Error(path, 0, "unknown action unit column '" + t.header[c] + "'");
			columns.emplace_back(*au, c);
		}
	std::map<std::string, AuProfile> out;
	for (const auto& r : t.rows) {
		const auto emotion = canonicalEmotion(r.fields[ce]);
		if (!emotion) throw Error(path, r.line, "unknown emotion '" + r.fields[ce] + "'");
		AuProfile p;
		for (const auto& [au, c] : columns) {
			const double v = t.number(r, c, 0, 1);
			if (v > 0) p.emplace_back(au, v);
		}
		out[*emotion] = p;
	}
	return out;
}

const std::map<std::string, AuProfile>& defaultAuProfiles() {
	static const std::map<std::string, AuProfile> profiles = [] {
		const auto path = findDataFile("corpus-tools/data/expression-aus.tsv");
		if (!path) throw Error("data file 'corpus-tools/data/expression-aus.tsv' not found");
		return loadAuProfiles(*path);
	}();
	return profiles;
}

AuTemplates parseAuTemplates(const std::string& text, const std::string& path, const Scheme& scheme) {
	const TsvTable t = parseTsv(text, path);
	const std::size_t ca = t.column("au"), cp = t.column("point"), cx = t.column("dx"), cy = t.column("dy");
	AuTemplates out;
	out.scheme = scheme.name;
	std::vector<std::vector<bool>> seen;
	for (const auto& r : t.rows) {
		const auto au = canonicalActionUnit(r.fields[ca]);
		if (!au) throw Error(path, r.line, "unknown action unit '" + r.fields[ca] + "'");
		const int point = scheme.indexOf(r.fields[cp]);
		if (point < 0) throw Error(path, r.line, "point '" + r.fields[cp] + "' is not in scheme " + scheme.name);
		int a = out.find(*au);
		if (a < 0) {
			a = int(out.names.size());
			out.names.push_back(*au);
			out.offsets.push_back(Points::Zero(scheme.pointCount(), 2));
			seen.emplace_back(std::size_t(scheme.pointCount()), false);
		}
		if (seen[std::size_t(a)][std::size_t(point)]) throw Error(path, r.line, *au + " " + r.fields[cp] + " given twice");
		seen[std::size_t(a)][std::size_t(point)] = true;
		out.offsets[std::size_t(a)](point, 0) = t.number(r, cx, -2, 2);
		out.offsets[std::size_t(a)](point, 1) = t.number(r, cy, -2, 2);
	}
	for (std::size_t a = 0; a < out.names.size(); ++a)
		for (int p = 0; p < scheme.pointCount(); ++p)
			if (!seen[a][std::size_t(p)]) throw Error(path, 0, out.names[a] + " has no row for point " + scheme.pointNames[std::size_t(p)]);
	if (out.names.empty()) throw Error(path, 0, "no templates");
	return out;
}

std::string formatAuTemplates(const AuTemplates& t, const Scheme& scheme, const std::string& comment) {
	std::string s;
	for (std::size_t a = 0, b; a < comment.size(); a = b + 1) {
		b = comment.find('\n', a);
		if (b == std::string::npos) b = comment.size();
		s += "# " + comment.substr(a, b - a) + "\n";
	}
	s += "au\tpoint\tdx\tdy\n";
	char buf[96];
	for (std::size_t a = 0; a < t.names.size(); ++a)
		for (int p = 0; p < scheme.pointCount(); ++p) {
			auto r = [](double v) { return std::round(v * 1e4) / 1e4 + 0.0; };  // no "-0.0000"
			std::snprintf(buf, sizeof buf, "\t%.4f\t%.4f\n", r(t.offsets[a](p, 0)), r(t.offsets[a](p, 1)));
			s += t.names[a] + "\t" + scheme.pointNames[std::size_t(p)] + buf;
		}
	return s;
}

std::optional<AuTemplates> findAuTemplates(const Scheme& scheme) {
	const auto path = findDataFile("au-templates/" + scheme.name + ".tsv");
	if (!path) return std::nullopt;
	return parseAuTemplates(readTextFile(*path), *path, scheme);
}

EyeFrame eyeFrame(const Scheme& scheme, const Points& shape) {
	if (scheme.eyes.size() < 2) throw Error("scheme " + scheme.name + " names no two eyes ('eye' lines): action units need them");
	auto centre = [&](const EyeSpec& e) -> Eigen::RowVector2d { return 0.5 * (shape.row(e.corner0) + shape.row(e.corner1)); };
	Eigen::RowVector2d a = centre(scheme.eyes[0]), b = centre(scheme.eyes[1]);
	if (a(0) > b(0)) std::swap(a, b);
	EyeFrame f;
	f.origin = 0.5 * (a + b);
	f.iod = (b - a).norm();
	if (!(f.iod > 0)) throw Error("the eyes of the shape coincide: no eye frame");
	f.x = (b - a) / f.iod;
	f.y = Eigen::RowVector2d(-f.x(1), f.x(0));
	return f;
}

void applyActionUnits(Points& shape, const AuTemplates& t, const std::vector<AuWeight>& weights, const EyeFrame& frame) {
	for (const AuWeight& w : weights) {
		if (w.au < 0 || std::size_t(w.au) >= t.offsets.size() || w.weight == 0) continue;
		const Points& o = t.offsets[std::size_t(w.au)];
		for (Eigen::Index i = 0; i < shape.rows() && i < o.rows(); ++i) {
			double k = w.weight;
			if (w.side != 0) {
				const double along = (shape.row(i) - frame.origin).dot(frame.x) / frame.iod;
				k *= std::abs(along) < 0.05 ? 0.5 : (along * w.side > 0 ? 1.0 : 0.0);
			}
			if (k == 0) continue;
			shape.row(i) += k * frame.iod * (o(i, 0) * frame.x + o(i, 1) * frame.y);
		}
	}
}

std::vector<AuWeight> profileWeights(const AuTemplates& t, const AuProfile& profile, double intensity) {
	std::vector<AuWeight> w;
	for (const auto& [au, v] : profile)
		if (int a = t.find(au); a >= 0) w.push_back({a, v * intensity, 0});
	return w;
}

AuFit learnAuTemplates(const Scheme& scheme, const std::vector<LabelledShape>& shapes, const std::map<std::string, AuProfile>& profiles) {
	const int k = scheme.pointCount();
	// The rigid points: the scheme's heaviest weight class (eye corners, nose tip, ears, head top).
	const double heaviest = scheme.weights.maxCoeff();
	Eigen::VectorXd rigid = (scheme.weights.array() >= heaviest).cast<double>();
	// The AUs any profile of a non-neutral emotion uses.
	std::vector<std::string> aus;
	for (const auto& au : knownActionUnits())
		for (const auto& [emotion, p] : profiles)
			if (emotion != Emotion::neutralLabel() && std::any_of(p.begin(), p.end(), [&](const auto& x) { return x.first == au && x.second > 0; }) &&
			    std::find(aus.begin(), aus.end(), au) == aus.end())
				aus.push_back(au);
	AuFit fit;
	for (const auto& au : knownActionUnits())
		if (std::find(aus.begin(), aus.end(), au) == aus.end() && au != "AU45") fit.unused.push_back(au);
	// Neutral shape per CDV (the first).
	std::map<std::string, const Points*> neutral;
	for (const auto& s : shapes)
		if (s.emotion == Emotion::neutralLabel() && !neutral.count(s.cdv)) neutral[s.cdv] = &s.points;
	std::vector<Eigen::RowVectorXd> rows, targets;
	for (const auto& s : shapes) {
		if (s.emotion == Emotion::neutralLabel() || !profiles.count(s.emotion) || !neutral.count(s.cdv)) continue;
		if (s.points.rows() != k) throw Error("shape of " + s.emotion + " " + s.cdv + " has " + std::to_string(s.points.rows()) + " points, the scheme " + std::to_string(k));
		const Points& n = *neutral.at(s.cdv);
		const Points aligned = alignSimilarity(s.points, n, rigid).apply(s.points);
		const EyeFrame f = eyeFrame(scheme, n);
		Eigen::RowVectorXd d(2 * k);
		for (int i = 0; i < k; ++i) {
			const Eigen::RowVector2d v = (aligned.row(i) - n.row(i)) / f.iod;
			d(2 * i) = v.dot(f.x);
			d(2 * i + 1) = v.dot(f.y);
		}
		Eigen::RowVectorXd a = Eigen::RowVectorXd::Zero(Eigen::Index(aus.size()));
		for (const auto& [au, v] : profiles.at(s.emotion))
			if (auto it = std::find(aus.begin(), aus.end(), au); it != aus.end()) a(it - aus.begin()) = v;
		rows.push_back(a);
		targets.push_back(d);
	}
	if (rows.size() < aus.size() || aus.empty())
		throw Error("too few labelled shapes to learn action-unit templates: " + std::to_string(rows.size()) + " (emotion, CDV) shapes with a neutral of the same CDV for " +
		            std::to_string(aus.size()) + " action units");
	const Eigen::Index m = Eigen::Index(rows.size()), na = Eigen::Index(aus.size());
	Eigen::MatrixXd A(m, na), D(m, 2 * k);
	for (Eigen::Index i = 0; i < m; ++i) A.row(i) = rows[std::size_t(i)], D.row(i) = targets[std::size_t(i)];
	// Ridge least squares: a small penalty keeps AUs that always occur together from trading off wildly.
	const double ridge = 1e-3 * double(m);
	pinEigenBlocking();  // products that round the same on every machine (D74)
	const Eigen::MatrixXd T = (A.transpose() * A + ridge * Eigen::MatrixXd::Identity(na, na)).ldlt().solve(A.transpose() * D);
	const Eigen::MatrixXd R = A * T - D;
	fit.pairs = std::size_t(m);
	fit.rmsData = std::sqrt(D.squaredNorm() / double(D.size()));
	fit.rmsResidual = std::sqrt(R.squaredNorm() / double(R.size()));
	fit.templates.scheme = scheme.name;
	for (Eigen::Index a = 0; a < na; ++a) {
		fit.templates.names.push_back(aus[std::size_t(a)]);
		Points o(k, 2);
		for (int i = 0; i < k; ++i) o(i, 0) = T(a, 2 * i), o(i, 1) = T(a, 2 * i + 1);
		fit.templates.offsets.push_back(o);
	}
	return fit;
}

}  // namespace talkhead
