// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/controls.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "phonetics/labels.h"

namespace talkhead {

namespace {

// Longest a control track may reach (the transcript readers' limit, D40 and issue 15).
constexpr double kMaxSeconds = 86400;

std::string formatNumber(double v) {
	char b[32];
	std::snprintf(b, sizeof b, "%g", v);
	return b;
}

// Input quoted in a message: control bytes escaped, at most 40 bytes, never cut inside a UTF-8 character.
std::string shown(const std::string& s) {
	std::string o;
	std::size_t i = 0;
	for (; i < s.size() && o.size() < 40; ++i) {
		const unsigned char c = static_cast<unsigned char>(s[i]);
		if (c < 0x20 || c == 0x7f) {
			char b[8];
			std::snprintf(b, sizeof b, "\\x%02x", c);
			o += b;
		} else {
			o += char(c);
		}
	}
	if (i < s.size()) {
		while (!o.empty() && (static_cast<unsigned char>(o.back()) & 0xC0) == 0x80) o.pop_back();  // continuation bytes
		if (!o.empty() && static_cast<unsigned char>(o.back()) >= 0xC0) o.pop_back();             // a lead byte left alone
		o += "…";
	}
	return o;
}

struct EventReader {
	const JsonValue& v;
	const std::string& path;
	std::size_t index;  // 1-based
	[[noreturn]] void fail(const std::string& what) const { throw Error(path, 0, "event " + std::to_string(index) + ": " + what); }
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

}  // namespace

ControlTrack parseControls(const std::string& text, const std::string& path) {
	const JsonValue root = parseJson(text, path);
	const JsonValue* events = &root;
	if (root.kind == JsonValue::Kind::Object) {
		events = root.find("events");
		if (!events) throw Error(path, 0, "a control track is {\"events\": [...]} or an array of events");
	}
	if (events->kind != JsonValue::Kind::Array) throw Error(path, 0, "\"events\" must be an array");
	ControlTrack track;
	track.path = path;
	for (std::size_t i = 0; i < events->array.size(); ++i) {
		const JsonValue& e = events->array[i];
		const EventReader r{e, path, i + 1};
		if (e.kind != JsonValue::Kind::Object) r.fail("an event must be an object");
		const std::string type = r.text("type");
		const Ticks time = ticksFromSeconds(r.number("time", 0, 0, kMaxSeconds, true));
		if (type == "emotion") {
			r.only({"type", "time", "emotion", "intensity", "ramp"});
			ControlTrack::EmotionChange c;
			c.time = time;
			const std::string label = r.text("emotion");
			const auto canonical = canonicalEmotion(label);
			if (!canonical) r.fail("unknown emotion '" + shown(label) + "' (known: " + emotionList() + ")");
			c.emotion = *canonical;
			c.intensity = r.number("intensity", 1, 0, 1.5);
			c.ramp = ticksFromSeconds(r.number("ramp", 0.3, 0, 60));
			track.emotions.push_back(c);
		} else if (type == "blink") {
			r.only({"type", "time"});
			track.blinks.push_back(time);
		} else if (type == "nod" || type == "shake") {
			r.only({"type", "time", "duration", "amount"});
			HeadGesture g;
			g.kind = type == "nod" ? HeadGesture::Kind::Nod : HeadGesture::Kind::Shake;
			g.time = time;
			g.duration = ticksFromSeconds(r.number("duration", type == "nod" ? 0.6 : 0.9, 0.1, 10));
			g.amount = r.number("amount", 1, 0, 3);
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
		} else {
			r.fail("unknown type '" + shown(type) + "' (known: emotion, blink, nod, shake, brows)");
		}
	}
	std::stable_sort(track.emotions.begin(), track.emotions.end(), [](const auto& a, const auto& b) { return a.time < b.time; });
	return track;
}

ControlTrack loadControls(const std::string& path) { return parseControls(readTextFile(path), path); }

void applyControls(Performance& perf, const ControlTrack& track) {
	auto past = [&](Ticks t, const std::string& what) {
		if (t > perf.duration)
			throw Error(track.path, 0, what + " at " + formatNumber(toSeconds(t)) + " s is past the end of the video (" + formatNumber(toSeconds(perf.duration)) + " s)");
	};
	for (const auto& c : track.emotions) past(c.time, "the emotion change to " + c.emotion);
	for (Ticks t : track.blinks) past(t, "a blink");
	for (const auto& g : track.gestures) past(g.time, g.kind == HeadGesture::Kind::Nod ? "a nod" : "a shake");
	for (const auto& b : track.brows) past(b.time, "a brows event");
	// Each keypose takes the emotion in effect at its time.
	for (Keypose& k : perf.keys) {
		std::string before = perf.emotion;
		double beforeIntensity = perf.intensity;
		for (const auto& c : track.emotions) {
			if (c.time > k.time) break;
			const double ramp = toSeconds(c.ramp), s = ramp > 0 ? toSeconds(k.time - c.time) / ramp : 1.0;
			if (s >= 1) {
				k.emotion = c.emotion, k.intensity = c.intensity;
			} else if (s < 0.5) {  // the old emotion fading out
				k.emotion = before, k.intensity = beforeIntensity * (1 - 2 * s);
			} else {  // the new one fading in
				k.emotion = c.emotion, k.intensity = c.intensity * (2 * s - 1);
			}
			before = c.emotion, beforeIntensity = c.intensity;
		}
	}
	perf.modulation.forcedBlinks.insert(perf.modulation.forcedBlinks.end(), track.blinks.begin(), track.blinks.end());
	perf.modulation.gestures.insert(perf.modulation.gestures.end(), track.gestures.begin(), track.gestures.end());
	perf.modulation.browEvents.insert(perf.modulation.browEvents.end(), track.brows.begin(), track.brows.end());
}

}  // namespace talkhead
