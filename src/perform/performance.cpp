// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/performance.h"

#include <cstdio>

#include "base/json.h"
#include "base/text.h"

namespace talkhead {

void addLeadInAndTail(Performance& p, Ticks leadIn, Ticks tail) {
	for (Keypose& k : p.keys) k.time += leadIn;
	ModulatorOptions& m = p.modulation;
	for (Ticks& t : m.forcedBlinks) t += leadIn;
	for (HeadGesture& g : m.gestures) g.time += leadIn;
	for (BrowEvent& b : m.browEvents) b.time += leadIn;
	for (AuEvent& a : m.auEvents) a.time += leadIn;
	m.curves.start += leadIn;  // a tracked performance (D55) starts with the speech
	p.duration += leadIn + tail;
}

std::string timelineJson(const Performance& p, const std::vector<PhoneSegment>& phones, Ticks leadIn, Ticks tail, Ticks avOffset,
                         const std::vector<Interval>& words) {
	auto sec = [](Ticks t) {
		char b[32];
		std::snprintf(b, sizeof b, "%.6f", toSeconds(t));
		return std::string(b);
	};
	Ticks onset{-1}, offset{0};
	for (const auto& ph : phones)
		if (ph.phone != "_" && !ph.phone.empty()) {
			if (onset < Ticks(0)) onset = ph.start;
			offset = ph.end;
		}
	std::string s = "{\n  \"fps\": " + jsonQuote(p.rate.str()) + ",\n  \"frames\": " + std::to_string(p.frameCount()) + ",\n  \"duration\": " + sec(p.duration) +
	                ",\n  \"lead_in\": " + sec(leadIn) + ",\n  \"tail\": " + sec(tail) + ",\n  \"av_offset\": " + sec(avOffset) + ",\n  \"speech_onset\": " +
	                (onset < Ticks(0) ? std::string("null") : sec(onset + leadIn)) + ",\n  \"speech_offset\": " + (onset < Ticks(0) ? std::string("null") : sec(offset + leadIn)) +
	                ",\n  \"emotion\": " + jsonQuote(p.emotion.label()) + ",\n  \"words\": [";
	bool first = true;
	for (const auto& w : words) {
		const std::string l = toLower(w.label);
		if (l.empty() || l == "sil" || l == "sp" || l == "_" || l == "<p:>" || l == "#") continue;
		s += std::string(first ? "\n" : ",\n") + "    {\"start\": " + sec(w.start + leadIn) + ", \"end\": " + sec(w.end + leadIn) + ", \"word\": " + jsonQuote(w.label) + "}";
		first = false;
	}
	s += std::string(first ? "" : "\n  ") + "],\n  \"phones\": [";
	for (std::size_t i = 0; i < phones.size(); ++i)
		s += std::string(i ? ",\n" : "\n") + "    {\"start\": " + sec(phones[i].start + leadIn) + ", \"end\": " + sec(phones[i].end + leadIn) +
		     ", \"phone\": " + jsonQuote(phones[i].phone) + ", \"cdv\": " + jsonQuote(phones[i].cdv) + "}";
	s += "\n  ],\n  \"keyposes\": [";
	for (std::size_t i = 0; i < p.keys.size(); ++i)
		s += std::string(i ? ",\n" : "\n") + "    {\"time\": " + sec(p.keys[i].time) + ", \"cdv\": " + jsonQuote(p.keys[i].cdv) +
		     ", \"emotion\": " + jsonQuote(p.keys[i].emotion.value_or(p.emotion).label()) + "}";
	return s + "\n  ]\n}\n";
}

}  // namespace talkhead
