// SPDX-License-Identifier: GPL-3.0-or-later
#include "synth_corpus.h"

#include <algorithm>
#include <atomic>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <unistd.h>

#include "base/atomic_file.h"
#include "base/data_dirs.h"
#include "base/error.h"
#include "base/hash.h"
#include "base/parallel.h"
#include "base/text.h"
#include "base/tsv.h"
#include "corpus/corpus.h"
#include "media/image_io.h"
#include "phonetics/labels.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {

std::string dataFile(const std::string& rel) {
	if (auto p = findDataFile(rel)) return *p;
	throw Error("data file '" + rel + "' not found");
}

std::uint64_t splitmix(std::uint64_t x) { return splitmix64(x); }  // the per-image jitter's hash
std::uint64_t hashString(const std::string& s) {
	std::uint64_t h = 1469598103934665603ull;
	for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
	return h;
}
double unit(std::uint64_t& state) {  // uniform in [−1, 1)
	state = splitmix(state);
	return double(state >> 11) / double(1ull << 52) - 1.0;
}

// The per-image head jitter (≤ 2°, ± 2 % scale, a few pixels at 720 lines), from a seed.
HeadPose jitter(std::uint64_t seed, int height) {
	std::uint64_t s = splitmix(seed);
	const double scale = height / 720.0;
	HeadPose p;
	p.angleDeg = 2.0 * unit(s);
	p.scale = 1.0 + 0.02 * unit(s);
	p.dx = 12.0 * scale * unit(s);
	p.dy = 8.0 * scale * unit(s);
	return p;
}

}  // namespace

std::map<std::string, Articulation> loadArticulations(const std::string& path) {
	TsvTable t = readTsv(path);
	const auto cl = t.column("label");
	std::map<std::string, Articulation> out;
	for (const auto& r : t.rows) {
		Articulation a;
		a.jaw = t.number(r, t.column("jaw"), 0, 1);
		a.width = t.number(r, t.column("width"), -1, 1);
		a.round = t.number(r, t.column("round"), 0, 1);
		a.upper = t.number(r, t.column("upper"), 0, 1);
		a.tuck = t.number(r, t.column("tuck"), 0, 1);
		a.closed = t.number(r, t.column("closed"), 0, 1);
		a.tongue = t.number(r, t.column("tongue"), 0, 1);
		a.teeth = t.number(r, t.column("teeth"), 0, 1);
		auto label = canonicalViseme(r.fields[cl]);
		if (!label) throw Error(path, r.line, "unknown viseme '" + r.fields[cl] + "'");
		out[*label] = a;
	}
	for (const auto& v : visemeLabels())
		if (!out.count(v.label)) throw Error(path, 0, "no articulation for viseme '" + v.label + "'");
	return out;
}

std::map<std::string, ActionUnits> loadActionUnits(const std::string& path) {
	TsvTable t = readTsv(path);
	const auto cl = t.column("emotion");
	std::map<std::string, ActionUnits> out;
	for (const auto& r : t.rows) {
		ActionUnits u;
		auto au = [&](const char* name) { return t.number(r, t.column(name), 0, 1); };
		u.au1 = au("AU1"), u.au2 = au("AU2"), u.au4 = au("AU4"), u.au5 = au("AU5"), u.au6 = au("AU6"), u.au7 = au("AU7");
		u.au9 = au("AU9"), u.au10 = au("AU10"), u.au12 = au("AU12"), u.au15 = au("AU15"), u.au16 = au("AU16"), u.au17 = au("AU17");
		u.au20 = au("AU20"), u.au23 = au("AU23"), u.au24 = au("AU24"), u.au25 = au("AU25"), u.au43 = au("AU43"), u.au26 = au("AU26");
		auto label = canonicalEmotion(r.fields[cl]);
		if (!label) throw Error(path, r.line, "unknown emotion '" + r.fields[cl] + "'");
		out[*label] = u;
	}
	for (const auto& e : emotionLabels())
		if (!out.count(e.label)) throw Error(path, 0, "no action-unit profile for emotion '" + e.label + "'");
	return out;
}

const std::map<std::string, Articulation>& articulations() {
	static const auto m = loadArticulations(dataFile("corpus-tools/data/viseme-articulation.tsv"));
	return m;
}

const std::map<std::string, ActionUnits>& actionUnits() {
	static const auto m = loadActionUnits(dataFile("corpus-tools/data/expression-aus.tsv"));
	return m;
}

std::vector<SynthItem> synthCorpusItems(const SynthCorpusOptions& o) {
	std::vector<std::string> emotions = o.emotions, visemes = o.visemes;
	if (emotions.empty())
		for (const auto& e : emotionLabels()) emotions.push_back(e.label);
	if (visemes.empty())
		for (const auto& v : visemeLabels()) visemes.push_back(v.label);
	std::vector<SynthItem> items;
	for (const auto& e : emotions) {
		for (const auto& vl : visemes) {
			const VisemeLabel* v = nullptr;
			for (const auto& x : visemeLabels())
				if (x.label == vl) v = &x;
			if (!v) throw std::logic_error("synthCorpusItems: unknown viseme " + vl);
			SynthItem it;
			it.emotion = e;
			it.viseme = v->label;
			it.articulation = articulations().at(v->label);
			it.actionUnits = actionUnits().at(e);
			it.pose = jitter(o.seed ^ splitmix(hashString(e) ^ (hashString(v->label) << 1)), o.height);
			it.fileName = e + "_" + v->ascii + ".png";
			// Phone context: the viseme's first listed context (V1 C V2 or C V), centre = the group's first phone.
			it.context = {"_", "_", v->group.empty() ? "_" : v->group.front(), "_", "_"};
			if (v->kind == "consonant" && !v->contexts.empty()) {
				const std::string& c = v->contexts.front();
				const std::string& centre = v->group.front();
				auto pos = c.find(centre);
				if (pos != std::string::npos) {
					if (pos > 0) it.context[1] = c.substr(0, pos);
					if (pos + centre.size() < c.size()) it.context[3] = c.substr(pos + centre.size());
				}
			}
			it.word = "-";
			items.push_back(std::move(it));
		}
	}
	return items;
}

SynthItem closedEyesItem(const SynthCorpusOptions& o) {
	SynthItem it;
	it.emotion = "-";
	it.viseme = "closed-eyes";
	it.articulation = articulations().at("sil");
	it.actionUnits = actionUnits().at("neutral");
	it.actionUnits.au43 = 1;
	it.pose = jitter(o.seed ^ splitmix(hashString("closed-eyes")), o.height);
	it.fileName = "neutral_closed.png";
	it.context = {"_", "_", "_", "_", "_"};
	it.word = "-";
	return it;
}

void writeSynthCorpus(const std::string& dir, const SynthCorpusOptions& o, ProgressSink& progress) {
	if (o.width < 64 || o.height < 64 || o.width > 7680 || o.height > 4320)
		throw Error("absurd corpus image size " + std::to_string(o.width) + "x" + std::to_string(o.height) + " (64x64 to 7680x4320)");
	// All or nothing: a staged folder that replaces `dir` (new, empty, or a corpus written before) at the end.
	StagedFolder staged(dir, [](const std::string& n) { return n == "corpus.csv" || (n.size() > 4 && n.compare(n.size() - 4, 4, ".png") == 0); });
	std::vector<SynthItem> items = synthCorpusItems(o);
	// D50: with neutral, one more image: the neutral face at rest with its eyes shut, an unlabelled row that
	// the CSV names with "# closed-eyes:" (blinks take the closed lid's skin from it).
	const bool closedEyes = o.emotions.empty() || std::find(o.emotions.begin(), o.emotions.end(), "neutral") != o.emotions.end();
	if (closedEyes) items.push_back(closedEyesItem(o));
	const FaceRenderer renderer(o.width, o.height);
	std::vector<std::string> rows(items.size());
	std::atomic<std::size_t> done{0};
	std::mutex m;
	parallelFor(items.size(), o.threads, [&](std::size_t i) {
		SynthFace face = renderer.render(items[i].articulation, items[i].actionUnits, items[i].pose);
		staged.writeFile(items[i].fileName, [&](const std::string& p) { writeImage(p, face.image, o.pngCompression); });
		CorpusEntry row;
		row.imagePath = items[i].fileName, row.context = items[i].context;
		row.setLabels(items[i].emotion, items[i].viseme);
		row.word = items[i].word, row.points = face.points;
		rows[i] = chUnicampCsvRow(row);
		std::size_t d = ++done;
		std::lock_guard<std::mutex> lock(m);
		progress.report(double(d) / double(items.size()), "drawing faces");
	});
	std::string csv = closedEyes ? "# closed-eyes: neutral_closed.png\n" : "";
	for (const auto& r : rows) csv += r + '\n';
	staged.writeFile("corpus.csv", [&](const std::string& p) { writeFileAtomically(p, csv); });
	staged.commit();
}

}  // namespace talkhead
