// SPDX-License-Identifier: GPL-3.0-or-later
#include "corpus/corpus.h"

#include <algorithm>
#include <filesystem>

#include "base/error.h"
#include "base/text.h"
#include "media/image_io.h"
#include "phonetics/labels.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {


std::string schemeForCount(int n) {
	switch (n) {
		case 56: return "ch-unicamp-56";
		case 68: return "ibug-68";
		case 73: return "imm-73";
		default: return "";
	}
}

std::string resolveImage(const fs::path& shapeFile, const std::string& name) {
	fs::path dir = shapeFile.parent_path();
	for (const fs::path& cand : {dir / name, dir.parent_path() / name}) {
		std::error_code ec;
		if (fs::is_regular_file(cand, ec)) return cand.string();
	}
	throw Error(shapeFile.string(), 0, "image '" + name + "' not found beside the shape file or one folder up");
}

// D36: a row labelled with an emotion gets canonical emotion and CDV labels (phonetics/emotions.tsv,
// visemes.tsv: aliases, "<p1>" for p1), or an error naming the row; emotion "-" marks an unlabelled row,
// whose CDV (an image stem, D11) is kept as written.
void readLabels(CorpusEntry& e, const std::string& emotion, const std::string& cdv, const std::string& path, long lineNo) {
	e.emotion.reset(), e.cdv.reset(), e.name.clear();
	if (emotion == "-") {
		e.name = cdv;
		return;
	}
	e.emotion = Emotion::find(emotion);
	if (!e.emotion) throw Error(path, lineNo, "unknown emotion '" + emotion + "' (known: " + emotionList() + "; '-' for an unlabelled row)");
	e.cdv = Cdv::find(cdv);
	if (!e.cdv) {
		std::string known;
		for (const auto& l : visemeLabels()) known += (known.empty() ? "" : " ") + l.label;
		throw Error(path, lineNo, "unknown viseme '" + cdv + "' (known: " + known + ", their ASCII aliases, with or without <>)");
	}
}

}  // namespace

void CorpusEntry::setLabels(const std::string& emotionColumn, const std::string& cdvColumn) {
	readLabels(*this, emotionColumn, cdvColumn, source.empty() ? imagePath : source, 0);
}

Corpus readChUnicampCsv(const std::string& path, int pointCount) {
	const std::string text = readTextFile(path);
	Corpus corpus;
	corpus.path = path;
	const fs::path dir = fs::path(path).parent_path();
	long lineNo = 0;
	for (std::string line : split(text, '\n')) {
		++lineNo;
		if (!line.empty() && line.back() == '\r') line.pop_back();
		if (lineNo == 1 && startsWith(line, "\xEF\xBB\xBF")) line.erase(0, 3);
		if (trim(line).empty()) continue;
		if (trim(line).front() == '#') {
			std::string_view c = trim(trim(line).substr(1));
			if (startsWith(std::string(c), "baseface:")) {
				const std::string image(trim(c.substr(9)));
				if (image.empty()) throw Error(path, lineNo, "'# baseface:' names no image");
				corpus.baseface = (fs::path(image).is_absolute() ? fs::path(image) : dir / image).string();
			} else if (startsWith(std::string(c), "closed-eyes:")) {
				const std::string image(trim(c.substr(12)));
				if (image.empty()) throw Error(path, lineNo, "'# closed-eyes:' names no image");
				corpus.closedEyes = (fs::path(image).is_absolute() ? fs::path(image) : dir / image).string();
			}
			continue;
		}
		auto f = splitCsvRecord(line);
		if (pointCount == 0) {
			const int n = int(f.size()) - 9;
			if (schemeForCount(n).empty())
				throw Error(path, lineNo, "expected image, emotion, 5 phones, CDV, word and 56, 68 or 73 points, found " + std::to_string(f.size()) + " columns");
			pointCount = n;
		}
		const std::size_t expected = 9 + std::size_t(pointCount);
		if (f.size() != expected)
			throw Error(path, lineNo, "expected " + std::to_string(expected) + " columns (image, emotion, 5 phones, CDV, word, " +
			                              std::to_string(pointCount) + " points), found " + std::to_string(f.size()));
		CorpusEntry e;
		e.source = path + ":" + std::to_string(lineNo);
		std::string image(trim(f[0]));
		if (image.empty()) throw Error(path, lineNo, "empty image name");
		e.imagePath = (fs::path(image).is_absolute() ? fs::path(image) : dir / image).string();
		const std::string emotion(trim(f[1])), cdv(trim(f[7]));
		for (int k = 0; k < 5; ++k) e.context[k] = std::string(trim(f[2 + k]));
		e.word = std::string(trim(f[8]));
		if (emotion.empty()) throw Error(path, lineNo, "empty emotion label");
		if (cdv.empty()) throw Error(path, lineNo, "empty CDV label");
		readLabels(e, emotion, cdv, path, lineNo);
		e.points.resize(pointCount, 2);
		for (int k = 0; k < pointCount; ++k) {
			std::string_view cell = trim(f[9 + k]);
			double x, y;
			bool ok = cell.size() >= 5 && cell.front() == '(' && cell.back() == ')';
			if (ok) {
				auto xy = split(cell.substr(1, cell.size() - 2), ';');
				ok = xy.size() == 2 && parseDouble(xy[0], x) && parseDouble(xy[1], y);
			}
			if (!ok)
				throw Error(path, lineNo, "column " + std::to_string(10 + k) + ": expected a point '(x;y)', found '" + std::string(cell) + "'");
			e.points(k, 0) = x;
			e.points(k, 1) = y;
		}
		corpus.entries.push_back(std::move(e));
	}
	if (corpus.entries.empty()) throw Error(path, 0, "the corpus file has no rows");
	corpus.schemeName = schemeForCount(pointCount);
	if (!corpus.baseface.empty() &&
	    std::none_of(corpus.entries.begin(), corpus.entries.end(), [&](const CorpusEntry& e) { return e.imagePath == corpus.baseface; }))
		throw Error(path, 0, "the baseface '" + corpus.baseface + "' is not one of the corpus's images");
	if (!corpus.closedEyes.empty()) {
		auto e = std::find_if(corpus.entries.begin(), corpus.entries.end(), [&](const CorpusEntry& x) { return x.imagePath == corpus.closedEyes; });
		if (e == corpus.entries.end()) throw Error(path, 0, "the closed-eyes image '" + corpus.closedEyes + "' is not one of the corpus's images");
		if (e->labelled()) throw Error(e->source + ": the closed-eyes image must be an unlabelled row (emotion '-'), so no keypose uses it");
	}
	return corpus;
}

CorpusEntry readAsf(const std::string& path) {
	const std::string text = readTextFile(path);
	std::vector<std::pair<long, std::string>> lines;  // non-comment, non-empty lines
	long lineNo = 0;
	for (std::string l : split(text, '\n')) {
		++lineNo;
		std::string t(trim(l));
		if (t.empty() || t[0] == '#') continue;
		lines.emplace_back(lineNo, t);
	}
	if (lines.empty()) throw Error(path, 0, "empty shape file");
	long long n;
	if (!parseInt(lines[0].second, n) || n < 3 || n > 10000) throw Error(path, lines[0].first, "expected the number of points");
	if (lines.size() < std::size_t(n) + 2) throw Error(path, 0, "expected " + std::to_string(n) + " point lines and a host image name");
	CorpusEntry e;
	e.source = path;
	e.points.resize(n, 2);
	for (long long k = 0; k < n; ++k) {
		auto [ln, l] = lines[1 + k];
		auto f = splitWhitespace(l);
		double x, y;
		if (f.size() < 4 || !parseDouble(f[2], x) || !parseDouble(f[3], y))
			throw Error(path, ln, "expected '<path> <type> <x> <y> …' for point " + std::to_string(k));
		e.points(k, 0) = x;
		e.points(k, 1) = y;
	}
	e.imagePath = resolveImage(path, lines[1 + n].second);
	int w, h;
	imageSize(e.imagePath, w, h);
	// Relative coordinates: 0..1 across the image; pixel centres at integer positions.
	e.points.col(0) *= w;
	e.points.col(1) *= h;
	e.name = fs::path(e.imagePath).stem().string();  // unlabelled
	return e;
}

CorpusEntry readPts(const std::string& path) {
	const std::string text = readTextFile(path);
	CorpusEntry e;
	e.source = path;
	long lineNo = 0, n = -1;
	bool inPoints = false;
	std::vector<std::array<double, 2>> pts;
	for (std::string l : split(text, '\n')) {
		++lineNo;
		std::string t(trim(l));
		if (t.empty()) continue;
		if (!inPoints) {
			if (startsWith(t, "n_points:")) {
				long long v;
				if (!parseInt(t.substr(9), v) || v < 3 || v > 10000) throw Error(path, lineNo, "bad n_points");
				n = long(v);
			} else if (t == "{") {
				inPoints = true;
			}
			continue;
		}
		if (t == "}") break;
		auto f = splitWhitespace(t);
		double x, y;
		if (f.size() != 2 || !parseDouble(f[0], x) || !parseDouble(f[1], y)) throw Error(path, lineNo, "expected 'x y'");
		pts.push_back({x - 1.0, y - 1.0});
	}
	if (n < 0) throw Error(path, 0, "missing 'n_points:' line");
	if (long(pts.size()) != n) throw Error(path, 0, "n_points says " + std::to_string(n) + " but " + std::to_string(pts.size()) + " points follow");
	e.points.resize(n, 2);
	for (long k = 0; k < n; ++k) {
		e.points(k, 0) = pts[k][0];
		e.points(k, 1) = pts[k][1];
	}
	fs::path p(path);
	std::string found;
	for (const char* ext : {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".ppm", ".PNG", ".JPG", ".JPEG", ".BMP", ".TIF"}) {
		fs::path cand = p;
		cand.replace_extension(ext);
		std::error_code ec;
		if (fs::is_regular_file(cand, ec)) {
			found = cand.string();
			break;
		}
	}
	if (found.empty()) throw Error(path, 0, "no image with the same name beside it (.png, .jpg, .jpeg, .bmp, .tif, .tiff, .ppm)");
	e.imagePath = found;
	e.name = p.stem().string();  // unlabelled
	return e;
}

Corpus loadCorpus(const std::string& path) {
	std::error_code ec;
	if (!fs::exists(path, ec)) throw Error(path, 0, "corpus not found");
	if (fs::is_regular_file(path, ec)) {
		if (endsWith(toLower(path), ".csv")) return readChUnicampCsv(path);
		throw Error(path, 0, "not a corpus: expected a CH-Unicamp .csv file or a folder of images with .asf/.pts files");
	}
	std::vector<fs::path> files;
	for (auto it = fs::recursive_directory_iterator(path, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
		if (!it->is_regular_file()) continue;
		std::string ext = toLower(it->path().extension().string());
		if (ext == ".asf" || ext == ".pts") files.push_back(it->path());
	}
	if (ec) throw Error(path, 0, "cannot list folder: " + ec.message());
	if (files.empty()) throw Error(path, 0, "no .asf or .pts shape files in this folder");
	std::sort(files.begin(), files.end());
	Corpus c;
	c.path = path;
	for (const auto& f : files) {
		std::string ext = toLower(f.extension().string());
		c.entries.push_back(ext == ".asf" ? readAsf(f.string()) : readPts(f.string()));
		if (c.entries.back().points.rows() != c.entries.front().points.rows())
			throw Error(f.string(), 0, "has " + std::to_string(c.entries.back().points.rows()) + " points but " +
			                               files.front().string() + " has " + std::to_string(c.entries.front().points.rows()));
	}
	std::sort(c.entries.begin(), c.entries.end(), [](const CorpusEntry& a, const CorpusEntry& b) { return a.imagePath < b.imagePath; });
	c.schemeName = schemeForCount(int(c.entries.front().points.rows()));
	return c;
}

namespace {
std::string csvField(const std::string& s) {
	if (s.find_first_of(",\"") != std::string::npos) {
		std::string q = "\"";
		for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
		return q + "\"";
	}
	return s.empty() ? std::string("-") : s;
}
}  // namespace

std::string chUnicampCsvRow(const CorpusEntry& e) {
	std::string row = csvField(e.imagePath) + "," + csvField(e.emotionLabel());
	for (const auto& c : e.context) row += "," + csvField(c);
	row += "," + csvField(e.cdvLabel()) + "," + csvField(e.word);
	char buf[64];
	for (Eigen::Index i = 0; i < e.points.rows(); ++i) {
		std::snprintf(buf, sizeof buf, ",(%.3f;%.3f)", e.points(i, 0), e.points(i, 1));
		row += buf;
	}
	return row;
}

}  // namespace talkhead
