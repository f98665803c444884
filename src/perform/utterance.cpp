// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/utterance.h"

#include <algorithm>
#include <cmath>

#include "base/error.h"
#include "phonetics/labels.h"
#include "phonetics/transcript.h"

namespace talkhead {

namespace {

// Linear resampling of mono PCM (espeak-ng speaks at 22050 Hz, the session's default rate, so say never
// needs it).
std::vector<float> resampled(const std::vector<float>& in, int from, int to) {
	if (from == to || in.empty()) return in;
	const std::size_t n = std::size_t(std::llround(double(in.size()) * to / from));
	std::vector<float> out(n);
	for (std::size_t i = 0; i < n; ++i) {
		const double x = double(i) * from / to;
		const std::size_t a = std::min(in.size() - 1, std::size_t(x));
		const std::size_t b = std::min(in.size() - 1, a + 1);
		out[i] = float(in[a] + (x - double(a)) * (in[b] - in[a]));
	}
	return out;
}

}  // namespace

Ticks Utterance::duration() const {
	Ticks d = audio.duration();
	if (!phones.empty()) d = std::max(d, phones.back().end);
	return d;
}

Utterance speakText(const std::string& text, const Language& language, const std::string& voiceName, int sampleRate, int rateWpm, int pitch,
                    const SpeechLimits& limits) {
	const std::string voice = voiceName.empty() ? espeakVoiceFor(language.tag()) : voiceName;
	Utterance u;
	Speech speech;
	if (looksLikeSsml(text)) {
		const SsmlText ssml = parseSsml(text, "text");
		for (const auto& e : ssml.events)
			if (e.kind == SsmlText::Event::Kind::EmotionStart)
				throw Error("text", e.line, "column " + std::to_string(e.column) + ": an emotion element in live speech: send an emotion message instead");
		std::vector<Ticks> times;
		speech = espeakSpeakSsml(ssml, voice, times, rateWpm, pitch, limits);
		const Ticks end = speech.sampleRate ? Ticks(std::int64_t(speech.pcm.size()) * (kTicksPerSecond / speech.sampleRate)) : Ticks(0);
		SpeechEvents events = ssmlEvents(ssml, times, end);
		u.marks = std::move(events.marks);
		u.blinks = std::move(events.blinks);
		u.brows = std::move(events.brows);
	} else {
		speech = espeakSpeak(text, voice, rateWpm, pitch, 0, limits);
	}
	u.warnings = speech.warnings;
	u.phones = phoneSegments(speech.phones, language, UnknownPhone::Nearest, Notation::Espeak);
	u.audio.sampleRate = sampleRate;
	u.audio.channels = 1;
	u.audio.samples = resampled(audioOf(speech).samples, speech.sampleRate, sampleRate);
	return u;
}

Utterance utteranceFromAudio(const std::string& audioPath, const std::string& transcript, const std::string& transcriptName, const Language& language,
                             int sampleRate, double maxSeconds) {
	Utterance u;
	AudioClip clip = decodeAudio(audioPath, sampleRate, maxSeconds > 0 ? maxSeconds : kMaxAudioSeconds);
	u.audio.sampleRate = sampleRate;
	u.audio.channels = 1;
	const std::size_t n = clip.frameCount(), ch = std::size_t(std::max(1, clip.channels));
	u.audio.samples.resize(n);
	for (std::size_t i = 0; i < n; ++i) {
		float s = 0;
		for (std::size_t c = 0; c < ch; ++c) s += clip.samples[i * ch + c];
		u.audio.samples[i] = s / float(ch);
	}
	if (!transcript.empty()) {
		const Transcript t = parseTranscript(transcript, transcriptName);
		u.warnings = t.warnings;
		u.phones = phoneSegments(t, language);
	}
	return u;
}

SpeechEvents ssmlEvents(const SsmlText& ssml, const std::vector<Ticks>& times, Ticks end, const Expression& outer) {
	SpeechEvents out;
	std::vector<Expression> stack{outer};
	for (std::size_t i = 0; i < ssml.events.size() && i < times.size(); ++i) {
		const SsmlText::Event& e = ssml.events[i];
		const Ticks t = std::min(times[i], end);
		switch (e.kind) {
		case SsmlText::Event::Kind::Mark: out.marks.push_back({e.name, t}); break;
		case SsmlText::Event::Kind::Blink: out.blinks.push_back(t); break;
		case SsmlText::Event::Kind::Brows: out.brows.push_back(BrowEvent{t, ticksFromSeconds(0.8), e.intensity, e.frown}); break;
		case SsmlText::Event::Kind::EmotionStart:
		case SsmlText::Event::Kind::EmotionEnd:
			if (e.kind == SsmlText::Event::Kind::EmotionStart) {
				const auto c = Emotion::find(e.name);
				if (!c) throw Error("text", e.line, "column " + std::to_string(e.column) + ": unknown emotion '" + e.name + "'");
				stack.emplace_back(*c, e.intensity);  // checked by the SSML reader
			} else if (stack.size() > 1) {
				stack.pop_back();
			}
			out.emotions.push_back(ControlTrack::EmotionChange{t, ticksFromSeconds(0.2), stack.back()});
			break;
		}
	}
	return out;
}

ControlTrack controlTrackOf(SpeechEvents events, const std::string& path) {
	ControlTrack track;
	track.path = path;
	track.blinks = std::move(events.blinks);
	track.brows = std::move(events.brows);
	track.emotions = std::move(events.emotions);
	return track;
}

SpokenText speakWithEvents(const std::string& text, const std::string& textName, const std::string& voice, int rateWpm, int pitch) {
	SpokenText s;
	if (looksLikeSsml(text)) {
		s.ssml = parseSsml(text, textName);
		for (const auto& e : s.ssml->events)  // checked before any speech is synthesised
			if (e.kind == SsmlText::Event::Kind::EmotionStart && !Emotion::find(e.name))
				throw Error(textName, e.line, "column " + std::to_string(e.column) + ": unknown emotion '" + e.name + "'");
		s.speech = espeakSpeakSsml(*s.ssml, voice, s.eventTimes, rateWpm, pitch);
	} else {
		s.speech = espeakSpeak(text, voice, rateWpm, pitch);
	}
	return s;
}

AudioClip audioOf(const Speech& speech) {
	AudioClip audio;
	audio.sampleRate = speech.sampleRate;
	audio.channels = 1;
	audio.samples.reserve(speech.pcm.size());
	for (short v : speech.pcm) audio.samples.push_back(float(v) / 32768.f);
	return audio;
}

}  // namespace talkhead
