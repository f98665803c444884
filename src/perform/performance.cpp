// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/performance.h"

#include <cstdio>

#include "base/json.h"
#include "base/text.h"

namespace talkhead {

void addLeadInAndTail(Performance& p, Ticks leadIn, Ticks tail) {
	p.timeline.shift(leadIn);  // a tracked performance's curves (D55) start with the speech too
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
	const JsonLayout itemLines{"\n    ", ",\n    ", "\n  "};
	JsonArray wordItems, phoneItems, keyItems;
	for (const auto& w : words) {
		const std::string l = toLower(w.label);
		if (l.empty() || l == "sil" || l == "sp" || l == "_" || l == "<p:>" || l == "#") continue;
		wordItems.raw(JsonObject().raw("start", sec(w.start + leadIn)).raw("end", sec(w.end + leadIn)).add("word", w.label).str());
	}
	for (const auto& ph : phones)
		phoneItems.raw(JsonObject().raw("start", sec(ph.start + leadIn)).raw("end", sec(ph.end + leadIn)).add("phone", ph.phone).add("cdv", ph.cdv.label()).str());
	for (const auto& k : p.timeline.keys) {
		JsonObject key;
		key.raw("time", sec(k.time)).add("cdv", k.cdv.label()).add("emotion", k.emotion.value_or(p.expression.emotion()).label());
		// The coarticulation model's prediction (D62, D90): the opening and width it asked the face for, in
		// units of a speaker's own (90th percentile of openings, median width, in speech).
		auto unit = [](double v) {
			char b[32];
			std::snprintf(b, sizeof b, "%.3f", v);
			return std::string(b);
		};
		if (k.mouthOpening) key.raw("mouth_opening", unit(*k.mouthOpening));
		if (k.mouthWidth) key.raw("mouth_width", unit(*k.mouthWidth));
		keyItems.raw(key.str());
	}
	JsonObject o;
	o.add("fps", p.rate.str()).add("frames", p.frameCount()).raw("duration", sec(p.duration)).raw("lead_in", sec(leadIn)).raw("tail", sec(tail));
	o.raw("av_offset", sec(avOffset)).raw("speech_onset", onset < Ticks(0) ? "null" : sec(onset + leadIn));
	o.raw("speech_offset", onset < Ticks(0) ? "null" : sec(offset + leadIn)).add("emotion", p.expression.emotion().label());
	o.raw("words", wordItems.str(itemLines)).raw("phones", phoneItems.str(itemLines)).raw("keyposes", keyItems.str(itemLines));
	return o.str({"\n  ", ",\n  ", "\n"}) + "\n";
}

}  // namespace talkhead
