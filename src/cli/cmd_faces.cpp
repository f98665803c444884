// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead faces [--build NAME|all] [--format table|tsv]: the faces that ship with talkhead (issue 48, D91).
#include <cstdio>
#include <string>
#include <vector>

#include "base/data_dirs.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/run.h"
#include "model/faces.h"
#include "phonetics/emotion.h"

namespace talkhead::cli {

namespace {

struct FaceRow {
	std::string name, size, emotions, licence, built, source;
};

// "2 recorded (neutral, joy), 21 from action units"; "?" when unknown.
std::string emotionsCell(const std::vector<std::string>& recorded) {
	if (recorded.empty()) return "?";
	const std::size_t all = Emotion::count();
	std::string cell = std::to_string(recorded.size()) + " recorded";
	if (recorded.size() < all) cell += " (" + joined(recorded) + "), " + std::to_string(all - recorded.size()) + " from action units";
	return cell;
}

std::vector<FaceRow> faceRows() {
	std::vector<FaceRow> rows;
	rows.push_back({kSyntheticFace, "1280x720", std::to_string(Emotion::count()) + " recorded", "GPL-3.0-or-later", findDefaultModel() ? "yes" : "no (made on first use)",
	                "talkhead's synthetic corpus (a drawn face): the default"});
	for (const ShippedFace& f : shippedFaces()) {
		rows.push_back({f.name, std::to_string(f.width) + "x" + std::to_string(f.height), emotionsCell(f.emotions), f.licence,
		                builtShippedFace(f) ? "yes" : "no (built on first use)", f.source});
	}
	for (const OwnFace& f : ownFaces()) {  // `face create --name`
		rows.push_back({f.name, f.size.empty() ? "?" : f.size, emotionsCell(f.emotions.empty() ? std::vector<std::string>{} : split(f.emotions, ',')), "yours", "yes", f.source.empty() ? "face create" : f.source});
	}
	return rows;
}

}  // namespace

int runFaces(const std::vector<std::string>& argv) {
	Args args("faces", "talkhead faces [--build NAME|all] [--format table|tsv]",
	          {{"--build", "NAME|all", "build a shipped face now (or all of them) instead of on first use"},
	           {"--format", "FORMAT", "table (default: aligned columns) or tsv (tab-separated, with a header)"},
	           {"--quiet", "", "with --build: no progress and no summary", "-q"}},
	          "Lists the faces that ship with talkhead: name (what --face takes), frame size, the emotions recorded\n"
	          "(the other OCC emotions are drawn from action units), licence, whether it is built, and its source.\n"
	          "A real face is built once from its clips into the cache (~/.cache/talkhead/models/faces) the first\n"
	          "time a command names it; the clips' attribution is in NOTICE.");
	if (!args.parse(argv)) return 0;
	if (!args.positionals().empty()) throw UsageError("faces: takes no arguments (did you mean --build NAME?)");
	const std::string format = args.get("--format", "table");
	if (format != "table" && format != "tsv") throw UsageError("faces: --format is table or tsv, not '" + format + "'");
	if (auto b = args.get("--build")) {
		std::vector<std::string> names;
		if (*b == "all")
			for (const auto& f : shippedFaces()) names.push_back(f.name);
		else
			names.push_back(*b);
		for (const auto& n : names) shippedFaceModel(n, args.has("--quiet"));
		return 0;
	}
	const std::vector<FaceRow> rows = faceRows();
	const std::vector<std::string> header = {"name", "size", "emotions", "licence", "built", "source"};
	auto fields = [](const FaceRow& r) { return std::vector<std::string>{r.name, r.size, r.emotions, r.licence, r.built, r.source}; };
	if (format == "tsv") {
		std::printf("%s\n", joined(header, "\t").c_str());
		for (const auto& r : rows) std::printf("%s\n", joined(fields(r), "\t").c_str());
		return 0;
	}
	std::vector<std::size_t> width(header.size());
	auto cells = [](const std::string& s) {  // UTF-8 code points, for alignment
		std::size_t n = 0;
		for (unsigned char c : s) n += (c & 0xC0) != 0x80;
		return n;
	};
	for (std::size_t i = 0; i < header.size(); ++i) width[i] = cells(header[i]);
	for (const auto& r : rows) {
		const auto f = fields(r);
		for (std::size_t i = 0; i < f.size(); ++i) width[i] = std::max(width[i], cells(f[i]));
	}
	auto line = [&](const std::vector<std::string>& f) {
		std::string s;
		for (std::size_t i = 0; i < f.size(); ++i) {
			s += f[i];
			if (i + 1 < f.size()) s += std::string(width[i] - cells(f[i]) + 2, ' ');
		}
		std::printf("%s\n", s.c_str());
	};
	line(header);
	for (const auto& r : rows) line(fields(r));
	return 0;
}

}  // namespace talkhead::cli
