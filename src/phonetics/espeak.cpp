// SPDX-License-Identifier: GPL-3.0-or-later
// libespeak-ng lives in this translation unit only (PRIVATE to the phonetics module).
#include "phonetics/espeak.h"

#include <espeak-ng/speak_lib.h>

#include <cstring>
#include <mutex>

#include "base/error.h"
#include "base/text.h"

namespace talkhead {

namespace {

std::mutex& espeakMutex() {
	static std::mutex m;  // espeak-ng keeps global state: one synthesis at a time
	return m;
}

struct Collector {
	std::vector<std::pair<std::string, int>> phonemes;  // name, audio position (ms)
	long samples = 0;
};

Collector* g_current = nullptr;  // the synthesis in progress (guarded by espeakMutex)

int onSynth(short*, int count, espeak_EVENT* events) {
	Collector* c = g_current;
	if (!c) return 0;
	if (count > 0) c->samples += count;
	for (espeak_EVENT* e = events; e && e->type != espeakEVENT_LIST_TERMINATED; ++e) {
		if (e->type == espeakEVENT_PHONEME) {
			char name[9] = {};
			std::memcpy(name, e->id.string, 8);
			c->phonemes.emplace_back(name, e->audio_position);
		}
	}
	return 0;
}

int initialise() {
	static int rate = [] {
		int r = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 0, nullptr, espeakINITIALIZE_PHONEME_EVENTS | espeakINITIALIZE_PHONEME_IPA);
		if (r > 0) espeak_SetSynthCallback(onSynth);
		return r;
	}();
	if (rate <= 0) throw Error("cannot initialise espeak-ng (is the espeak-ng-data package installed?)");
	return rate;
}

bool isPause(const std::string& ipa) { return ipa.empty() || ipa == "_" || ipa == "_:" || ipa == "_!" || ipa == "||" || ipa == "|"; }

}  // namespace

std::string espeakVoiceFor(const std::string& tag) { return toLower(tag); }

std::vector<SpokenPhone> espeakPhones(const std::string& text, const std::string& voice) {
	std::lock_guard<std::mutex> lock(espeakMutex());
	const int rate = initialise();
	if (espeak_SetVoiceByName(voice.c_str()) != EE_OK) throw Error("espeak-ng has no voice '" + voice + "'");
	Collector c;
	g_current = &c;
	const std::string z = text + '\0';
	const espeak_ERROR err = espeak_Synth(z.data(), z.size(), 0, POS_CHARACTER, 0, espeakCHARS_UTF8, nullptr, nullptr);
	espeak_Synchronize();
	g_current = nullptr;
	if (err != EE_OK) throw Error("espeak-ng could not synthesise '" + text + "'");
	const int endMs = int(c.samples * 1000 / rate);
	std::vector<SpokenPhone> out;
	for (std::size_t i = 0; i < c.phonemes.size(); ++i) {
		const int next = i + 1 < c.phonemes.size() ? c.phonemes[i + 1].second : endMs;
		const std::string& name = c.phonemes[i].first;
		if (isPause(name)) continue;
		out.push_back({name, Ticks(std::int64_t(std::max(1, next - c.phonemes[i].second)) * (kTicksPerSecond / 1000))});
	}
	return out;
}

std::vector<Interval> expandWords(const Transcript& words, const std::string& tag) {
	const std::string voice = espeakVoiceFor(tag);
	std::vector<Interval> out;
	for (const Interval& w : words.intervals) {
		const std::string l = toLower(w.label);
		if (l.empty() || l == "sil" || l == "sp" || l == "_" || l == "#" || l == "pau") {
			out.push_back({w.start, w.end, "", w.line});
			continue;
		}
		std::vector<SpokenPhone> ph = espeakPhones(w.label, voice);
		if (ph.empty()) {
			out.push_back({w.start, w.end, "", w.line});
			continue;
		}
		std::int64_t total = 0;
		for (const auto& p : ph) total += p.duration.count();
		const std::int64_t span = (w.end - w.start).count();
		std::int64_t acc = 0;
		for (const auto& p : ph) {
			const Ticks a = w.start + Ticks(span * acc / total);
			acc += p.duration.count();
			const Ticks b = w.start + Ticks(span * acc / total);
			out.push_back({a, b, p.ipa, w.line});
		}
	}
	return out;
}

}  // namespace talkhead
