// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/speech_source.h"

#include "base/error.h"
#include "perform/utterance.h"

namespace talkhead {

TimedSpeech loadSpeech(const SpeechSource& source, const Language& language, const std::function<void(const Transcript&)>& onRead) {
	switch (source.kind) {
	case SpeechSource::Kind::None:
		return {};
	case SpeechSource::Kind::Transcript:
		if (source.transcript.empty()) throw FieldError("transcript", "no transcript named");
		return speechFromTranscript(source.transcript, source.read, language, source.unknown, source.notation, source.audio, source.wantWords, onRead);
	case SpeechSource::Kind::AlignedText:
		if (!source.audio) throw FieldError("audio", fieldRef("text") + " needs " + fieldRef("audio") + " (the speech to align the text to)");
		if (!source.textIsHint) return speechFromText(source.text, *source.audio, language, source.unknown);
		try {
			return speechFromText(source.text, *source.audio, language, source.unknown);
		} catch (const Error& e) {
			TimedSpeech s = speechFromAudio(*source.audio, language);
			s.warnings.insert(s.warnings.begin(), std::string(e.what()) + ": the " + source.textName + " was a hint; the phones were recognised from the audio instead");
			return s;
		}
	case SpeechSource::Kind::RecognizedAudio:
		if (!source.audio) throw FieldError("audio", "no " + fieldRef("audio") + " to recognise the speech of");
		return speechFromAudio(*source.audio, language);
	case SpeechSource::Kind::SpokenText: {
		if (source.audio) throw FieldError("audio", "espeak-ng makes the sound of spoken text: no " + fieldRef("audio") + " with it");
		SpokenText spoken = speakWithEvents(source.text, source.textName, source.voice, source.rateWpm, source.pitch);
		TimedSpeech s = speechFromEspeak(spoken.speech, language);
		s.audio = audioOf(spoken.speech);
		s.ssml = std::move(spoken.ssml);
		s.eventTimes = std::move(spoken.eventTimes);
		return s;
	}
	}
	throw std::logic_error("loadSpeech: unknown kind");
}

}  // namespace talkhead
