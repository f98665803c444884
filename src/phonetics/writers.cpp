// SPDX-License-Identifier: GPL-3.0-or-later
#include "phonetics/writers.h"

#include <cstdio>
#include <map>
#include <sstream>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/json.h"
#include "base/tsv.h"

namespace talkhead {

const std::vector<std::string>& visemeOutputFormats() {
	static const std::vector<std::string> f = {"tsv", "json", "textgrid", "rhubarb-tsv", "rhubarb-json"};
	return f;
}

std::string rhubarbShape(const std::string& cdv) {
	static const std::map<std::string, std::string> table = [] {
		std::map<std::string, std::string> t;
		auto path = findDataFile("phonetics/rhubarb-shapes.tsv");
		if (!path) throw Error("data file 'phonetics/rhubarb-shapes.tsv' not found");
		TsvTable tab = readTsv(*path);
		const auto cc = tab.column("cdv"), cs = tab.column("shape");
		for (const auto& r : tab.rows) t[r.fields[cc]] = r.fields[cs];
		return t;
	}();
	auto it = table.find(cdv);
	return it == table.end() ? "X" : it->second;
}

namespace {

std::string sec(Ticks t) {
	char buf[32];
	std::snprintf(buf, sizeof buf, "%.6f", toSeconds(t));
	return buf;
}

// Keypose time of each phone: its first keypose of its own CDV ("" when it was dropped as too close to a
// neighbour). A pause may have several (rest, in-breath; D34).
std::vector<std::string> keyTimes(const std::vector<PhoneSegment>& ph, const std::vector<Keypose>& keys) {
	std::vector<std::string> t(ph.size());
	for (const auto& k : keys)
		for (std::size_t i = k.first; i <= k.last && i < ph.size(); ++i)
			if (t[i].empty() && !k.breath) t[i] = sec(k.time);
	return t;
}

std::string textGridString(const std::string& s) {
	std::string o = "\"";
	for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
	return o + "\"";
}

struct Cue {
	Ticks start, end;
	std::string shape;
};
std::vector<Cue> rhubarbCues(const std::vector<PhoneSegment>& ph) {
	std::vector<Cue> cues;
	for (const auto& p : ph) {
		const std::string s = rhubarbShape(p.cdv.label());
		if (!cues.empty() && cues.back().shape == s && cues.back().end == p.start) cues.back().end = p.end;
		else cues.push_back({p.start, p.end, s});
	}
	return cues;
}

}  // namespace

// A document a member a line, and its arrays an item a line (visemes and Rhubarb JSON).
constexpr JsonLayout kMemberLines{"\n  ", ",\n  ", "\n"};
constexpr JsonLayout kItemLines{"\n    ", ",\n    ", "\n  "};

std::string formatVisemes(const std::vector<PhoneSegment>& ph, const std::vector<Keypose>& keys, const std::string& format,
                          const std::string& lang, const std::string& source, const std::string& notation, const std::vector<double>* confidence) {
	if (confidence && confidence->size() != ph.size()) throw std::logic_error("formatVisemes: one confidence per phone");
	const auto conf = [&](std::size_t i) {
		char b[16];
		std::snprintf(b, sizeof b, "%.2f", (*confidence)[i]);
		return std::string(b);
	};
	std::ostringstream o;
	const auto kt = keyTimes(ph, keys);
	const Ticks end = ph.empty() ? Ticks(0) : ph.back().end;
	if (format == "tsv") {
		o << "start\tend\tphone\tcdv\tkeypose" << (confidence ? "\tconfidence" : "") << '\n';
		for (std::size_t i = 0; i < ph.size(); ++i) {
			o << sec(ph[i].start) << '\t' << sec(ph[i].end) << '\t' << ph[i].phone << '\t' << ph[i].cdv.label() << '\t' << (kt[i].empty() ? "-" : kt[i]);
			if (confidence) o << '\t' << conf(i);
			o << '\n';
		}
	} else if (format == "json") {
		JsonArray phones, keyposes;
		for (std::size_t i = 0; i < ph.size(); ++i)
		{
			JsonObject one;
			one.raw("start", sec(ph[i].start)).raw("end", sec(ph[i].end)).add("label", ph[i].label).add("phone", ph[i].phone)
			    .add("cdv", ph[i].cdv.label()).raw("keypose", kt[i].empty() ? "null" : kt[i]);
			if (confidence) one.raw("confidence", conf(i));
			phones.raw(one.str());
		}
		for (const Keypose& k : keys) {
			JsonObject key;
			key.raw("time", sec(k.time)).add("cdv", k.cdv.label());
			if (k.breath) key.add("breath", true);
			keyposes.raw(key.str());
		}
		JsonObject doc;
		doc.add("language", lang).add("source", source);
		if (!notation.empty()) doc.add("notation", notation);
		doc.raw("duration", sec(end)).raw("phones", phones.str(kItemLines)).raw("keyposes", keyposes.str(kItemLines));
		o << doc.str(kMemberLines) << "\n";
	} else if (format == "textgrid") {
		o << "File type = \"ooTextFile\"\nObject class = \"TextGrid\"\n\nxmin = 0\nxmax = " << sec(end) << "\ntiers? <exists>\nsize = 3\nitem []:\n";
		auto tier = [&](int n, const char* name, auto labelOf) {
			o << "    item [" << n << "]:\n        class = \"IntervalTier\"\n        name = \"" << name << "\"\n        xmin = 0\n        xmax = " << sec(end)
			  << "\n        intervals: size = " << ph.size() << "\n";
			for (std::size_t i = 0; i < ph.size(); ++i)
				o << "        intervals [" << i + 1 << "]:\n            xmin = " << sec(ph[i].start) << "\n            xmax = " << sec(ph[i].end)
				  << "\n            text = " << textGridString(labelOf(ph[i])) << "\n";
		};
		tier(1, "phones", [](const PhoneSegment& p) { return p.phone == "_" ? std::string() : p.phone; });
		tier(2, "cdv", [](const PhoneSegment& p) { return p.cdv.label(); });
		o << "    item [3]:\n        class = \"TextTier\"\n        name = \"keyposes\"\n        xmin = 0\n        xmax = " << sec(end)
		  << "\n        points: size = " << keys.size() << "\n";
		for (std::size_t i = 0; i < keys.size(); ++i)
			o << "        points [" << i + 1 << "]:\n            number = " << sec(keys[i].time) << "\n            mark = " << textGridString(keys[i].cdv.label())
			  << "\n";
	} else if (format == "rhubarb-tsv") {
		auto cues = rhubarbCues(ph);
		for (const auto& c : cues) o << sec(c.start).substr(0, sec(c.start).size() - 4) << '\t' << c.shape << '\n';
		o << sec(end).substr(0, sec(end).size() - 4) << "\tX\n";
	} else if (format == "rhubarb-json") {
		auto cues = rhubarbCues(ph);
		JsonArray mouthCues;
		for (const auto& c : cues)
			mouthCues.raw(JsonObject().raw("start", sec(c.start)).raw("end", sec(c.end)).add("value", c.shape).str({" ", ", ", " "}));
		JsonObject doc;
		doc.raw("metadata", JsonObject().add("soundFile", source).raw("duration", sec(end)).str(kItemLines));
		doc.raw("mouthCues", mouthCues.str(kItemLines));
		o << doc.str(kMemberLines) << "\n";
	} else {
		throw Error("unknown output format '" + format + "' (tsv, json, textgrid, rhubarb-tsv, rhubarb-json)");
	}
	return o.str();
}

}  // namespace talkhead
