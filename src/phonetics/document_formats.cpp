// SPDX-License-Identifier: GPL-3.0-or-later
// Annotation documents and console outputs (issue 50): TTML, ELAN .eaf, Transcriber .trs, Rhubarb XML
// (read with pugixml), BAS Partitur, the whisper console, CLAN CHAT, YouTube .sbv.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>

#include <pugixml.hpp>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/timing_readers.h"

namespace talkhead {

namespace {

std::string localName(const char* name) {
	std::string n = name;
	if (const auto c = n.find(':'); c != std::string::npos) n = n.substr(c + 1);
	return n;
}

pugi::xml_document parseXml(const TimingSample& s) {
	pugi::xml_document doc;
	const pugi::xml_parse_result r = doc.load_buffer(s.text().data(), s.text().size(), pugi::parse_default | pugi::parse_ws_pcdata_single);
	if (!r) {
		// The line of the offset, for the message.
		long line = 1 + long(std::count(s.text().begin(), s.text().begin() + std::min<std::ptrdiff_t>(r.offset, std::ptrdiff_t(s.text().size())), '\n'));
		throw Error(s.path(), line, std::string("malformed XML: ") + r.description());
	}
	return doc;
}

// Elements nested deeper than this are an error (the readers walk the tree recursively).
constexpr int kMaxXmlDepth = 64;

// All text below a node, white space collapsed.
std::string textOf(const pugi::xml_node& n, int depth = 0) {
	std::string out;
	if (depth > kMaxXmlDepth) throw Error("XML elements nested deeper than " + std::to_string(kMaxXmlDepth));
	for (const pugi::xml_node& c : n.children()) {
		if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) out += std::string(" ") + c.value() + " ";
		else if (c.type() == pugi::node_element) {
			const std::string name = localName(c.name());
			if (name == "br") out += " ";
			else out += textOf(c, depth + 1);
		}
	}
	std::string collapsed;
	for (const std::string& w : splitWhitespace(out)) collapsed += (collapsed.empty() ? "" : " ") + w;
	return collapsed;
}

Interval timed(double a, double b, std::string label, const std::string& path, const std::string& where, long line = 0) {
	return {timing::secondsAt(a, path, where), timing::secondsAt(b, path, where), std::move(label), line};
}

// ---- TTML: <p begin end> (and <span begin end> inside), clock or offset times --------------------------
// "0.000s", "12.3s", "100ms", "1.5m", "00:00:01.500", "00:00:01:12" (frames, at ttp:frameRate), "1234t" (ticks).
std::optional<double> ttmlTime(std::string v, double frameRate, double tickRate) {
	v = std::string(trim(v));
	if (v.empty()) return std::nullopt;
	double d;
	auto unit = [&](const char* u, double scale) -> std::optional<double> {
		if (!endsWith(v, u)) return std::nullopt;
		if (!parseDouble(std::string_view(v).substr(0, v.size() - std::strlen(u)), d)) return std::nullopt;
		return d * scale;
	};
	if (auto r = unit("ms", 0.001)) return r;
	if (auto r = unit("h", 3600)) return r;
	if (auto r = unit("m", 60)) return r;
	if (auto r = unit("s", 1)) return r;
	if (auto r = unit("f", 1.0 / frameRate)) return r;
	if (auto r = unit("t", 1.0 / tickRate)) return r;
	const auto parts = split(v, ':');
	if (parts.size() == 3 || parts.size() == 4) {
		double h, m, sec, f = 0;
		if (!parseDouble(parts[0], h) || !parseDouble(parts[1], m) || !parseDouble(parts[2], sec)) return std::nullopt;
		if (parts.size() == 4 && !parseDouble(parts[3], f)) return std::nullopt;
		return h * 3600 + m * 60 + sec + f / frameRate;
	}
	return std::nullopt;
}

Transcript ttml(const TimingSample& s, const ReadOptions&) {
	const pugi::xml_document doc = parseXml(s);
	const pugi::xml_node tt = doc.document_element();
	double frameRate = 30, tickRate = 1;
	for (const pugi::xml_attribute& a : tt.attributes()) {
		const std::string n = localName(a.name());
		if (n == "frameRate") frameRate = std::max(1.0, a.as_double(30));
		if (n == "tickRate") tickRate = std::max(1.0, a.as_double(1));
	}
	Transcript tr;
	tr.level = LabelLevel::Word;
	bool sentences = false;
	// Times are relative to the parent's begin (timeContainer par, the default).
	std::function<void(const pugi::xml_node&, double, int)> walk = [&](const pugi::xml_node& n, double offset, int depth) {
		if (depth > kMaxXmlDepth) throw Error(s.path(), 0, "TTML elements nested deeper than " + std::to_string(kMaxXmlDepth));
		for (const pugi::xml_node& c : n.children()) {
			if (c.type() != pugi::node_element) continue;
			const std::string name = localName(c.name());
			const auto b = ttmlTime(c.attribute("begin").value(), frameRate, tickRate);
			auto e = ttmlTime(c.attribute("end").value(), frameRate, tickRate);
			if (!e && b)
				if (const auto d = ttmlTime(c.attribute("dur").value(), frameRate, tickRate)) e = *b + *d;
			if (name == "p" || (name == "span" && b && e)) {
				// A <p> whose spans are timed: the spans are the words.
				bool timedSpans = false;
				for (const pugi::xml_node& sp : c.children("span")) timedSpans |= !sp.attribute("begin").empty();
				if (name == "p" && timedSpans) {
					walk(c, offset + (b ? *b : 0), depth + 1);
					continue;
				}
				if (!b || !e) throw Error(s.path(), 0, "<" + name + "> '" + safeQuote(textOf(c), 30) + "' has no begin and end (or dur)");
				const std::string text = textOf(c);
				sentences |= text.find(' ') != std::string::npos;
				tr.intervals.push_back(timed(offset + *b, offset + *e, text, s.path(), "<" + name + " begin=" + c.attribute("begin").value() + ">"));
				continue;
			}
			walk(c, offset + (b ? *b : 0), depth + 1);
		}
	};
	walk(tt, 0, 0);
	if (tr.intervals.empty()) throw Error(s.path(), 0, "a TTML document with no timed <p> or <span>");
	if (sentences)
		tr.warnings.push_back("cues hold several words: each cue's phones are spread by espeak-ng's durations (approximate; word-level cues, or talkhead align on the audio, time them)");
	return tr;
}

// ---- ELAN .eaf: time slots (ms), alignable annotations per tier; tiers as speakers ---------------------
Transcript elan(const TimingSample& s, const ReadOptions& o) {
	const pugi::xml_document doc = parseXml(s);
	const pugi::xml_node root = doc.child("ANNOTATION_DOCUMENT");
	const std::string units = root.child("HEADER").attribute("TIME_UNITS").as_string("milliseconds");
	if (units != "milliseconds") throw Error(s.path(), 0, "ELAN TIME_UNITS '" + safeQuote(units) + "': only milliseconds are defined by EAF");
	std::map<std::string, double> slots;
	for (const pugi::xml_node& t : root.child("TIME_ORDER").children("TIME_SLOT"))
		if (!t.attribute("TIME_VALUE").empty()) slots[t.attribute("TIME_SLOT_ID").value()] = t.attribute("TIME_VALUE").as_double() / 1000;
	struct Tier {
		std::string id, participant;
		std::vector<Interval> intervals;
	};
	std::vector<Tier> tiers;
	for (const pugi::xml_node& t : root.children("TIER")) {
		Tier tier{t.attribute("TIER_ID").value(), t.attribute("PARTICIPANT").value(), {}};
		for (const pugi::xml_node& a : t.children("ANNOTATION")) {
			const pugi::xml_node al = a.child("ALIGNABLE_ANNOTATION");
			if (!al) continue;  // symbolic (REF_ANNOTATION) tiers hang on another tier's times
			const auto x = slots.find(al.attribute("TIME_SLOT_REF1").value()), y = slots.find(al.attribute("TIME_SLOT_REF2").value());
			if (x == slots.end() || y == slots.end()) continue;  // an unaligned slot: no time
			tier.intervals.push_back(timed(x->second, y->second, textOf(al.child("ANNOTATION_VALUE")), s.path(),
			                               "annotation " + std::string(al.attribute("ANNOTATION_ID").value())));
		}
		if (!tier.intervals.empty()) tiers.push_back(std::move(tier));
	}
	if (tiers.empty()) throw Error(s.path(), 0, "an ELAN file with no time-aligned annotation");
	std::vector<std::string> names;
	for (const Tier& t : tiers) names.push_back(t.id);
	// A tier by its id, or by its participant.
	ReadOptions byId = o;
	for (const Tier& t : tiers)
		if (!o.tier.empty() && o.tier != t.id && o.tier == t.participant) byId.tier = t.id;
	const std::string chosen = timing::chooseSpeaker(names, byId, s.path(), "tier");
	Transcript tr;
	tr.level = LabelLevel::Word;
	tr.speakers = names;
	for (const Tier& t : tiers)
		if (t.id == chosen) tr.intervals = t.intervals, tr.speaker = t.id, tr.tier = t.id;
	tr.tierNote = "words" + std::string(tiers.size() > 1 ? "; {{tier}}" : "");
	// Overlapping annotations in one tier (ELAN allows none in a top-level tier; a file may still hold them).
	return tr;
}

// ---- Transcriber .trs: <Turn speaker startTime endTime> with <Sync time/> points ------------------------
Transcript transcriber(const TimingSample& s, const ReadOptions& o) {
	const pugi::xml_document doc = parseXml(s);
	const pugi::xml_node trans = doc.child("Trans");
	std::map<std::string, std::string> names;  // spk1 → "Nicola"
	for (const pugi::xml_node& sp : trans.child("Speakers").children("Speaker")) names[sp.attribute("id").value()] = sp.attribute("name").value();
	struct Piece {
		double a, b;
		std::string text, speaker;
	};
	std::vector<Piece> pieces;
	int events = 0;
	for (const pugi::xml_node& sec : trans.child("Episode").children("Section"))
		for (const pugi::xml_node& turn : sec.children("Turn")) {
			const double end = turn.attribute("endTime").as_double();
			std::string speaker = turn.attribute("speaker").value();
			if (names.count(speaker) && !names[speaker].empty()) speaker = names[speaker];
			double at = turn.attribute("startTime").as_double();
			std::string text;
			auto flush = [&](double until) {
				std::string t(trim(text));
				if (!t.empty()) pieces.push_back({at, until, t, speaker});
				text.clear();
			};
			for (const pugi::xml_node& c : turn.children()) {
				if (c.type() == pugi::node_pcdata) text += std::string(" ") + c.value();
				else if (std::string(c.name()) == "Sync") {
					flush(c.attribute("time").as_double());
					at = c.attribute("time").as_double();
				} else if (std::string(c.name()) == "Event" || std::string(c.name()) == "Comment" || std::string(c.name()) == "Background") ++events;
				else if (std::string(c.name()) == "Who") text += " ";
			}
			flush(end);
		}
	std::vector<std::string> speakers;
	for (const Piece& p : pieces)
		if (std::find(speakers.begin(), speakers.end(), p.speaker) == speakers.end()) speakers.push_back(p.speaker);
	Transcript tr;
	tr.level = LabelLevel::Word;
	tr.speakers = speakers;
	tr.speaker = timing::chooseSpeaker(speakers, o, s.path(), "speaker");
	for (const Piece& p : pieces)
		if (p.speaker == tr.speaker || tr.speaker.empty()) tr.intervals.push_back(timed(p.a, p.b, p.text, s.path(), "a turn of " + p.speaker));
	if (tr.intervals.empty()) throw Error(s.path(), 0, "a Transcriber file with no transcribed turn");
	if (events) tr.warnings.push_back(std::to_string(events) + " Transcriber event" + (events > 1 ? "s" : "") + " (noise, comments) not spoken");
	return tr;
}

// ---- Rhubarb Lip Sync XML: <mouthCue start end>SHAPE</mouthCue>, metadata/duration ----------------------
Transcript rhubarbXml(const TimingSample& s, const ReadOptions&) {
	const pugi::xml_document doc = parseXml(s);
	const pugi::xml_node r = doc.child("rhubarbResult");
	Transcript tr;
	tr.level = LabelLevel::Viseme;
	tr.visemeScheme = "rhubarb";
	long k = 0;
	for (const pugi::xml_node& c : r.child("mouthCues").children("mouthCue")) {
		++k;
		double a, b;
		if (!parseDouble(c.attribute("start").value(), a) || !parseDouble(c.attribute("end").value(), b))
			throw Error(s.path(), 0, "mouthCue " + std::to_string(k) + " needs start and end (seconds)");
		tr.intervals.push_back(timed(a, b, std::string(trim(c.text().get())), s.path(), "mouthCue " + std::to_string(k), k));
	}
	if (tr.intervals.empty()) throw Error(s.path(), 0, "a Rhubarb XML file with no <mouthCue>");
	double d;
	if (parseDouble(r.child("metadata").child("duration").text().get(), d)) tr.statedDuration = d;
	return tr;
}

// ---- BAS Partitur (.par): MAU tier "begin duration word phone" in samples at SAM Hz, SAMPA -------------
Transcript basPartitur(const TimingSample& s, const ReadOptions&) {
	double rate = 0;
	Transcript tr;
	tr.level = LabelLevel::Phone;
	long no = 0;
	std::vector<std::pair<long, std::vector<std::string>>> mau;
	bool kan = false;
	for (const std::string& raw : split(s.text(), '\n')) {
		++no;
		const std::string l(trim(raw));
		if (startsWith(l, "SAM:")) {
			if (!parseDouble(trim(std::string_view(l).substr(4)), rate) || rate < 1000 || rate > 384000)
				throw Error(s.path(), no, "SAM: '" + safeQuote(l.substr(4)) + "' is no sample rate");
		}
		if (startsWith(l, "MAU:")) mau.emplace_back(no, splitWhitespace(std::string_view(l).substr(4)));
		kan |= startsWith(l, "KAN:") || startsWith(l, "ORT:");
	}
	if (rate == 0) throw Error(s.path(), 0, "a BAS Partitur file without SAM: (its sample rate): its times are samples");
	if (mau.empty())
		throw Error(s.path(), 0, std::string("a BAS Partitur file without a MAU tier (the phone segmentation)") +
		                             (kan ? ": run WebMAUS with output format 'par' (or export a TextGrid), which holds MAU" : ""));
	for (const auto& [line, f] : mau) {
		long long b, d;
		if (f.size() < 4 || !parseInt(f[0], b) || !parseInt(f[1], d) || b < 0 || d < 0 || b > 1'000'000'000'000LL || d > 1'000'000'000'000LL)
			throw Error(s.path(), line, "expected 'MAU: begin duration word phone' (samples), found '" + safeQuote(joined(f, " ")) + "'");
		// Duration is the last sample's offset: the segment covers d + 1 samples.
		tr.intervals.push_back(timed(double(b) / rate, double(b + d + 1) / rate, f[3] == "<p:>" || f[3] == "<p>" ? "" : f[3], s.path(), "MAU", line));
	}
	tr.unit = "samples at " + std::to_string(long(rate)) + " Hz";
	return tr;
}

// ---- the whisper console: "[00:00.000 --> 00:04.000]  text" lines --------------------------------------
std::optional<double> clockTime(std::string_view v) {
	const auto parts = split(trim(v), ':');
	if (parts.size() < 2 || parts.size() > 3) return std::nullopt;
	double h = 0, m, sec;
	if (parts.size() == 3 && !parseDouble(parts[0], h)) return std::nullopt;
	if (!parseDouble(parts[parts.size() - 2], m) || !parseDouble(parts.back(), sec) || sec >= 60 || (m >= 60 && parts.size() == 3)) return std::nullopt;
	return h * 3600 + m * 60 + sec;
}

struct ConsoleLine {
	double a, b;
	std::string text;
};
std::optional<ConsoleLine> consoleLine(std::string_view l) {
	if (l.empty() || l[0] != '[') return std::nullopt;
	const auto close = l.find(']');
	const auto arrow = l.find("-->");
	if (close == std::string_view::npos || arrow == std::string_view::npos || arrow > close) return std::nullopt;
	const auto a = clockTime(l.substr(1, arrow - 1)), b = clockTime(l.substr(arrow + 3, close - arrow - 3));
	if (!a || !b) return std::nullopt;
	return ConsoleLine{*a, *b, std::string(trim(l.substr(close + 1)))};
}

bool isWhisperConsole(const TimingSample& s) {
	int timed = 0;
	for (const std::string& l : s.firstLines()) {
		if (l.empty() || l[0] == '#') continue;
		if (!consoleLine(l)) return false;
		++timed;
	}
	return timed > 0;
}

Transcript whisperConsole(const TimingSample& s, const ReadOptions&) {
	Transcript tr;
	tr.level = LabelLevel::Word;
	long no = 0;
	for (const std::string& raw : split(s.text(), '\n')) {
		++no;
		const std::string l(trim(raw));
		if (l.empty() || l[0] == '#') continue;
		const auto c = consoleLine(l);
		if (!c) throw Error(s.path(), no, "expected '[mm:ss.mmm --> mm:ss.mmm]  text', found '" + safeQuote(l) + "'");
		tr.intervals.push_back(timed(c->a, c->b, c->text, s.path(), "line " + std::to_string(no), no));
	}
	tr.warnings.push_back("segments hold several words: each segment's phones are spread by espeak-ng's durations (approximate; whisper --word_timestamps True, or talkhead align on the audio, time them)");
	return tr;
}

// ---- CLAN CHAT (.cha): "*SPK:\ttext \x15start_end\x15" utterances with media bullets in ms --------------
std::string chatText(std::string t) {
	// CHAT codes: [/] [//] [: word] [*] [+ …] postcodes, &=laughs events, &-uh fillers (spoken: kept),
	// &+fragments, xxx/yyy/www unintelligible, (.) pauses, +... +/. terminators, 0word omitted words.
	std::string out;
	for (std::string w : splitWhitespace(t)) {
		if (w.empty()) continue;
		if (startsWith(w, "&=") || w == "xxx" || w == "yyy" || w == "www" || startsWith(w, "0") || startsWith(w, "+") || startsWith(w, "(.")) continue;
		if (startsWith(w, "&-") || startsWith(w, "&+")) w = w.substr(2);
		w.erase(std::remove_if(w.begin(), w.end(), [](char c) { return c == '(' || c == ')' || c == '@' || c == '^'; }), w.end());
		if (const auto at = w.find('@'); at != std::string::npos) w.resize(at);
		if (w == "." || w == "?" || w == "!") continue;
		out += (out.empty() ? "" : " ") + w;
	}
	return out;
}

Transcript chat(const TimingSample& s, const ReadOptions& o) {
	struct Utt {
		double a, b;
		std::string text, speaker;
		long line;
	};
	std::vector<Utt> utts;
	long no = 0, untimed = 0;
	std::string current;
	long currentLine = 0;
	auto finish = [&]() {
		if (current.empty()) return;
		const auto b1 = current.find('\x15');
		const auto b2 = b1 == std::string::npos ? std::string::npos : current.find('\x15', b1 + 1);
		const auto colon = current.find(':');
		if (b1 == std::string::npos || b2 == std::string::npos) {
			++untimed;
			current.clear();
			return;
		}
		const std::string bullet = current.substr(b1 + 1, b2 - b1 - 1);
		const auto us = bullet.find('_');
		long long a, b;
		if (us == std::string::npos || !parseInt(bullet.substr(0, us), a) || !parseInt(bullet.substr(us + 1), b))
			throw Error(s.path(), currentLine, "a media bullet '" + safeQuote(bullet) + "' is not 'start_end' in ms");
		std::string text = current.substr(colon + 1, b1 - colon - 1);
		// Bracketed CHAT codes ([/], [: x], [+ …]) are no speech.
		for (std::size_t p; (p = text.find('[')) != std::string::npos;) {
			const auto q = text.find(']', p);
			if (q == std::string::npos) break;
			text.erase(p, q - p + 1);
		}
		utts.push_back({double(a) / 1000, double(b) / 1000, chatText(text), current.substr(1, colon - 1), currentLine});
		current.clear();
	};
	for (const std::string& raw : split(s.text(), '\n')) {
		++no;
		std::string l = raw;
		if (!l.empty() && l.back() == '\r') l.pop_back();
		if (!l.empty() && l[0] == '*') {
			finish();
			current = l, currentLine = no;
		} else if (!l.empty() && l[0] == '\t' && !current.empty()) {
			current += " " + l;  // a continuation line
		} else {
			finish();
		}
	}
	finish();
	if (utts.empty()) throw Error(s.path(), 0, "a CHAT file without media bullets (start_end in ms) on its utterances: link it to its media in CLAN (or export a TextGrid)");
	std::vector<std::string> speakers;
	for (const Utt& u : utts)
		if (std::find(speakers.begin(), speakers.end(), u.speaker) == speakers.end()) speakers.push_back(u.speaker);
	Transcript tr;
	tr.level = LabelLevel::Word;
	tr.speakers = speakers;
	tr.speaker = timing::chooseSpeaker(speakers, o, s.path(), "speaker");
	for (const Utt& u : utts)
		if (u.speaker == tr.speaker) tr.intervals.push_back(timed(u.a, u.b, u.text, s.path(), "utterance", u.line));
	tr.unit = "ms";
	if (untimed) tr.warnings.push_back(std::to_string(untimed) + " utterance" + (untimed > 1 ? "s" : "") + " without a media bullet left out");
	return tr;
}

// ---- YouTube .sbv: "0:00:01.000,0:00:03.000" then the text ----------------------------------------------
std::optional<std::pair<double, double>> sbvTimes(std::string_view l) {
	const auto comma = l.find(',');
	if (comma == std::string_view::npos) return std::nullopt;
	const auto a = clockTime(l.substr(0, comma)), b = clockTime(l.substr(comma + 1));
	if (!a || !b || split(l.substr(0, comma), ':').size() != 3) return std::nullopt;
	return std::make_pair(*a, *b);
}

Transcript sbv(const TimingSample& s, const ReadOptions&) {
	Transcript tr;
	tr.level = LabelLevel::Word;
	const auto lines = split(s.text(), '\n');
	for (std::size_t i = 0; i < lines.size(); ++i) {
		const auto t = sbvTimes(trim(lines[i]));
		if (!t) continue;
		std::string text;
		std::size_t j = i + 1;
		for (; j < lines.size() && !trim(lines[j]).empty(); ++j) text += " " + std::string(trim(lines[j]));
		tr.intervals.push_back(timed(t->first, t->second, std::string(trim(text)), s.path(), "cue", long(i + 1)));
		i = j;
	}
	if (tr.intervals.empty()) throw Error(s.path(), 0, "no '0:00:01.000,0:00:03.000' cue in this .sbv file");
	return tr;
}

// ---- openai-whisper's TSV and whisper.cpp's CSV: "start end text" with a header, times in integer ms --------
bool msTable(const TimingSample& s, char sep) {
	const auto& l = s.firstLines();
	if (l.empty()) return false;
	const auto h = split(l[0], sep);
	if (h.size() != 3 || toLower(trim(h[0])) != "start" || toLower(trim(h[1])) != "end" || toLower(trim(h[2])) != "text") return false;
	for (std::size_t i = 1; i < l.size() && i < 50; ++i) {
		if (l[i].empty()) continue;
		const auto f = split(l[i], sep);
		long long a, b;
		if (f.size() < 3 || !parseInt(trim(f[0]), a) || !parseInt(trim(f[1]), b)) return false;
	}
	return l.size() > 1;
}

Transcript msTableRead(const TimingSample& s, char sep) {
	Transcript tr;
	tr.level = LabelLevel::Word;
	long no = 0;
	bool sentences = false;
	for (const std::string& raw : split(s.text(), '\n')) {
		++no;
		std::string l(trim(raw));
		if (no == 1 || l.empty()) continue;
		std::vector<std::string> f = sep == ',' ? splitCsvRecord(l) : split(l, sep);
		long long a, b;
		if (f.size() < 3 || !parseInt(trim(f[0]), a) || !parseInt(trim(f[1]), b) || a < 0 || b < 0 || b > 86'400'000LL)
			throw Error(s.path(), no, "expected 'start end text' in milliseconds, found '" + safeQuote(l) + "'");
		std::string text = f[2];
		for (std::size_t k = 3; k < f.size(); ++k) text += std::string(1, sep) + f[k];
		text = std::string(trim(text));
		sentences |= text.find(' ') != std::string::npos;
		tr.intervals.push_back(timed(double(a) / 1000, double(b) / 1000, text, s.path(), "line " + std::to_string(no), no));
	}
	tr.unit = "ms";
	if (sentences)
		tr.warnings.push_back("segments hold several words: each segment's phones are spread by espeak-ng's durations (approximate; word timestamps, or talkhead align on the audio, time them)");
	return tr;
}

// ---- LRC lyrics ("[mm:ss.xx] line"; whisper.cpp -olrc): each line until the next ------------------------
std::optional<std::pair<double, std::string>> lrcLine(std::string_view l) {
	if (l.size() < 7 || l[0] != '[') return std::nullopt;
	const auto close = l.find(']');
	if (close == std::string_view::npos) return std::nullopt;
	const auto t = clockTime(l.substr(1, close - 1));
	if (!t) return std::nullopt;
	return std::make_pair(*t, std::string(trim(l.substr(close + 1))));
}

bool isLrc(const TimingSample& s) {
	int timed = 0;
	for (const std::string& l : s.firstLines()) {
		if (l.empty()) continue;
		if (lrcLine(l)) {
			++timed;
			continue;
		}
		// Tags ([ar:…], [by:…], [length: 03:20]) are allowed; anything else is not LRC.
		if (l[0] != '[' || l.find(':') == std::string::npos || l.back() != ']') return false;
	}
	return timed >= 2;
}

Transcript lrc(const TimingSample& s, const ReadOptions&) {
	std::vector<std::pair<double, std::pair<std::string, long>>> lines;
	long no = 0;
	for (const std::string& raw : split(s.text(), '\n')) {
		++no;
		if (const auto x = lrcLine(trim(raw))) lines.push_back({x->first, {x->second, no}});
	}
	Transcript tr;
	tr.level = LabelLevel::Word;
	for (std::size_t i = 0; i + 1 < lines.size(); ++i)
		tr.intervals.push_back(timed(lines[i].first, lines[i + 1].first, lines[i].second.first, s.path(), "line", lines[i].second.second));
	tr.warnings.push_back("lines hold several words: each line's phones are spread by espeak-ng's durations until the next line (approximate)");
	// LRC times starts only: the last line ends 0.35 s a word later (a typical speaking rate), said in a warning.
	if (!lines.empty() && !lines.back().second.first.empty()) {
		const double words = double(splitWhitespace(lines.back().second.first).size());
		tr.intervals.push_back(timed(lines.back().first, lines.back().first + std::max(1.0, 0.35 * words), lines.back().second.first, s.path(), "line", lines.back().second.second));
		tr.warnings.push_back("the last line has no end (LRC gives starts only): it lasts 0.35 s a word");
	}
	return tr;
}

// ---- EXMARaLDA basic transcription (.exb): a common timeline of points, events per speaker tier ------------
Transcript exmaralda(const TimingSample& s, const ReadOptions& o) {
	const pugi::xml_document doc = parseXml(s);
	const pugi::xml_node bt = doc.child("basic-transcription");
	std::map<std::string, double> points;
	for (const pugi::xml_node& t : bt.child("basic-body").child("common-timeline").children("tli"))
		if (!t.attribute("time").empty()) points[t.attribute("id").value()] = t.attribute("time").as_double();
	std::map<std::string, std::string> abbreviations;
	for (const pugi::xml_node& sp : bt.child("head").child("speakertable").children("speaker"))
		abbreviations[sp.attribute("id").value()] = sp.child_value("abbreviation");
	struct Tier {
		std::string name;
		std::vector<Interval> intervals;
	};
	std::vector<Tier> tiers;
	for (const pugi::xml_node& t : bt.child("basic-body").children("tier")) {
		if (std::string(t.attribute("type").value()) != "t") continue;  // annotation (a) and description (d) tiers are no speech
		std::string name = t.attribute("speaker").value();
		if (abbreviations.count(name) && !abbreviations[name].empty()) name = abbreviations[name];
		if (name.empty()) name = t.attribute("id").value();
		Tier tier{name, {}};
		std::string text;
		double start = -1, end = -1;
		for (const pugi::xml_node& e : t.children("event")) {
			const auto a = points.find(e.attribute("start").value()), b = points.find(e.attribute("end").value());
			// Events between points without a time join the timed ones around them.
			if (a != points.end() && start < 0) start = a->second;
			text += e.child_value();
			if (b != points.end()) {
				end = b->second;
				if (start >= 0) tier.intervals.push_back(timed(start, end, std::string(trim(text)), s.path(), "an event of " + name));
				text.clear();
				start = -1;
			}
		}
		if (!tier.intervals.empty()) tiers.push_back(std::move(tier));
	}
	if (tiers.empty()) throw Error(s.path(), 0, "an EXMARaLDA transcription with no timed event in a transcription (type t) tier");
	std::vector<std::string> names;
	for (const Tier& t : tiers) names.push_back(t.name);
	Transcript tr;
	tr.level = LabelLevel::Word;
	tr.speakers = names;
	tr.speaker = timing::chooseSpeaker(names, o, s.path(), "speaker");
	for (const Tier& t : tiers)
		if (t.name == tr.speaker) tr.intervals = t.intervals;
	return tr;
}

}  // namespace

void registerDocumentTimingFormats(std::vector<TimingFormat>& v) {
	v.push_back(timing::makeFormat("ttml", "TTML / IMSC captions (aeneas, broadcasters)", {".ttml", ".dfxp", ".xml"}, "sentences or words (timed spans)",
	                  "begin/end/dur clock and offset times; xml:lang", 3, [](const TimingSample& s) { return s.xmlRoot() == "tt"; }, ttml));
	v.push_back(timing::makeFormat("elan", "ELAN annotation document (.eaf)", {".eaf"}, "sentences (annotations)", "time slots in ms; tiers as speakers ({{tier}}); LANG_REF", 3,
	                  [](const TimingSample& s) { return s.xmlRoot() == "ANNOTATION_DOCUMENT"; }, elan));
	v.push_back(timing::makeFormat("transcriber", "Transcriber (.trs)", {".trs"}, "sentences (turns between syncs)", "times in s; speakers; events as pauses", 3,
	                  [](const TimingSample& s) { return s.xmlRoot() == "Trans"; }, transcriber));
	v.push_back(timing::makeFormat("rhubarb-xml", "Rhubarb Lip Sync XML", {".xml"}, "visemes (Rhubarb's A–H, X)", "times in s; metadata/duration", 3,
	                  [](const TimingSample& s) { return s.xmlRoot() == "rhubarbResult"; }, rhubarbXml));
	v.push_back(timing::makeFormat("bas-partitur", "BAS Partitur (WebMAUS .par)", {".par"}, "phones (SAMPA)", "MAU tier in samples at SAM: Hz", 3,
	                  [](const TimingSample& s) {
		                  const auto& l = s.firstLines();
		                  if (!l.empty() && startsWith(l[0], "LHD:")) return true;
		                  int keys = 0;
		                  for (const std::string& x : l) keys += x.size() > 4 && x[3] == ':' && std::isupper(static_cast<unsigned char>(x[0])) &&
		                                                         std::isupper(static_cast<unsigned char>(x[1])) && std::isupper(static_cast<unsigned char>(x[2]));
		                  return keys >= 3 && std::any_of(l.begin(), l.end(), [](const std::string& x) { return startsWith(x, "SAM:"); });
	                  },
	                  basPartitur));
	v.push_back(timing::makeFormat("whisper-console", "openai-whisper console output ([mm:ss.mmm --> mm:ss.mmm]  text)", {".wt", ".txt", ".log"}, "sentences (segments)",
	                  "times mm:ss.mmm", 3, isWhisperConsole, whisperConsole));
	v.push_back(timing::makeFormat("chat", "CLAN CHAT (.cha) with media bullets", {".cha"}, "sentences (utterances)", "bullets in ms; speakers (*SPK:); @Languages", 3,
	                  [](const TimingSample& s) { return startsWith(s.trimmed(), "@UTF8") || startsWith(s.trimmed(), "@Begin"); }, chat));
	v.push_back(timing::makeFormat("sbv", "YouTube SubViewer (.sbv)", {".sbv"}, "sentences (cues)", "times h:mm:ss.mmm", 2,
	                  [](const TimingSample& s) {
		                  for (const std::string& l : s.firstLines())
			                  if (!l.empty()) return sbvTimes(l).has_value();
		                  return false;
	                  },
	                  sbv));
	v.push_back(timing::makeFormat("whisper-tsv", "openai-whisper TSV (start, end, text in ms)", {".tsv"}, "sentences (segments)", "times in ms", 2,
	                  [](const TimingSample& s) { return msTable(s, '\t'); }, [](const TimingSample& s, const ReadOptions&) { return msTableRead(s, '\t'); }));
	v.push_back(timing::makeFormat("whispercpp-csv", "whisper.cpp CSV (whisper-cli -ocsv: start, end, text in ms)", {".csv"}, "sentences (segments)", "times in ms", 2,
	                  [](const TimingSample& s) { return msTable(s, ','); }, [](const TimingSample& s, const ReadOptions&) { return msTableRead(s, ','); }));
	v.push_back(timing::makeFormat("lrc", "LRC lyrics ([mm:ss.xx] line; whisper-cli -olrc)", {".lrc"}, "sentences (lines)", "start times mm:ss.xx; each line until the next", 3, isLrc, lrc));
	v.push_back(timing::makeFormat("exmaralda", "EXMARaLDA basic transcription (.exb)", {".exb"}, "sentences (events)", "a common timeline in s; speakers (tiers of type t)", 3,
	                  [](const TimingSample& s) { return s.xmlRoot() == "basic-transcription"; }, exmaralda));
	// Named and refused: formats people try that hold no timing of speech talkhead can use.
	v.push_back(timing::makeFormat("microdvd", "MicroDVD subtitles ({start frame}{end frame}text)", {".sub"}, "", "", 3,
	                  [](const TimingSample& s) {
		                  const auto& l = s.firstLines();
		                  return !l.empty() && l[0].size() > 4 && l[0][0] == '{' && std::isdigit(static_cast<unsigned char>(l[0][1])) && l[0].find("}{") != std::string::npos;
	                  },
	                  nullptr, "not read: its times are frame numbers of a video; export SRT or WebVTT (Subtitle Edit, Aegisub)"));
	v.push_back(timing::makeFormat("ass", "Advanced SubStation Alpha subtitles (.ass/.ssa)", {".ass", ".ssa"}, "", "", 3,
	                  [](const TimingSample& s) { return startsWith(s.trimmed(), "[Script Info]"); }, nullptr,
	                  "not read: export SRT or WebVTT from the subtitle editor (Aegisub: File > Export Subtitles)"));
	v.push_back(timing::makeFormat("praat-collection", "Praat binary or collection file", {".textgrid", ".collection"}, "", "", 3,
	                  [](const TimingSample& s) { return startsWith(s.trimmed(), "ooBinaryFile") || (s.trimmed().substr(0, 200).find("Collection") != std::string_view::npos && startsWith(s.trimmed(), "File type")); },
	                  nullptr, "not read: save the TextGrid as a text file from Praat (Save as text file…)"));
}

}  // namespace talkhead
