// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/faces.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/text.h"
#include "base/tsv.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {

// Bumped when what builds a shipped face changes its bytes (frame choice, colours, the builder): the faces
// built before are then built again.
const char* const kShippedFaceBuilder = "talkhead shipped face 1: the take list planned and built as from-video and build do (D91)\n";

}  // namespace

std::vector<ShippedFace> shippedFaces() {
	const auto registry = findDataFile("models/faces/faces.tsv");
	if (!registry) return {};
	const TsvTable tab = readTsv(*registry);
	const std::size_t cn = tab.column("name"), cs = tab.column("size"), cl = tab.column("lang"), ce = tab.column("emotions"), cli = tab.column("licence"),
	                  cso = tab.column("source"), ct = tab.column("takes");
	const fs::path folder = fs::path(*registry).parent_path();
	std::vector<ShippedFace> out;
	for (const auto& r : tab.rows) {
		ShippedFace f;
		f.name = r.fields[cn];
		const std::string& size = r.fields[cs];
		const auto x = size.find('x');
		try {
			if (x == std::string::npos) throw std::invalid_argument(size);
			f.width = std::stoi(size.substr(0, x));
			f.height = std::stoi(size.substr(x + 1));
		} catch (const std::exception&) {
			throw Error(*registry, r.line, "size '" + size + "' is not WIDTHxHEIGHT");
		}
		f.lang = r.fields[cl];
		f.emotions = split(r.fields[ce], ',');
		f.licence = r.fields[cli];
		f.source = r.fields[cso];
		f.takes = (folder / r.fields[ct]).string();
		if (f.name.empty() || f.emotions.empty()) throw Error(*registry, r.line, "a face needs a name and its recorded emotions");
		out.push_back(std::move(f));
	}
	return out;
}

ShippedFace shippedFace(const std::string& name) {
	std::string names;
	for (auto& f : shippedFaces()) {
		if (f.name == name) return f;
		names += (names.empty() ? "" : ", ") + f.name;
	}
	throw Error("no face named '" + safeLine(name, 80) + "' ships with talkhead (" + (names.empty() ? "none is installed" : "the faces: " + names + ", synthetic") + ")");
}

std::string shippedFaceModelPath(const ShippedFace& face) {
	const std::string cache = userCacheDir();
	if (cache.empty()) return "";
	return (fs::path(cache) / "models" / "faces" / (face.name + ".thm")).string();
}

std::string shippedFaceRecipe(const ShippedFace& face) {
	std::string recipe = kShippedFaceBuilder;
	recipe += "face " + face.name + " " + face.lang + "\n";
	const std::string list = readTextFile(face.takes);
	recipe += list;
	// Each file the list names (any field that is a file beside it), by name and size.
	const TsvTable tab = parseTsv(list, face.takes);
	const fs::path folder = fs::path(face.takes).parent_path();
	for (const auto& r : tab.rows)
		for (const std::string& field : r.fields) {
			std::error_code ec;
			const fs::path p = folder / field;
			if (field.empty() || !fs::is_regular_file(p, ec)) continue;
			recipe += field + " " + std::to_string(fs::file_size(p, ec)) + "\n";
		}
	return recipe;
}

std::optional<std::string> builtShippedFace(const ShippedFace& face) {
	const std::string model = shippedFaceModelPath(face);
	if (model.empty()) return std::nullopt;
	std::error_code ec;
	if (!fs::is_regular_file(model, ec)) return std::nullopt;
	std::string stamp;
	try {
		stamp = readTextFile(fs::path(model).replace_extension(".recipe").string());
	} catch (const std::exception&) {
		return std::nullopt;
	}
	if (stamp != shippedFaceRecipe(face)) return std::nullopt;
	return model;
}

std::string ownFacesDir() {
	const std::string cache = userCacheDir();
	return cache.empty() ? "" : (fs::path(cache) / "models" / "faces" / "own").string();
}

std::vector<OwnFace> ownFaces() {
	std::vector<OwnFace> out;
	const std::string dir = ownFacesDir();
	std::error_code ec;
	if (dir.empty() || !fs::is_directory(dir, ec)) return out;
	for (const auto& e : fs::directory_iterator(dir, ec)) {
		if (e.path().extension() != ".thm" || !e.is_regular_file(ec)) continue;
		OwnFace f;
		f.name = e.path().stem().string();
		f.model = e.path().string();
		try {
			for (const std::string& line : split(readTextFile(fs::path(e.path()).replace_extension(".info").string()), '\n')) {
				const auto tab = line.find('\t');
				if (tab == std::string::npos) continue;
				const std::string k = line.substr(0, tab), v = line.substr(tab + 1);
				if (k == "size") f.size = v;
				else if (k == "emotions") f.emotions = v;
				else if (k == "source") f.source = v;
			}
		} catch (const std::exception&) {  // no .info: listed with what is known
		}
		out.push_back(std::move(f));
	}
	std::sort(out.begin(), out.end(), [](const OwnFace& a, const OwnFace& b) { return a.name < b.name; });
	return out;
}

std::optional<OwnFace> ownFace(const std::string& name) {
	for (auto& f : ownFaces())
		if (f.name == name) return f;
	return std::nullopt;
}

void checkOwnFaceName(const std::string& name) {
	const bool chars = !name.empty() && name.size() <= 40 && name[0] != '.' &&
	                   std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'; });
	if (!chars) throw Error("'" + safeLine(name, 60) + "' cannot name a face: 1–40 letters, digits, '.', '_' and '-', not starting with '.'");
	if (name == "synthetic") throw Error("'synthetic' is the default face's name: choose another");
	for (const auto& f : shippedFaces())
		if (f.name == name) throw Error("'" + name + "' is a face that ships with talkhead: choose another name");
}

}  // namespace talkhead
