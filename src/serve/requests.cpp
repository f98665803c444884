// SPDX-License-Identifier: GPL-3.0-or-later
// Live requests: parsing (JSON text messages) and turning them into utterances and session commands.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "base/base64.h"
#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "phonetics/labels.h"
#include "serve/server.h"

namespace talkhead {

namespace {

const std::string& stringMember(const JsonValue& v, const char* key, bool required) {
	static const std::string none;
	const JsonValue* m = v.find(key);
	if (!m || m->kind == JsonValue::Kind::Null) {
		if (required) throw Error(std::string("'") + key + "' is missing");
		return none;
	}
	if (m->kind != JsonValue::Kind::String) throw Error(std::string("'") + key + "' must be a string");
	return m->string;
}

std::optional<double> numberMember(const JsonValue& v, const char* key, double lo, double hi) {
	const JsonValue* m = v.find(key);
	if (!m || m->kind == JsonValue::Kind::Null) return std::nullopt;
	if (m->kind != JsonValue::Kind::Number || !std::isfinite(m->number)) throw Error(std::string("'") + key + "' must be a number");
	if (m->number < lo || m->number > hi) {
		char b[160];
		std::snprintf(b, sizeof b, "'%s' must be from %g to %g", key, lo, hi);
		throw Error(b);
	}
	return m->number;
}

}  // namespace

LiveRequest parseLiveRequest(const std::string& json) {
	const JsonValue v = parseJson(json, "request");
	if (v.kind != JsonValue::Kind::Object) throw Error("a request is a JSON object");
	const std::string& type = stringMember(v, "type", true);
	LiveRequest r;
	if (type == "say") r.kind = LiveRequest::Kind::Say;
	else if (type == "speak") r.kind = LiveRequest::Kind::Speak;
	else if (type == "emotion") r.kind = LiveRequest::Kind::Emotion;
	else if (type == "stop") r.kind = LiveRequest::Kind::Stop;
	else throw Error("unknown request type '" + safeQuote(type) + "' (say, speak, emotion, stop)");
	const JsonValue* id = v.find("id");
	if (id && id->kind == JsonValue::Kind::String) r.id = id->string;
	else if (id && id->kind == JsonValue::Kind::Number) r.id = std::to_string(std::llround(id->number));
	else if (id && id->kind != JsonValue::Kind::Null) throw Error("'id' must be a string or a number");
	if (r.id.size() > 200) throw Error("'id' is longer than 200 bytes");
	const std::string& emotion = stringMember(v, "emotion", r.kind == LiveRequest::Kind::Emotion);
	if (!emotion.empty()) {
		const auto e = canonicalEmotion(emotion);
		if (!e) throw Error("unknown emotion '" + safeQuote(emotion) + "' (" + emotionList() + ")");
		r.emotion = *e;
	}
	r.intensity = numberMember(v, "intensity", 0, 1.5).value_or(1);
	if (auto ramp = numberMember(v, "ramp", 0, 10)) r.ramp = ticksFromSeconds(*ramp);
	if (r.kind == LiveRequest::Kind::Say) {
		r.text = stringMember(v, "text", true);
		if (r.text.size() > 100000) throw Error("'text' is longer than 100 000 bytes");
		r.lang = stringMember(v, "lang", false);
		r.voice = stringMember(v, "voice", false);
		r.rate = int(numberMember(v, "rate", 80, 450).value_or(0));
		r.pitch = int(numberMember(v, "pitch", 0, 100).value_or(-1));
	} else if (r.kind == LiveRequest::Kind::Speak) {
		const auto audio = decodeBase64(stringMember(v, "audio", true));
		if (!audio) throw Error("'audio' is not base64");
		if (audio->empty()) throw Error("'audio' is empty (zero-length audio)");
		r.audio = *audio;
		r.transcript = stringMember(v, "transcript", true);
		r.lang = stringMember(v, "lang", false);
	}
	return r;
}

Utterance prepareUtterance(const LiveRequest& r, const std::string& defaultLang, int sampleRate) {
	const Language& lang = Language::get(r.lang.empty() ? defaultLang : r.lang);
	Utterance u;
	if (r.kind == LiveRequest::Kind::Say) {
		u = speakText(r.text, lang, r.voice, sampleRate, r.rate, r.pitch);
	} else {
		// libav reads files: the sound goes through a private temporary file, removed at once.
		char path[] = "/tmp/talkhead-speak-XXXXXX";
		const int fd = mkstemp(path);
		if (fd < 0) throw Error("cannot make a temporary file for the audio");
		std::size_t done = 0;
		while (done < r.audio.size()) {
			const ssize_t n = ::write(fd, r.audio.data() + done, r.audio.size() - done);
			if (n <= 0) break;
			done += std::size_t(n);
		}
		::close(fd);
		try {
			if (done != r.audio.size()) throw Error("cannot write the audio to a temporary file");
			u = utteranceFromAudio(path, r.transcript, "transcript", lang, sampleRate);
		} catch (const std::exception& e) {
			::unlink(path);
			// The temporary name means nothing to the client.
			std::string m = describeException(e);
			const std::string p = std::string(path) + ": ";
			if (m.rfind(p, 0) == 0) m = "audio: " + m.substr(p.size());
			throw Error(m);
		}
		::unlink(path);
		if (u.phones.empty()) throw Error("transcript: no phones");
	}
	u.id = r.id;
	return u;
}

void applyLiveRequest(LiveSession& session, const LiveRequest& r, std::optional<Utterance> utterance) {
	switch (r.kind) {
	case LiveRequest::Kind::Stop: session.stop(); break;
	case LiveRequest::Kind::Emotion: session.setEmotion(*r.emotion, r.intensity, r.ramp); break;
	case LiveRequest::Kind::Say:
	case LiveRequest::Kind::Speak:
		if (r.emotion) session.setEmotion(*r.emotion, r.intensity, r.ramp);
		if (utterance) session.enqueue(std::move(*utterance));
		break;
	}
}

}  // namespace talkhead
