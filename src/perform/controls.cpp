// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/controls.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>
#include <vector>

#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "phonetics/labels.h"
#include "phonetics/transcript.h"
#include "synth/action_units.h"

namespace talkhead {

namespace {

// Longest a control track may reach (the transcript readers' limit, D40 and issue 15).
constexpr double kMaxSeconds = 86400;

std::string formatNumber(double v) {
	char b[32];
	std::snprintf(b, sizeof b, "%g", v);
	return b;
}

// Input quoted in a message (base/text.h quoted).
std::string shown(const std::string& s) { return safeQuote(s, 40); }

struct EventReader {
	const JsonValue& v;
	const std::string& path;
	std::size_t index;  // 1-based
	long line = 0;      // a TextGrid label's line: errors name it instead of the event number
	[[noreturn]] void fail(const std::string& what) const {
		if (line > 0) throw Error(path, line, what);
		throw Error(path, 0, "event " + std::to_string(index) + ": " + what);
	}
	double number(const std::string& key, double fallback, double lo, double hi, bool required = false) const {
		const JsonValue* f = v.find(key);
		if (!f) {
			if (required) fail("missing \"" + key + "\"");
			return fallback;
		}
		if (f->kind != JsonValue::Kind::Number || !std::isfinite(f->number)) fail("\"" + key + "\" must be a number");
		if (f->number < lo || f->number > hi) fail("\"" + key + "\" " + formatNumber(f->number) + " is outside " + formatNumber(lo) + "–" + formatNumber(hi));
		return f->number;
	}
	std::string text(const std::string& key) const {
		const JsonValue* f = v.find(key);
		if (!f) fail("missing \"" + key + "\"");
		if (f->kind != JsonValue::Kind::String) fail("\"" + key + "\" must be a string");
		return f->string;
	}
	void only(std::initializer_list<const char*> keys) const {
		for (const auto& member : v.object)
			if (std::none_of(keys.begin(), keys.end(), [&](const char* known) { return member.first == known; }))
				fail("unknown field \"" + shown(member.first) + "\" for a \"" + text("type") + "\" event");
	}
};

void addEvent(ControlTrack& track, const EventReader& r) {
	const JsonValue& e = r.v;
	if (e.kind != JsonValue::Kind::Object) r.fail("an event must be an object");
	const std::string type = r.text("type");
	const Ticks time = ticksFromSeconds(r.number("time", 0, 0, kMaxSeconds, true));
	if (type == "emotion") {
		r.only({"type", "time", "emotion", "intensity", "ramp"});
		ControlTrack::EmotionChange c;
		c.time = time;
		const std::string label = r.text("emotion");
		const auto emotion = Emotion::find(label);
		if (!emotion) r.fail("unknown emotion '" + shown(label) + "' (known: " + emotionList() + ")");
		c.expression = Expression(*emotion, r.number("intensity", 1, 0, Expression::kMaxIntensity));
		c.ramp = ticksFromSeconds(r.number("ramp", 0.3, 0, 60));
		track.emotions.push_back(c);
	} else if (type == "blink") {
		r.only({"type", "time"});
		track.blinks.push_back(time);
	} else if (type == "nod" || type == "shake" || type == "turn") {
		HeadGesture g;
		g.kind = type == "nod" ? HeadGesture::Kind::Nod : type == "shake" ? HeadGesture::Kind::Shake : HeadGesture::Kind::Turn;
		g.time = time;
		g.duration = ticksFromSeconds(r.number("duration", type == "nod" ? 0.6 : type == "shake" ? 0.9 : 1.5, 0.1, 30));
		g.amount = r.number("amount", 1, 0, 3);
		if (type == "turn") {
			r.only({"type", "time", "duration", "amount", "direction"});
			const std::string d = r.text("direction");
			if (d == "left") g.directionX = 1;  // the subject's left: toward the image's right
			else if (d == "right") g.directionX = -1;
			else if (d == "up") g.directionY = -1;
			else if (d == "down") g.directionY = 1;
			else r.fail("\"direction\" '" + shown(d) + "' is not left, right, up or down");
		} else {
			r.only({"type", "time", "duration", "amount"});
		}
		track.gestures.push_back(g);
	} else if (type == "brows") {
		r.only({"type", "time", "duration", "raise", "frown"});
		BrowEvent b;
		b.time = time;
		b.duration = ticksFromSeconds(r.number("duration", 0.8, 0.2, 30));
		b.raise = r.number("raise", 0, 0, 1.5);
		b.frown = r.number("frown", 0, 0, 1.5);
		if (b.raise == 0 && b.frown == 0) r.fail("a \"brows\" event needs \"raise\" or \"frown\" (0–1.5)");
		track.brows.push_back(b);
	} else if (type == "au") {
		r.only({"type", "time", "au", "intensity", "side", "onset", "apex", "offset"});
		const std::string name = r.text("au");
		const auto au = canonicalActionUnit(name);
		if (!au) {
			std::string known;
			for (const auto& k : knownActionUnits()) known += (known.empty() ? "" : " ") + k;
			r.fail("unknown action unit '" + shown(name) + "' (known: " + known + ")");
		}
		if (*au == "AU45") {  // a blink
			track.blinks.push_back(time);
			return;
		}
		AuEvent a;
		a.au = *au;
		a.time = time;
		a.intensity = r.number("intensity", 1, 0, 1.5);
		a.onset = ticksFromSeconds(r.number("onset", 0.2, 0.02, 30));
		a.apex = ticksFromSeconds(r.number("apex", 0.5, 0, 600));
		a.offset = ticksFromSeconds(r.number("offset", 0.3, 0.02, 30));
		if (r.v.find("side")) {
			const std::string side = r.text("side");
			if (side == "left") a.side = 1;  // the subject's left (FACS L): the image's right half
			else if (side == "right") a.side = -1;
			else if (side != "both") r.fail("\"side\" '" + shown(side) + "' is not left, right or both");
		}
		track.actionUnits.push_back(a);
	} else {
		r.fail("unknown type '" + shown(type) + "' (known: emotion, blink, nod, shake, turn, brows, au)");
	}
}

void finish(ControlTrack& track) {
	std::stable_sort(track.emotions.begin(), track.emotions.end(), [](const auto& a, const auto& b) { return a.time < b.time; });
}

}  // namespace

namespace {

constexpr double kPi = 3.14159265358979323846;

// "curves" (D55): every channel an array of finite numbers within [lo, hi], all of one length.
void readCurves(ControlTrack& track, const JsonValue& c, const std::string& path) {
	auto fail = [&](const std::string& what) -> void { throw Error(path, 0, "curves: " + what); };
	if (c.kind != JsonValue::Kind::Object) fail("must be an object");
	for (const auto& m : c.object)
		if (m.first != "rate" && m.first != "start" && m.first != "head" && m.first != "au" && m.first != "lost")
			fail("unknown field \"" + shown(m.first) + "\" (known: rate, start, head, au, lost)");
	auto number = [&](const JsonValue* v, const std::string& name, double lo, double hi) {
		if (!v) fail("missing \"" + name + "\"");
		if (v->kind != JsonValue::Kind::Number || !std::isfinite(v->number)) fail("\"" + name + "\" must be a number");
		if (v->number < lo || v->number > hi) fail("\"" + name + "\" " + formatNumber(v->number) + " is outside " + formatNumber(lo) + "–" + formatNumber(hi));
		return v->number;
	};
	ControlCurves& out = track.curves;
	out.rate = number(c.find("rate"), "rate", 0.01, 1000);
	out.start = ticksFromSeconds(c.find("start") ? number(c.find("start"), "start", 0, kMaxSeconds) : 0.0);
	std::size_t length = 0;
	bool first = true;
	auto channel = [&](const JsonValue& v, const std::string& name, double lo, double hi, double factor) {
		if (v.kind != JsonValue::Kind::Array) fail("\"" + name + "\" must be an array of numbers");
		if (double(v.array.size()) > out.rate * kMaxSeconds) fail("\"" + name + "\" is longer than a day");
		if (!first && v.array.size() != length)
			fail("\"" + name + "\" has " + std::to_string(v.array.size()) + " samples, the curves before it " + std::to_string(length));
		first = false;
		length = v.array.size();
		std::vector<float> samples;
		samples.reserve(v.array.size());
		for (std::size_t i = 0; i < v.array.size(); ++i) {
			const JsonValue& x = v.array[i];
			if (x.kind != JsonValue::Kind::Number || !std::isfinite(x.number)) fail("\"" + name + "\" sample " + std::to_string(i + 1) + " is not a number");
			if (x.number < lo || x.number > hi)
				fail("\"" + name + "\" sample " + std::to_string(i + 1) + " (" + formatNumber(x.number) + ") is outside " + formatNumber(lo) + "–" + formatNumber(hi));
			samples.push_back(float(x.number * factor));
		}
		return samples;
	};
	if (const JsonValue* h = c.find("head")) {
		if (h->kind != JsonValue::Kind::Object) fail("\"head\" must be an object");
		for (const auto& [key, v] : h->object) {
			if (key == "roll") out.roll = channel(v, "head.roll", -90, 90, kPi / 180);
			else if (key == "x") out.x = channel(v, "head.x", -5, 5, 1);
			else if (key == "y") out.y = channel(v, "head.y", -5, 5, 1);
			else if (key == "scale") out.scale = channel(v, "head.scale", 0.5, 2, 1);
			else if (key == "yaw" || key == "pitch") channel(v, "head." + key, -180, 180, 1);  // informational: a 2D face does not turn
			else fail("unknown head channel \"" + shown(key) + "\" (known: roll, x, y, scale, yaw, pitch)");
		}
	}
	if (const JsonValue* a = c.find("au")) {
		if (a->kind != JsonValue::Kind::Array) fail("\"au\" must be an array");
		for (std::size_t i = 0; i < a->array.size(); ++i) {
			const EventReader r{a->array[i], path, i + 1};
			if (r.v.kind != JsonValue::Kind::Object) fail("au curve " + std::to_string(i + 1) + " must be an object");
			for (const auto& m : r.v.object)
				if (m.first != "au" && m.first != "side" && m.first != "weight") fail("au curve " + std::to_string(i + 1) + ": unknown field \"" + shown(m.first) + "\"");
			const std::string name = r.text("au");
			const auto au = canonicalActionUnit(name);
			if (!au || *au == "AU45") fail("au curve " + std::to_string(i + 1) + ": unknown action unit '" + shown(name) + "' (AU45 blinks are events)");
			ControlCurves::Au curve;
			curve.au = *au;
			if (r.v.find("side")) {
				const std::string side = r.text("side");
				if (side == "left") curve.side = 1;
				else if (side == "right") curve.side = -1;
				else if (side != "both") fail("au curve " + std::to_string(i + 1) + ": \"side\" '" + shown(side) + "' is not left, right or both");
			}
			const JsonValue* w = r.v.find("weight");
			if (!w) fail("au curve " + std::to_string(i + 1) + ": missing \"weight\"");
			curve.weight = channel(*w, curve.au + " weight", 0, 1.5, 1);
			out.aus.push_back(std::move(curve));
		}
	}
	if (const JsonValue* l = c.find("lost"); l && l->kind != JsonValue::Kind::Array) fail("\"lost\" must be an array of [start, end] pairs");
	if (length == 0) fail("no samples (give head channels or au curves)");
}

}  // namespace

ControlTrack parseControls(const std::string& text, const std::string& path) {
	const JsonValue root = parseJson(text, path);
	const JsonValue* events = &root;
	ControlTrack track;
	track.path = path;
	static const JsonValue none{JsonValue::Kind::Array};
	if (root.kind == JsonValue::Kind::Object) {
		for (const auto& m : root.object)
			if (m.first != "events" && m.first != "curves" && m.first != "drawn_blinks" && m.first != "source" && m.first != "note")
				throw Error(path, 0, "unknown field \"" + shown(m.first) + "\" (known: events, curves, drawn_blinks, source, note)");
		events = root.find("events");
		const JsonValue* curves = root.find("curves");
		if (!events && !curves) throw Error(path, 0, "a control track is {\"events\": [...]} or an array of events");
		if (curves) readCurves(track, *curves, path);
		if (const JsonValue* d = root.find("drawn_blinks")) {
			if (d->kind != JsonValue::Kind::Bool) throw Error(path, 0, "\"drawn_blinks\" must be true or false");
			track.drawnBlinks = d->boolean;
		}
		if (!events) events = &none;
	}
	if (events->kind != JsonValue::Kind::Array) throw Error(path, 0, "\"events\" must be an array");
	for (std::size_t i = 0; i < events->array.size(); ++i) addEvent(track, EventReader{events->array[i], path, i + 1});
	finish(track);
	return track;
}

namespace {

// A number as the control files write it: up to 4 decimals, trailing zeros dropped, never "-0".
std::string controlNumber(double v) {
	char b[32];
	std::snprintf(b, sizeof b, "%.4f", v);
	std::string s = b;
	while (s.size() > 1 && s.back() == '0') s.pop_back();
	if (s.back() == '.') s.pop_back();
	if (s == "-0") s = "0";
	return s;
}

std::string seconds(Ticks t) { return controlNumber(toSeconds(t)); }

const char* sideName(int side) { return side > 0 ? "left" : side < 0 ? "right" : "both"; }

// The track's events, one object each, in time order (stable: kinds in the order below at equal times).
std::vector<std::string> eventObjects(const ControlTrack& t) {
	std::vector<std::pair<Ticks, JsonObject>> events;
	auto event = [&](Ticks time, const char* type) -> JsonObject& {
		events.emplace_back(time, JsonObject());
		return events.back().second.add("type", type).raw("time", seconds(time));
	};
	for (const auto& e : t.emotions)
		event(e.time, "emotion").add("emotion", e.expression.emotion().label()).raw("intensity", controlNumber(e.expression.intensity())).raw("ramp", seconds(e.ramp));
	for (Ticks b : t.blinks) event(b, "blink");
	for (const auto& g : t.gestures) {
		JsonObject& e = event(g.time, g.kind == HeadGesture::Kind::Nod ? "nod" : g.kind == HeadGesture::Kind::Shake ? "shake" : "turn");
		e.raw("duration", seconds(g.duration)).raw("amount", controlNumber(g.amount));
		if (g.kind == HeadGesture::Kind::Turn) e.add("direction", g.directionX > 0 ? "left" : g.directionX < 0 ? "right" : g.directionY < 0 ? "up" : "down");
	}
	for (const auto& b : t.brows) {
		JsonObject& e = event(b.time, "brows").raw("duration", seconds(b.duration));
		if (b.raise > 0) e.raw("raise", controlNumber(b.raise));
		if (b.frown > 0) e.raw("frown", controlNumber(b.frown));
	}
	for (const auto& a : t.actionUnits)
		event(a.time, "au").add("au", a.au).raw("intensity", controlNumber(a.intensity)).add("side", sideName(a.side)).raw("onset", seconds(a.onset))
		    .raw("apex", seconds(a.apex)).raw("offset", seconds(a.offset));
	std::stable_sort(events.begin(), events.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
	std::vector<std::string> out;
	for (const auto& e : events) out.push_back(e.second.str());
	return out;
}

std::string curvesObject(const ControlCurves& c) {
	auto array = [](const std::vector<float>& v, double factor) {
		JsonArray a;
		for (float x : v) a.raw(controlNumber(double(x) * factor));
		return a.str({"", ",", ""});
	};
	JsonObject o;
	o.raw("rate", controlNumber(c.rate)).raw("start", seconds(c.start));
	if (c.hasHead()) {
		JsonObject h;
		using Curve = std::tuple<const char*, const std::vector<float>*, double>;
		for (const auto& [name, v, factor] : std::initializer_list<Curve>{{"roll", &c.roll, 180 / kPi}, {"x", &c.x, 1}, {"y", &c.y, 1}, {"scale", &c.scale, 1}})
			if (!v->empty()) h.raw(name, array(*v, factor));
		o.then(",\n  ").raw("head", h.str({"", ",\n   ", ""}));
	}
	if (!c.aus.empty()) {
		JsonArray aus;
		for (const auto& a : c.aus) aus.raw(JsonObject().add("au", a.au).add("side", sideName(a.side)).raw("weight", array(a.weight, 1)).str());
		o.then(",\n  ").raw("au", aus.str({"\n   ", ",\n   ", ""}));
	}
	return o.str();
}

}  // namespace

std::string controlTrackJson(const ControlTrack& t, const std::string& source, const std::string& note) {
	JsonObject o;
	if (!source.empty()) o.add("source", source);
	if (!note.empty()) o.add("note", note);
	if (!t.drawnBlinks) o.add("drawn_blinks", false);
	JsonArray events;
	for (std::string& e : eventObjects(t)) events.raw(std::move(e));
	o.raw("events", events.str({"\n  ", ",\n  ", "\n "}));
	if (!t.curves.empty()) o.raw("curves", curvesObject(t.curves));
	return o.str({"", ",\n ", ""}) + "\n";
}

ControlTrack parseControlTier(const std::string& text, const std::string& path, const std::string& tierName) {
	const std::vector<TextGridTier> tiers = readTextGridTiers(text, path);
	const TextGridTier* tier = nullptr;
	std::string names;
	for (const auto& t : tiers) {
		names += (names.empty() ? "'" : ", '") + t.name + "'";
		if (!tier && t.name == tierName) tier = &t;
	}
	if (!tier) throw Error(path, 0, "no tier named '" + shown(tierName) + "' (tiers: " + (names.empty() ? "none" : names) + ")");
	ControlTrack track;
	track.path = path;
	std::size_t index = 0;
	for (const Interval& iv : tier->intervals) {
		const std::vector<std::string> words = splitWhitespace(iv.label);
		if (words.empty()) continue;
		// "TYPE [positional values] [key=value …]": each type's positional fields, in order; an interval's
		// length is the event's duration (for au: onset, apex and offset).
		static const std::map<std::string, std::vector<std::string>> positional = {
		    {"emotion", {"emotion", "intensity", "ramp"}}, {"blink", {}},           {"nod", {"amount"}}, {"shake", {"amount"}},
		    {"turn", {"direction", "amount"}},             {"brows", {"*", "*"}},   {"au", {"au", "intensity", "side"}}};
		JsonValue e;
		e.kind = JsonValue::Kind::Object;
		auto set = [&](const std::string& key, const std::string& value) {
			JsonValue v;
			double number;
			if (parseDouble(value, number)) v.kind = JsonValue::Kind::Number, v.number = number;
			else v.kind = JsonValue::Kind::String, v.string = value;
			for (auto& m : e.object)
				if (m.first == key) throw Error(path, iv.line, "'" + shown(key) + "' given twice in '" + shown(iv.label) + "'");
			e.object.emplace_back(key, v);
		};
		set("type", words[0]);
		JsonValue t;
		t.kind = JsonValue::Kind::Number, t.number = toSeconds(iv.start);
		e.object.emplace_back("time", t);
		const auto p = positional.find(words[0]);
		std::size_t next = 0;
		std::string browKind;
		for (std::size_t w = 1; w < words.size(); ++w) {
			if (auto eq = words[w].find('='); eq != std::string::npos) {
				set(words[w].substr(0, eq), words[w].substr(eq + 1));
				continue;
			}
			if (p == positional.end() || next >= p->second.size())
				throw Error(path, iv.line, "too many values in '" + shown(iv.label) + "' (write key=value for the others)");
			if (words[0] == "brows" && next == 0) {  // brows raise|frown [amount]
				browKind = words[w];
				if (browKind != "raise" && browKind != "frown") throw Error(path, iv.line, "brows take raise or frown, not '" + shown(browKind) + "'");
				++next;
				continue;
			}
			set(words[0] == "brows" ? browKind : p->second[next], words[w]);
			++next;
		}
		if (words[0] == "brows" && !browKind.empty() && !e.find(browKind)) set(browKind, "0.8");
		const double length = toSeconds(iv.end - iv.start);
		if (length > 0 && words[0] != "au" && words[0] != "emotion" && words[0] != "blink" && !e.find("duration")) set("duration", std::to_string(length));
		if (length > 0 && words[0] == "au" && !e.find("apex")) {
			const double on = std::min(0.2, length / 3), off = std::min(0.3, length / 3);
			set("onset", std::to_string(on));
			set("offset", std::to_string(off));
			set("apex", std::to_string(std::max(0.0, length - on - off)));
		}
		addEvent(track, EventReader{e, path, ++index, iv.line});
	}
	finish(track);
	return track;
}

ControlTrack loadControlTier(const std::string& path, const std::string& tier) { return parseControlTier(readTextFile(path), path, tier); }

ControlTrack loadControls(const std::string& path) { return parseControls(readTextFile(path), path); }

void applyControls(Performance& perf, const ControlTrack& track) {
	auto past = [&](Ticks t, const std::string& what) {
		if (t > perf.duration)
			throw Error(track.path, 0, what + " at " + formatNumber(toSeconds(t)) + " s is past the end of the video (" + formatNumber(toSeconds(perf.duration)) + " s)");
	};
	for (const auto& c : track.emotions) past(c.time, "the emotion change to " + c.expression.emotion().label());
	for (Ticks t : track.blinks) past(t, "a blink");
	for (const auto& g : track.gestures) past(g.time, g.kind == HeadGesture::Kind::Nod ? "a nod" : g.kind == HeadGesture::Kind::Shake ? "a shake" : "a turn");
	for (const auto& b : track.brows) past(b.time, "a brows event");
	for (const auto& a : track.actionUnits) past(a.time, "the action unit " + a.au);
	// Each keypose takes the emotion in effect at its time.
	for (Keypose& k : perf.timeline.keys) {
		Emotion before = perf.expression.emotion();
		double beforeIntensity = perf.expression.intensity();
		for (const auto& c : track.emotions) {
			if (c.time > k.time) break;
			const double ramp = toSeconds(c.ramp), s = ramp > 0 ? toSeconds(k.time - c.time) / ramp : 1.0;
			const Emotion to = c.expression.emotion();
			const double toIntensity = c.expression.intensity();
			if (s >= 1) {
				k.emotion = to, k.intensity = toIntensity;
			} else if (s < 0.5) {  // the old emotion fading out
				k.emotion = before, k.intensity = beforeIntensity * (1 - 2 * s);
			} else {  // the new one fading in
				k.emotion = to, k.intensity = toIntensity * (2 * s - 1);
			}
			before = to, beforeIntensity = toIntensity;
		}
	}
	TimedEvents& e = perf.timeline.events;
	e.blinks.insert(e.blinks.end(), track.blinks.begin(), track.blinks.end());
	e.gestures.insert(e.gestures.end(), track.gestures.begin(), track.gestures.end());
	e.brows.insert(e.brows.end(), track.brows.begin(), track.brows.end());
	e.actionUnits.insert(e.actionUnits.end(), track.actionUnits.begin(), track.actionUnits.end());
	if (!track.curves.empty()) {
		if (track.curves.start > perf.duration) past(track.curves.start, "the curves' start");
		e.curves = track.curves;
	}
	if (!track.drawnBlinks) perf.modulation.blinks = false;
}

}  // namespace talkhead
