// SPDX-License-Identifier: GPL-3.0-or-later
#include "stimuli/batch.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>
#include <filesystem>
#include <numeric>
#include <set>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/atomic_file.h"
#include "base/frame_rate.h"
#include "base/hash.h"
#include "base/sha256.h"
#include "base/json.h"
#include "base/text.h"
#include "media/image_io.h"
#include "phonetics/emotion.h"
#include "phonetics/labels.h"
#include "render/render.h"

namespace fs = std::filesystem;

namespace talkhead {

ManifestErrors::ManifestErrors(std::vector<std::string> m)
    : Error(m.empty() ? "manifest errors" : m.front()), messages(std::move(m)) {}

namespace {

std::uint64_t splitmix(std::uint64_t x) { return splitmix64(x); }

// Columns that pass to the row's command as the field of the same name: column → (passes, say, render);
// the others are handled below.
struct Column {
	const char* name;
	bool passes;  // false: handled specially
	bool say, render;
};
const std::vector<Column>& columns() {
	static const std::vector<Column> c = {
	    {"text", false, true, true},           {"transcript", true, false, true}, {"audio", true, false, true},
	    {"lang", true, true, true},      {"voice", true, true, false},           {"model", true, true, true},
	    {"emotion", false, true, true},         {"intensity", false, true, true},               {"muted", false, true, true},
	    {"fps", true, true, true},        {"size", true, true, true},              {"trajectory", true, true, true},
	    {"dissolve", true, true, true}, {"warp", true, true, true},           {"pauses", true, true, true},
	    {"blinks", true, true, true},  {"head-motion", true, true, true}, {"speech-brows", true, true, true},
	    {"emotion-source", true, true, true}, {"controls", true, true, true}, {"seed", true, true, true},
	    {"rate", true, true, false},     {"pitch", true, true, false},           {"crf", true, true, true},
	    {"lead-in", true, true, true}, {"tail", true, true, true},             {"av-offset", true, true, true},
	    {"components", true, true, true}, {"drive", true, false, true}, {"drive-mouth", false, false, true},
	    {"timing-text", true, false, true}, {"condition", false, true, true}, {"resampling", true, true, true},
	    {"au-appearance", true, true, true}, {"coarticulation", true, true, true}, {"face", true, true, true}};
	return c;
}
const Column* findColumn(const std::string& name) {
	for (const auto& c : columns())
		if (name == c.name) return &c;
	return nullptr;
}
bool isAnnotation(const std::string& name) { return name == "condition" || startsWith(name, "x-"); }

std::string knownColumns() {
	std::string s;
	for (const auto& c : columns()) s += (s.empty() ? "" : ", ") + std::string(c.name);
	return s + ", x-…";
}

// The manifest as (line, column → value) records, CSV or JSON.
struct Record {
	long line;
	std::vector<std::pair<std::string, std::string>> fields;
};

std::vector<Record> readRecords(const std::string& text, const std::string& path, std::vector<std::string>& header, long& headerLine,
                                std::vector<std::string>& errors) {
	std::vector<Record> out;
	const std::string_view t = trim(text);
	if (!t.empty() && (t.front() == '[' || t.front() == '{')) {
		const JsonValue root = parseJson(text, path);
		const JsonValue* items = &root;
		if (root.kind == JsonValue::Kind::Object) {
			items = root.find("stimuli");
			if (!items) throw Error(path, 0, "a JSON manifest is an array of stimuli or {\"stimuli\": [...]}");
		}
		if (items->kind != JsonValue::Kind::Array) throw Error(path, 0, "\"stimuli\" must be an array");
		for (std::size_t i = 0; i < items->array.size(); ++i) {
			const JsonValue& o = items->array[i];
			Record r{long(i + 1), {}};
			if (o.kind != JsonValue::Kind::Object) {
				errors.push_back(path + ":" + std::to_string(i + 1) + ": a stimulus must be an object");
				continue;
			}
			for (const auto& [k, v] : o.object) {
				std::string value;
				if (v.kind == JsonValue::Kind::String) value = v.string;
				else if (v.kind == JsonValue::Kind::Number) {
					char b[32];
					std::snprintf(b, sizeof b, "%.10g", v.number);
					value = b;
				} else if (v.kind == JsonValue::Kind::Bool) value = v.boolean ? "yes" : "no";
				else if (v.kind != JsonValue::Kind::Null) {
					errors.push_back(path + ":" + std::to_string(i + 1) + ":" + k + ": must be a string, number or boolean");
					continue;
				}
				r.fields.emplace_back(k, value);
				if (std::find(header.begin(), header.end(), k) == header.end()) header.push_back(k);
			}
			out.push_back(std::move(r));
		}
		return out;
	}
	long lineNo = 0;
	bool haveHeader = false;
	for (std::string line : split(text, '\n')) {
		++lineNo;
		if (!line.empty() && line.back() == '\r') line.pop_back();
		if (lineNo == 1 && startsWith(line, "\xEF\xBB\xBF")) line.erase(0, 3);
		if (trim(line).empty() || trim(line).front() == '#') continue;
		std::vector<std::string> f = splitCsvRecord(line);
		for (auto& x : f) x = std::string(trim(x));
		if (!haveHeader) {
			header = f;
			headerLine = lineNo;
			haveHeader = true;
			std::set<std::string> seen;
			for (const auto& h : header)
				if (!seen.insert(h).second) errors.push_back(path + ":" + std::to_string(lineNo) + ":" + h + ": column named twice");
			continue;
		}
		if (f.size() != header.size()) {
			errors.push_back(path + ":" + std::to_string(lineNo) + ": " + std::to_string(f.size()) + " fields, the header has " + std::to_string(header.size()));
			continue;
		}
		Record r{lineNo, {}};
		for (std::size_t i = 0; i < f.size(); ++i) r.fields.emplace_back(header[i], f[i]);
		out.push_back(std::move(r));
	}
	if (!haveHeader) throw Error(path, 0, "empty manifest (a CSV header row, then one row per stimulus)");
	return out;
}

const std::string kVersus = "versus:";
// Columns a side-by-side row's other side may change: what is drawn, never the speech, timing or frame.
bool versusColumn(const std::string& c) {
	static const std::set<std::string> allowed = {"model", "emotion", "intensity", "trajectory", "dissolve", "warp", "pauses", "blinks", "head-motion",
	                                              "speech-brows", "emotion-source", "controls", "seed", "components",
	                                              "resampling", "au-appearance", "face"};
	return allowed.count(c) > 0;
}

// A row's command ("say" or "render"; "" when it has no text, transcript or audio) and its arguments, from
// its fields; every problem goes to fail(column, what). Files resolve against the manifest's folder.
template <class Fail>
std::string rowJob(const std::map<std::string, std::string>& fields, const fs::path& dir, std::vector<JobField>& job, std::string& canonical,
                         Fail&& fail) {
	auto get = [&](const char* k) -> std::string {
		auto it = fields.find(k);
		return it == fields.end() ? std::string() : it->second;
	};
	std::map<std::string, std::string> resolved;
	for (const char* k : {"transcript", "timing-text", "audio", "model", "controls", "drive"}) {
		auto it = fields.find(k);
		if (it == fields.end()) continue;
		const fs::path p = fs::path(it->second).is_absolute() ? fs::path(it->second) : dir / it->second;
		std::error_code ec;
		if (!fs::is_regular_file(p, ec)) fail(k, "no such file '" + it->second + "'");
		resolved[k] = p.string();
	}
	const bool text = !get("text").empty(), transcript = !get("transcript").empty(), audio = !get("audio").empty(), drive = !get("drive").empty();
	// Issue 17: a driving video gives the head, brows, eyes and blinks (and its audio); with drive-mouth
	// the mouth too, and no text or transcript.
	bool driveMouth = false;
	if (auto dm = toLower(get("drive-mouth")); !dm.empty()) {
		if (dm == "yes" || dm == "true" || dm == "1") driveMouth = true;
		else if (dm != "no" && dm != "false" && dm != "0") fail("drive-mouth", "'" + get("drive-mouth") + "' is not yes or no");
	}
	if (!get("face").empty() && fields.count("model")) fail("face", "a row names its face or its model, not both");
	if (driveMouth && !drive) fail("drive-mouth", "needs a drive video");
	if (driveMouth && (text || transcript)) fail("drive-mouth", "takes the mouth from the drive video: no text or transcript");
	if (!text && !transcript && !driveMouth && !audio)
		fail("text", "a stimulus needs text (spoken by espeak-ng), a transcript, or audio (its phones recognised)");
	if (text && transcript) fail("transcript", "text and transcript both given: one or the other");
	if (!get("timing-text").empty() && !transcript) fail("timing-text", "the text of a timing file, but the row has no transcript");
	const std::string command = transcript || driveMouth || drive || audio ? "render" : "say";  // audio alone: recognised
	if (driveMouth) job.push_back({"drive-mouth", std::nullopt});
	if (text) job.push_back({"text", get("text")});
	// Emotion (and intensity).
	std::string emotion = get("emotion"), intensity = get("intensity");
	if (auto colon = emotion.find(':'); colon != std::string::npos) {
		if (!intensity.empty()) fail("intensity", "given twice (emotion '" + emotion + "' has one)");
		intensity = emotion.substr(colon + 1);
		emotion = emotion.substr(0, colon);
	}
	try {  // checked as every front end checks it (phonetics/emotion.h); the child gets the row's own text
		canonical = Expression::parse((emotion.empty() ? Emotion::neutralLabel() : emotion) + (intensity.empty() ? "" : ":" + intensity)).emotion().label();
	} catch (const FieldError& e) {
		fail(e.field(), e.what());
	}
	job.push_back({"emotion", canonical + (intensity.empty() ? "" : ":" + intensity)});
	// Muted.
	if (auto muted = toLower(get("muted")); !muted.empty()) {
		if (muted == "yes" || muted == "true" || muted == "1") job.push_back({"no-audio", std::nullopt});
		else if (muted != "no" && muted != "false" && muted != "0") fail("muted", "'" + get("muted") + "' is not yes or no");
	}
	if (auto comps = get("components"); !comps.empty()) {
		try {
			parseComponentLevels(comps);
		} catch (const Error& e) {
			fail("components", e.what());
		}
	}
	if (auto fps = get("fps"); !fps.empty() && !FrameRate::parse(fps)) fail("fps", "'" + fps + "' is not a frame rate (30, 25, 29.97, 30000/1001)");
	for (const auto& [k, v] : fields) {
		const Column* c = findColumn(k);
		if (!c || !c->passes) continue;
		if (command == "say" && !c->say) fail(k, "only for a stimulus with a transcript (render)");
		else if (command == "render" && !c->render) fail(k, "only for a stimulus spoken from text (say)");
		else job.push_back({k, resolved.count(k) ? resolved.at(k) : v});
	}
	return (!text && !transcript && !driveMouth && !audio) ? std::string() : command;
}

}  // namespace

Manifest parseManifest(const std::string& text, const std::string& path) {
	Manifest m;
	m.path = path;
	std::vector<std::string> errors;
	long headerLine = 1;  // JSON: the columns are named in every item; their errors say line 1
	const std::vector<Record> records = readRecords(text, path, m.columns, headerLine, errors);
	const fs::path dir = fs::path(path).parent_path();
	for (const auto& c : m.columns) {
		if (startsWith(c, kVersus)) {
			if (!versusColumn(c.substr(kVersus.size())))
				errors.push_back(path + ":" + std::to_string(headerLine) + ":" + c +
				                 ": the two sides of a side-by-side stimulus share the speech, timing and frame; versus: columns may change model, emotion, "
				                 "intensity, trajectory, dissolve, warp, pauses, blinks, head-motion, speech-brows, emotion-source, controls, seed, components, "
				                 "resampling, au-appearance");
		} else if (!findColumn(c) && !isAnnotation(c)) {
			errors.push_back(path + ":" + std::to_string(headerLine) + ":" + c + ": unknown column (known: " + knownColumns() + ", versus:…)");
		}
	}
	for (const Record& rec : records) {
		BatchRow row;
		row.index = m.rows.size();
		row.line = rec.line;
		auto fail = [&](const std::string& column, const std::string& what) {
			errors.push_back(path + ":" + std::to_string(rec.line) + ":" + column + ": " + what);
		};
		for (const auto& [k, v] : rec.fields)
			if (!v.empty()) row.fields[k] = v;
		// Side-by-side: the `versus:` columns replace the row's own for the other side ("default" drops one).
		std::map<std::string, std::string> versus = row.fields;
		std::set<std::string> overridden;
		for (const auto& [k, v] : row.fields) {
			if (!startsWith(k, kVersus)) continue;
			const std::string base = k.substr(kVersus.size());
			if (!versusColumn(base)) continue;  // reported with the header
			row.sideBySide = true;
			overridden.insert(base);
			versus.erase(k);
			if (v == "default") versus.erase(base);
			else versus[base] = v;
		}
		for (auto it = versus.begin(); it != versus.end();) it = startsWith(it->first, kVersus) ? versus.erase(it) : std::next(it);
		const std::string command = rowJob(row.fields, dir, row.job, row.emotion, fail);
		row.command = command.empty() ? "say" : command;
		if (row.sideBySide && !command.empty()) {
			auto failVersus = [&](const std::string& column, const std::string& what) {
				if (overridden.count(column)) fail(kVersus + column, what);
			};
			std::string emotion;
			rowJob(versus, dir, row.versusJob, emotion, failVersus);
		}
		m.rows.push_back(std::move(row));
	}
	if (m.rows.empty() && errors.empty()) errors.push_back(path + ": no stimuli");
	if (!errors.empty()) throw ManifestErrors(errors);
	return m;
}

Manifest loadManifest(const std::string& path) { return parseManifest(readTextFile(path), path); }

void checkManifestModels(const Manifest& m, const std::function<std::string(const std::string&)>& faceModel) {
	std::vector<std::string> errors;
	std::map<std::string, std::vector<std::string>> regionsOf;  // model path ("" = default) → region names
	for (const BatchRow& row : m.rows) {
		auto comps = row.fields.find("components");
		if (comps == row.fields.end()) continue;
		std::string model = jobValue(row.job, "model").value_or("");
		if (auto face = jobValue(row.job, "face"); face && faceModel) {
			try {
				model = faceModel(*face);
			} catch (const Error& e) {
				errors.push_back(m.path + ":" + std::to_string(row.line) + ":face: " + e.what());
				continue;
			}
		}
		auto it = regionsOf.find(model);
		if (it == regionsOf.end()) {
			std::vector<std::string> names;
			try {
				for (const auto& r : loadRenderModel(model).regions) names.push_back(r.name);
			} catch (const Error& e) {
				errors.push_back(m.path + ":" + std::to_string(row.line) + ":model: " + e.what());
			}
			it = regionsOf.emplace(model, names).first;
		}
		if (it->second.empty()) continue;
		std::string regionList;
		for (const auto& n : it->second) regionList += (regionList.empty() ? "" : ", ") + n;
		for (const auto& [region, level] : parseComponentLevels(comps->second))
			if (std::find(it->second.begin(), it->second.end(), region) == it->second.end())
				errors.push_back(m.path + ":" + std::to_string(row.line) + ":components: the model has no region '" + region.substr(0, 40) +
				                 "' (regions: " + regionList + ")");
	}
	if (!errors.empty()) throw ManifestErrors(errors);
}

std::vector<std::string> blindIds(std::size_t rows, std::uint64_t seed) {
	static const char* alphabet = "ABCDEFGHJKLMNPQRSTUVWXYZ23456789";  // no I, O, 0, 1
	std::vector<std::string> ids;
	std::set<std::string> seen;
	for (std::size_t i = 0; i < rows; ++i) {
		std::uint64_t h = splitmix(seed ^ splitmix(0x51A7ull + i));
		for (;;) {
			std::string id = "S";
			std::uint64_t v = h;
			for (int k = 0; k < 6; ++k, v >>= 5) id += alphabet[v & 31];
			if (seen.insert(id).second) {
				ids.push_back(id);
				break;
			}
			h = splitmix(h);
		}
	}
	return ids;
}

std::vector<std::vector<std::size_t>> presentationOrders(std::size_t n, std::size_t participants, std::uint64_t seed,
                                                         const std::vector<std::string>* noRepeat, std::string* warning) {
	std::vector<std::vector<std::size_t>> out;
	if (n == 0 || participants == 0) return out;
	// Williams design: first row 0, 1, n−1, 2, n−2, …; row r adds r (mod n); for odd n the mirrored rows too.
	std::vector<std::size_t> first{0};
	for (std::size_t k = 1, lo = 1, hi = n - 1; k < n; ++k) first.push_back(k % 2 ? lo++ : hi--);
	std::vector<std::vector<std::size_t>> square;
	for (std::size_t r = 0; r < n; ++r) {
		std::vector<std::size_t> row;
		for (std::size_t v : first) row.push_back((v + r) % n);
		square.push_back(row);
	}
	if (n % 2 == 1)
		for (std::size_t r = 0; r < n; ++r) square.emplace_back(square[r].rbegin(), square[r].rend());
	// The stimuli relabelled by a seeded permutation; with a constraint, the first of 500 candidates that
	// keeps it in every order used, else the one that breaks it least.
	auto permutation = [&](std::uint64_t k) {
		std::vector<std::size_t> p(n);
		std::iota(p.begin(), p.end(), 0);
		std::uint64_t s = splitmix(seed ^ splitmix(0x0DE5ull + k));
		for (std::size_t i = n; i > 1; --i) {
			s = splitmix(s);
			std::swap(p[i - 1], p[std::size_t(s % i)]);
		}
		return p;
	};
	auto repeats = [&](const std::vector<std::size_t>& p) {
		std::size_t bad = 0;
		if (!noRepeat) return bad;
		for (std::size_t q = 0; q < participants; ++q) {
			const auto& row = square[q % square.size()];
			for (std::size_t k = 1; k < n; ++k) bad += (*noRepeat)[p[row[k]]] == (*noRepeat)[p[row[k - 1]]];
		}
		return bad;
	};
	std::vector<std::size_t> best = permutation(0);
	std::size_t bestBad = repeats(best);
	for (std::uint64_t k = 1; k < 500 && bestBad > 0; ++k) {
		auto p = permutation(k);
		const std::size_t bad = repeats(p);
		if (bad < bestBad) best = p, bestBad = bad;
	}
	if (bestBad > 0 && warning)
		*warning = std::to_string(bestBad) + " places where two neighbours share a label remain (too many stimuli share one)";
	for (std::size_t q = 0; q < participants; ++q) {
		std::vector<std::size_t> order;
		for (std::size_t v : square[q % square.size()]) order.push_back(best[v]);
		out.push_back(order);
	}
	return out;
}

namespace {
std::string csvField(const std::string& s) {
	if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
	std::string q = "\"";
	for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
	return q + "\"";
}
}  // namespace

void assignSides(Manifest& m, std::uint64_t seed) {
	// Balanced: the side-by-side rows in a seeded random order, the first half with the versus side left
	// (an odd one out by a seeded coin), so each variant is on each side equally often.
	std::vector<std::size_t> rows;
	for (auto& r : m.rows) {
		r.versusLeft = false;
		if (r.sideBySide) rows.push_back(r.index);
	}
	std::uint64_t s = splitmix(seed ^ 0x51DE51DEull);
	for (std::size_t i = rows.size(); i > 1; --i) {
		s = splitmix(s);
		std::swap(rows[i - 1], rows[std::size_t(s % i)]);
	}
	const std::size_t half = rows.size() / 2 + (rows.size() % 2 && (splitmix(s) >> 32) % 2);
	for (std::size_t i = 0; i < half; ++i) m.rows[rows[i]].versusLeft = true;
}

std::string keyCsv(const Manifest& m, const std::vector<std::string>& ids, const std::vector<StimulusResult>& results) {
	const bool sides = std::any_of(m.rows.begin(), m.rows.end(), [](const BatchRow& r) { return r.sideBySide; });
	std::string s = "id,row,status,sha256,file";
	if (sides) s += ",left,right";
	for (const auto& c : m.columns) s += "," + csvField(c);
	s += "\n";
	for (const auto& r : m.rows) {
		const StimulusResult& res = results[r.index];
		s += ids[r.index] + "," + std::to_string(r.line) + "," + res.status + "," + res.sha256 + "," + csvField(res.file);
		if (sides) s += !r.sideBySide ? "," : (r.versusLeft ? ",versus,row" : ",row,versus");
		for (const auto& c : m.columns) {
			auto it = r.fields.find(c);
			s += "," + csvField(it == r.fields.end() ? std::string() : it->second);
		}
		s += "\n";
	}
	return s;
}

std::map<std::string, std::string> readKeyChecksums(const std::string& path) {
	std::map<std::string, std::string> out;
	std::error_code ec;
	if (!fs::is_regular_file(path, ec)) return out;
	bool header = true;
	for (const auto& line : split(readTextFile(path), '\n')) {
		if (header || line.empty()) {
			header = false;
			continue;
		}
		const auto f = splitCsvRecord(line);
		if (f.size() >= 4 && f[2] == "ok" && f[3].size() == 64) out[f[0]] = f[3];
	}
	return out;
}

std::string orderCsv(const std::vector<std::size_t>& order, const std::vector<std::string>& ids, const std::vector<StimulusResult>& results) {
	std::string s = "position,id,file\n";
	for (std::size_t k = 0; k < order.size(); ++k) s += std::to_string(k + 1) + "," + ids[order[k]] + "," + csvField(results[order[k]].file) + "\n";
	return s;
}

namespace {

// A shard's key.csv: its header line and its records.
struct ShardKey {
	std::string header;
	std::vector<std::vector<std::string>> rows;
};

ShardKey readShardKey(const std::string& dir) {
	const std::string path = (fs::path(dir) / "key.csv").string();
	std::error_code ec;
	if (!fs::is_regular_file(path, ec)) throw Error(path, 0, "no key.csv: not a batch output folder");
	ShardKey k;
	bool first = true;
	for (const auto& line : split(readTextFile(path), '\n')) {
		if (line.empty()) continue;
		if (first) k.header = line, first = false;
		else k.rows.push_back(splitCsvRecord(line));
	}
	return k;
}

// The orders: the same in every shard (they come from the whole manifest), written once into `outDir`.
void mergeOrders(const std::string& outDir, const std::vector<std::string>& shardDirs) {
	std::error_code ec;
	for (const auto& e : fs::directory_iterator(shardDirs[0])) {
		const std::string name = e.path().filename().string();
		if (!startsWith(name, "order-") || !endsWith(name, ".csv")) continue;
		const std::string text = readTextFile(e.path().string());
		for (std::size_t s = 1; s < shardDirs.size(); ++s) {
			const fs::path other = fs::path(shardDirs[s]) / name;
			if (!fs::is_regular_file(other, ec) || readTextFile(other.string()) != text)
				throw Error(other.string(), 0, "not the same order as " + e.path().string());
		}
		if (fs::absolute(e.path(), ec) != fs::absolute(fs::path(outDir) / name, ec)) writeFileAtomically((fs::path(outDir) / name).string(), text);
	}
}

}  // namespace

std::size_t mergeShards(const std::string& outDir, const std::vector<std::string>& shardDirs) {
	if (shardDirs.empty()) throw Error("merging shards: no shard folders");
	using Key = ShardKey;
	const auto readKey = readShardKey;
	const Key base = readKey(shardDirs[0]);
	std::vector<Key> keys{base};
	for (std::size_t s = 1; s < shardDirs.size(); ++s) {
		keys.push_back(readKey(shardDirs[s]));
		const Key& k = keys.back();
		bool same = k.header == base.header && k.rows.size() == base.rows.size();
		for (std::size_t r = 0; same && r < k.rows.size(); ++r) {
			same = k.rows[r].size() == base.rows[r].size() && k.rows[r].size() >= 5;
			for (std::size_t c = 0; same && c < k.rows[r].size(); ++c)
				if (c != 2 && c != 3) same = k.rows[r][c] == base.rows[r][c];  // all but status and sha256
		}
		if (!same) throw Error(shardDirs[s] + "/key.csv: not the same manifest and seed as " + shardDirs[0] + "/key.csv");
	}
	std::error_code ec;
	fs::create_directories(outDir, ec);
	if (ec) throw Error(outDir, 0, "cannot create folder: " + ec.message());
	Key merged = base;
	std::size_t missing = 0;
	for (std::size_t r = 0; r < merged.rows.size(); ++r) {
		auto& row = merged.rows[r];
		row[2] = "missing", row[3].clear();
		for (std::size_t s = 0; s < keys.size(); ++s) {
			const auto& theirs = keys[s].rows[r];
			if (theirs[2] != "ok") continue;
			const fs::path from = fs::path(shardDirs[s]) / theirs[4];
			if (!fs::is_regular_file(from, ec) || sha256File(from.string()) != theirs[3])
				throw Error(from.string(), 0, "does not match its SHA-256 in " + shardDirs[s] + "/key.csv");
			if (row[2] == "ok") {
				if (row[3] != theirs[3]) throw Error(from.string(), 0, "differs from the same stimulus in another shard");
				continue;
			}
			const fs::path to = fs::path(outDir) / theirs[4];
			if (fs::absolute(from, ec) != fs::absolute(to, ec)) {
				fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
				if (ec) throw Error(to.string(), 0, "cannot copy: " + ec.message());
				const fs::path sidecar = fs::path(from).replace_extension(".json");
				if (fs::is_regular_file(sidecar, ec)) fs::copy_file(sidecar, fs::path(to).replace_extension(".json"), fs::copy_options::overwrite_existing, ec);
			}
			row[2] = "ok", row[3] = theirs[3];
		}
		missing += row[2] != "ok";
	}
	mergeOrders(outDir, shardDirs);
	std::string out = merged.header + "\n";
	for (const auto& row : merged.rows) {
		for (std::size_t c = 0; c < row.size(); ++c) out += (c ? "," : "") + csvField(row[c]);
		out += "\n";
	}
	writeFileAtomically((fs::path(outDir) / "key.csv").string(), out);
	return missing;
}

namespace {
// The thesis's order of the 22 terms (Table 6.1), for the answers and the truths (neutral first).
const std::vector<std::string>& thesisOrder() {
	static const std::vector<std::string> o = {"happy-for", "joy", "hope", "satisfaction", "relief", "pride", "gratification", "gratitude",
	                                           "admiration", "love", "pity", "distress", "fear", "resentment", "fears-confirmed", "shame",
	                                           "reproach", "remorse", "gloating", "disappointment", "hate", "anger"};
	return o;
}
}  // namespace

std::string playerHtml(const std::vector<std::string>& ids, const std::vector<StimulusResult>& results,
                       const std::vector<std::vector<std::size_t>>& orders, int replays, const std::string& lang) {
	const bool pt = lang == "pt";
	JsonObject stimuli;
	for (std::size_t i = 0; i < ids.size(); ++i) stimuli.add(ids[i], results[i].file);
	JsonArray orderList;
	for (const auto& order : orders) {
		JsonArray o;
		for (std::size_t k : order) o.add(ids[k]);
		orderList.raw(o.str());
	}
	auto pair = [](const std::string& key, const std::string& term) { return JsonArray().add(key).add(term).str(); };
	// The thesis's voting terms (phonetics/emotions.tsv, Table 6.1), in its order, then "none of the above".
	JsonArray emotions;
	for (const std::string& label : thesisOrder()) {
		const EmotionLabel& e = emotionLabels()[Emotion::of(label).index()];
		emotions.raw(pair(e.label, pt ? e.termPt : e.termEn));
	}
	emotions.raw(pair("none", pt ? "NDA (nenhuma das anteriores)" : "none of the above"));
	JsonArray valence;
	valence.raw(pair("negative", pt ? "NEGATIVA" : "negative")).raw(pair("neutral", pt ? "NEUTRA" : "neutral"));
	valence.raw(pair("positive", pt ? "POSITIVA" : "positive")).raw(pair("no-opinion", pt ? "NÃO SEI OPINAR" : "no opinion"));
	JsonObject text;
	text.add("valence", pt ? "A emoção expressa é:" : "The emotion expressed is:").add("emotion", pt ? "A informante parece estar:" : "The speaker seems:");
	const std::string data = JsonObject()
	                             .add("replays", replays)
	                             .raw("stimuli", stimuli.str())
	                             .raw("orders", orderList.str())
	                             .raw("emotions", emotions.str())
	                             .raw("valence", valence.str())
	                             .raw("text", text.str())
	                             .str();
	// </script> cannot occur inside the data: jsonQuote leaves '/' alone, so escape '<'.
	std::string safe;
	for (char c : data) safe += c == '<' ? std::string("\\u003c") : std::string(1, c);
	const auto page = findDataFile("examples/perceptual-test/player.html");
	if (!page) throw Error("the player page examples/perceptual-test/player.html is not installed");
	std::string html = readTextFile(*page);
	// The page's own comments stay out of the stimuli folder.
	const std::string from = "<!-- SPDX", to = "-->\n";
	if (const auto a = html.find(from); a != std::string::npos)
		if (const auto b = html.find(to, html.find(to, a) + to.size()); b != std::string::npos) html.erase(a, b + to.size() - a);
	for (const auto& [key, value] : {std::pair<std::string, std::string>{"{{LANG}}", pt ? "pt" : "en"}, {"{{DATA}}", safe}}) {
		const auto at = html.find(key);
		if (at == std::string::npos) throw Error(*page, 0, "the player page has no " + key);
		html.replace(at, key.size(), value);
	}
	return html;
}

namespace {
std::vector<std::vector<std::string>> csvRows(const std::string& path) {
	std::vector<std::vector<std::string>> rows;
	for (const auto& line : split(readTextFile(path), '\n')) {
		std::string l = line;
		if (!l.empty() && l.back() == '\r') l.pop_back();
		if (!l.empty()) rows.push_back(splitCsvRecord(l));
	}
	return rows;
}
std::size_t columnOf(const std::vector<std::string>& header, const std::string& name, const std::string& path, bool required) {
	for (std::size_t c = 0; c < header.size(); ++c)
		if (header[c] == name) return c;
	if (required) throw Error(path, 1, "no column '" + name + "'");
	return std::size_t(-1);
}
}  // namespace

Score scoreAnswers(const std::string& keyPath, const std::vector<std::string>& answerPaths) {
	const auto key = csvRows(keyPath);
	if (key.empty()) throw Error(keyPath, 0, "empty key");
	const std::size_t kid = columnOf(key[0], "id", keyPath, true), kem = columnOf(key[0], "emotion", keyPath, false),
	                  kcond = columnOf(key[0], "condition", keyPath, false);
	std::map<std::string, std::pair<std::string, std::string>> truth;  // id → (emotion, condition)
	for (std::size_t r = 1; r < key.size(); ++r) {
		std::string e = kem < key[r].size() ? key[r][kem] : "";
		if (auto colon = e.find(':'); colon != std::string::npos) e = e.substr(0, colon);
		const auto c = canonicalEmotion(e.empty() ? Emotion::neutralLabel() : e);
		if (!c) throw Error(keyPath, long(r + 1), "unknown emotion '" + e + "'");
		truth[key[r][kid]] = {*c, kcond < key[r].size() ? key[r][kcond] : ""};
	}
	Score s;
	s.truths = {Emotion::neutralLabel()};
	s.truths.insert(s.truths.end(), thesisOrder().begin(), thesisOrder().end());
	s.answers = thesisOrder();
	s.answers.push_back("none");
	s.confusion.assign(s.truths.size(), std::vector<int>(s.answers.size(), 0));
	for (const auto& path : answerPaths) {
		const auto rows = csvRows(path);
		if (rows.empty()) throw Error(path, 0, "empty answers file");
		const std::size_t aid = columnOf(rows[0], "id", path, true), aem = columnOf(rows[0], "emotion", path, true);
		for (std::size_t r = 1; r < rows.size(); ++r) {
			if (aid >= rows[r].size() || aem >= rows[r].size()) throw Error(path, long(r + 1), "too few fields");
			auto t = truth.find(rows[r][aid]);
			if (t == truth.end()) throw Error(path, long(r + 1), "stimulus '" + rows[r][aid] + "' is not in " + keyPath);
			const std::string& answer = rows[r][aem];
			const auto col = std::find(s.answers.begin(), s.answers.end(), answer);
			if (col == s.answers.end()) throw Error(path, long(r + 1), "unknown answer '" + answer + "'");
			const auto row = std::find(s.truths.begin(), s.truths.end(), t->second.first);
			++s.confusion[std::size_t(row - s.truths.begin())][std::size_t(col - s.answers.begin())];
			// Neutral is right when the answer is "none of the above" (the thesis's terms have no neutral).
			const bool right = answer == t->second.first || (t->second.first == Emotion::neutralLabel() && answer == "none");
			s.correct += right, ++s.answered;
			auto& c = s.byCondition[t->second.second];
			c.first += right, ++c.second;
		}
	}
	return s;
}

std::string scoreReport(const Score& s) {
	std::string out = "emotion            answers  recognised\n";
	char b[128];
	for (std::size_t r = 0; r < s.truths.size(); ++r) {
		int n = 0;
		for (int v : s.confusion[r]) n += v;
		if (n == 0) continue;
		const std::size_t col = s.truths[r] == Emotion::neutralLabel() ? s.answers.size() - 1 : std::size_t(std::find(s.answers.begin(), s.answers.end(), s.truths[r]) - s.answers.begin());
		std::snprintf(b, sizeof b, "%-18s %7d  %5.1f %%\n", s.truths[r].c_str(), n, 100.0 * s.confusion[r][col] / n);
		out += b;
	}
	if (s.byCondition.size() > 1 || (s.byCondition.size() == 1 && !s.byCondition.begin()->first.empty())) {
		out += "\ncondition          answers  recognised\n";
		for (const auto& [c, v] : s.byCondition) {
			std::snprintf(b, sizeof b, "%-18s %7d  %5.1f %%\n", c.empty() ? "(none)" : c.c_str(), v.second, v.second ? 100.0 * v.first / v.second : 0.0);
			out += b;
		}
	}
	std::snprintf(b, sizeof b, "\nall                %7d  %5.1f %%\n", s.answered, s.answered ? 100.0 * s.correct / s.answered : 0.0);
	return out + b;
}

void writeConfusionPng(const Score& s, const std::string& path) {
	const int cell = 26, left = 150, top = 130;
	const int w = left + cell * int(s.answers.size()) + 10, h = top + cell * int(s.truths.size()) + 10;
	cv::Mat m(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
	for (std::size_t r = 0; r < s.truths.size(); ++r) {
		int n = 0;
		for (int v : s.confusion[r]) n += v;
		cv::putText(m, s.truths[r], {6, top + int(r) * cell + 18}, cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
		for (std::size_t c = 0; c < s.answers.size(); ++c) {
			const double share = n ? double(s.confusion[r][c]) / n : 0.0;
			const int shade = int(std::lround(255 * (1 - share)));
			const cv::Rect box(left + int(c) * cell, top + int(r) * cell, cell - 1, cell - 1);
			cv::rectangle(m, box, cv::Scalar(255, shade, shade), cv::FILLED);  // blue, BGR (converted below)
			cv::rectangle(m, box, cv::Scalar(225, 225, 225), 1);
			if (s.confusion[r][c] > 0)
				cv::putText(m, std::to_string(s.confusion[r][c]), {box.x + 3, box.y + 17}, cv::FONT_HERSHEY_SIMPLEX, 0.38,
				            share > 0.5 ? cv::Scalar(255, 255, 255) : cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
		}
	}
	// Column labels, written vertically.
	for (std::size_t c = 0; c < s.answers.size(); ++c) {
		cv::Mat label(cell, top - 6, CV_8UC3, cv::Scalar(255, 255, 255));
		cv::putText(label, s.answers[c], {2, 18}, cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
		cv::Mat up;
		cv::rotate(label, up, cv::ROTATE_90_COUNTERCLOCKWISE);
		up.copyTo(m(cv::Rect(left + int(c) * cell, 2, cell, top - 6)));
	}
	Image8 img(w, h, 3);
	cv::Mat rgb(h, w, CV_8UC3, img.data.data());
	cv::cvtColor(m, rgb, cv::COLOR_BGR2RGB);
	writeImage(path, img);
}

}  // namespace talkhead
