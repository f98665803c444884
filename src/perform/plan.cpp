// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/plan.h"

#include <algorithm>
#include <cstdio>

#include "align/align.h"
#include "align/recognize.h"
#include "base/error.h"
#include "base/text.h"

namespace talkhead {

TimedSpeech speechFromTranscript(const std::string& path, const ReadOptions& read, const Language& language, UnknownPhone unknown,
                                 Notation notation, const std::optional<std::string>& audioPath, bool wantWords,
                                 const std::function<void(const Transcript&)>& onRead) {
	TimedSpeech s;
	s.name = path;
	s.read = readTranscript(path, read);
	if (onRead) onRead(s.read);
	Transcript tr = s.read;
	if (tr.level == LabelLevel::Word) s.words = tr.intervals;
	else if (wantWords && tr.format == "textgrid" && path != "-") s.words = textGridWords(path, tr.tier);
	// Sentence-level cues (subtitles, aeneas, utterance tiers) with the speech at hand: each cue's text is
	// aligned to its own stretch of the audio (issue 29), not spread by espeak-ng's durations.
	const bool sentences = std::any_of(tr.intervals.begin(), tr.intervals.end(), [](const Interval& i) { return i.label.find(' ') != std::string::npos; });
	bool aligned = false;
	if (tr.level == LabelLevel::Word && sentences && audioPath) {
		s.audio = decodeAudio(*audioPath);
		tr = alignCues(tr, s.audio, language.tag(), *audioPath);
		aligned = true;
		const auto cues = std::count_if(s.words.begin(), s.words.end(), [](const Interval& i) { return !isPauseLabel(i.label); });
		s.notes.push_back("talkhead: " + path + ": " + std::to_string(cues) + " cues aligned to " + *audioPath);
	}
	for (const std::string& w : tr.warnings) s.warnings.push_back(path + ": " + w);
	// An alignment's phones are canonical IPA.
	s.phones = phoneSegments(tr, language, unknown, aligned ? Notation::Ipa : notation);
	if (aligned) s.timing = PhoneTiming::Aligned;
	return s;
}

TimedSpeech speechFromText(const std::string& text, const std::string& audioPath, const Language& language, UnknownPhone unknown) {
	TimedSpeech s;
	s.name = audioPath;
	s.audio = decodeAudio(audioPath);
	AlignOptions ao;
	ao.languageTag = language.tag();
	Alignment al;
	try {
		al = alignSpeech(s.audio, text, ao);
	} catch (const Error& e) {
		throw Error(audioPath, 0, e.what());
	}
	for (const std::string& w : al.warnings) s.warnings.push_back(audioPath + ": " + w);
	s.notes.push_back("aligned: " + alignmentSummary(al));
	s.read = al.phones;
	s.words = al.words.intervals;
	s.phones = phoneSegments(al.phones, language, unknown, Notation::Ipa);
	s.timing = PhoneTiming::Aligned;
	return s;
}

double TimedSpeech::confidenceAt(Ticks t) const {
	if (confidence.size() != read.intervals.size()) return 1.0;
	for (std::size_t i = 0; i < read.intervals.size(); ++i)
		if (read.intervals[i].start <= t && t < read.intervals[i].end) return confidence[i];
	return 1.0;
}

int toLanguage(Transcript& phones, const Language& language) {
	if (language.tag() == "en-US") return 0;
	int moved = 0;
	for (Interval& iv : phones.intervals) {
		if (iv.label.empty() || language.normalize(iv.label, Notation::Ipa)) continue;
		const auto near = language.nearest(iv.label, Notation::Ipa);
		iv.label = near && !near->empty() ? near->front() : "";
		++moved;
	}
	return moved;
}

namespace {

// Recognised en-US phones in `language`, said in a note.
void inLanguage(Recognition& rec, const Language& language, std::vector<std::string>& notes) {
	if (language.tag() == "en-US") return;
	const int moved = toLanguage(rec.phones, language);
	notes.push_back("the phones are en-US's (the only phone recogniser talkhead has); " + std::to_string(moved) + " without a " + language.tag() +
	                " spelling took the nearest " + language.tag() + " phone");
}

}  // namespace

TimedSpeech speechFromAudio(const std::string& audioPath, const Language& language) {
	TimedSpeech s;
	s.name = audioPath;
	Recognition rec = recognizePhonesFile(audioPath);
	s.warnings = rec.warnings;
	s.notes.push_back(recognitionSummary(rec));
	inLanguage(rec, language, s.notes);
	s.read = rec.phones;
	s.confidence = rec.confidence;
	s.phones = phoneSegments(rec.phones, language, UnknownPhone::Silence, Notation::Ipa);
	s.timing = PhoneTiming::Recognised;
	return s;
}

std::vector<PhoneSegment> recognizedPhones(const AudioClip& audio, const std::string& name, const Language& language,
                                           std::vector<std::string>& notes, std::vector<std::string>& warnings) {
	Recognition rec = recognizePhonesClip(audio, name);
	for (const std::string& w : rec.warnings) warnings.push_back(w);
	notes.push_back(recognitionSummary(rec));
	inLanguage(rec, language, notes);
	return phoneSegments(rec.phones, language, UnknownPhone::Silence, Notation::Ipa);
}

void prepareSpeechRecognition() { warmRecognizer(); }

std::vector<PhoneSegment> alignedPhones(const AudioClip& audio, const std::string& text, const Language& language, std::vector<std::string>& warnings) {
	AlignOptions ao;
	ao.languageTag = language.tag();
	const Alignment al = alignSpeech(audio, text, ao);
	for (const std::string& w : al.warnings) warnings.push_back(w);
	return phoneSegments(al.phones, language, UnknownPhone::Error, Notation::Ipa);
}

TimedSpeech speechFromEspeak(const Speech& speech, const Language& language) {
	TimedSpeech s;
	s.name = "espeak-ng";
	s.read = speech.phones;
	s.words = speech.words.intervals;
	s.warnings = speech.warnings;
	// espeak-ng's phoneme names are IPA; any it has that the tables lack take the nearest known phone, said in
	// one line (the tables are meant to know every name their voice uses).
	std::vector<std::string> unknown;
	for (const auto& iv : speech.phones.intervals)
		if (!iv.label.empty() && !language.normalize(iv.label) && std::find(unknown.begin(), unknown.end(), iv.label) == unknown.end())
			unknown.push_back(iv.label);
	std::string list;
	for (const auto& u : unknown) {
		const auto near = language.nearest(u);
		std::string to;
		if (near)
			for (const auto& p : *near) to += (to.empty() ? "" : " ") + p;
		list += (list.empty() ? "" : ", ") + u + " -> " + (near ? to : "silence");
	}
	if (!list.empty()) s.warnings.push_back("espeak-ng phones unknown to the " + language.tag() + " table, substituted: " + list);
	s.phones = phoneSegments(speech.phones, language, UnknownPhone::Nearest, Notation::Espeak);
	return s;
}

PauseStyle defaultPauseStyle(bool withCoarticulation) { return withCoarticulation ? PauseStyle::Still : PauseStyle::Natural; }

ControlTrack clippedTo(ControlTrack track, Ticks end) {
	TimedEvents e;
	e.blinks = std::move(track.blinks), e.gestures = std::move(track.gestures), e.brows = std::move(track.brows), e.actionUnits = std::move(track.actionUnits);
	e.clip(end);
	track.blinks = std::move(e.blinks), track.gestures = std::move(e.gestures), track.brows = std::move(e.brows), track.actionUnits = std::move(e.actionUnits);
	return track;
}

Ticks PerformanceSpec::videoDuration() const {
	if (audioDuration) return *audioDuration;
	if (duration) return *duration;
	return phones.empty() ? Ticks(0) : phones.back().end;
}

Performance planPerformance(const PerformanceSpec& spec, std::vector<std::string>* warnings) {
	Performance perf;
	perf.rate = spec.rate;
	perf.expression = spec.expression;
	perf.modulation = spec.modulation;
	perf.modulation.intensity = spec.expression.intensity();
	perf.timeline.keys = spec.phones.empty() ? spec.keys : keyposes(spec.phones, spec.rate.frameLength(), spec.pauses, spec.coarticulation != nullptr);
	if (spec.coarticulation && !spec.phones.empty()) {
		const CoarticulationModel& m = spec.timing == PhoneTiming::Recognised && spec.coarticulation->recognised ? *spec.coarticulation->recognised : *spec.coarticulation;
		predictMouthOpenings(m, spec.phones, perf.timeline.keys);
		applyBilabialLead(m, spec.phones, perf.timeline.keys, spec.rate.frameLength());
		holdBilabials(spec.phones, perf.timeline.keys, spec.rate.frameLength());
		if (spec.timing == PhoneTiming::Aligned) applyVisualLead(m, perf.timeline.keys, spec.rate.frameLength());
	}
	if (spec.speechBrows > 0) {  // D49
		const auto brows = speechBrows(spec.phones, spec.speechBrows);
		perf.timeline.events.brows.insert(perf.timeline.events.brows.end(), brows.begin(), brows.end());
	}
	if (spec.audioDuration && !spec.phones.empty()) {
		// The speech against its audio (a driven mouth has no phones: the video's length is given).
		const Ticks speech = spec.duration.value_or(spec.phones.back().end), audio = *spec.audioDuration;
		if (speech > audio + Ticks(kTicksPerSecond / 10)) {
			char b[200];
			std::snprintf(b, sizeof b, "the transcript (%.3f s) is longer than the audio (%.3f s) by %.3f s", toSeconds(speech), toSeconds(audio),
			              toSeconds(speech - audio));
			throw Error(spec.source, 0, b);
		}
		// A transcript covering a small part of a long audio: the face holds still for the rest. Say so.
		const Ticks uncovered = audio - speech;
		if (warnings && uncovered > Ticks(10 * kTicksPerSecond) && speech * 2 < audio) {
			char b[240];
			std::snprintf(b, sizeof b, "the transcript covers %.1f s of %.1f s of audio; the face holds its last keypose, silent, for the other %.1f s",
			              toSeconds(speech), toSeconds(audio), toSeconds(uncovered));
			warnings->push_back(b);
		}
	}
	perf.duration = spec.videoDuration();
	for (const ControlTrack& c : spec.controls) applyControls(perf, c);
	if (spec.face) chooseMouthExemplars(*spec.face, perf.expression.emotion(), perf.timeline.keys);  // D62: each key by its own emotion
	return perf;
}

}  // namespace talkhead
