// SPDX-License-Identifier: GPL-3.0-or-later
// Live requests: parsing (JSON text messages) and turning them into utterances and session commands.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "base/base64.h"
#include "base/error.h"
#include "base/interrupt.h"
#include "base/json.h"
#include "base/text.h"
#include "perform/plan.h"
#include "phonetics/labels.h"
#include "phonetics/language.h"
#include "phonetics/timing_formats.h"
#include "phonetics/transcript.h"
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

// A 44-byte RIFF/WAVE header for 16-bit PCM.
std::string wavHeader(int rate, int channels, std::size_t frames) {
	std::string h;
	auto u32 = [&](std::uint32_t v) { for (int i = 0; i < 4; ++i) h.push_back(char((v >> (8 * i)) & 0xFF)); };
	auto u16 = [&](std::uint16_t v) { for (int i = 0; i < 2; ++i) h.push_back(char((v >> (8 * i)) & 0xFF)); };
	const std::uint32_t data = std::uint32_t(frames * std::size_t(channels) * 2);
	h += "RIFF";
	u32(36 + data);
	h += "WAVEfmt ";
	u32(16), u16(1), u16(std::uint16_t(channels)), u32(std::uint32_t(rate)), u32(std::uint32_t(rate * channels * 2)), u16(std::uint16_t(channels * 2)), u16(16);
	h += "data";
	u32(data);
	return h;
}

const char* const kIdRule = "'id' must be a string of at most 200 bytes or a whole number from -9007199254740991 to 9007199254740991, written without a fraction or an exponent";

}  // namespace

std::string requestIdJson(const std::string& member) {
	if (!member.empty() && member[0] == '"') {
		const JsonValue v = parseJson(member, "id");
		if (v.kind != JsonValue::Kind::String || v.string.size() > 200) throw Error(kIdRule);
		return member;
	}
	// An integer as digits (JSON's grammar: no leading zeros, an optional minus) within JavaScript's safe range.
	const std::size_t digits = member.size() - (member.rfind('-', 0) == 0 ? 1 : 0);
	if (digits == 0 || digits > 16 || member.find_first_not_of("-0123456789") != std::string::npos || member.find('-', 1) != std::string::npos)
		throw Error(kIdRule);
	const long long n = std::strtoll(member.c_str(), nullptr, 10);
	if (n > 9007199254740991LL || n < -9007199254740991LL) throw Error(kIdRule);
	return member == "-0" ? "0" : member;
}

LiveRequest parseLiveRequest(const std::string& json) {
	const JsonValue v = parseJson(json, "request", 1, kMaxRequestValues);
	if (v.kind != JsonValue::Kind::Object) throw Error("a request is a JSON object");
	const std::string& type = stringMember(v, "type", true);
	LiveRequest r;
	if (type == "say") r.kind = LiveRequest::Kind::Say;
	else if (type == "speak") r.kind = LiveRequest::Kind::Speak;
	else if (type == "emotion") r.kind = LiveRequest::Kind::Emotion;
	else if (type == "stop") r.kind = LiveRequest::Kind::Stop;
	else throw Error("unknown request type '" + safeQuote(type) + "' (say, speak, emotion, stop)");
	// An id as the client wrote it (issue 45): 2 and "2" are two ids, and no number is rounded into another.
	const auto idMember = [&](const char* key, const std::string& rule) -> std::optional<std::string> {
		const JsonValue* id = v.find(key);
		if (!id || id->kind == JsonValue::Kind::Null) return std::nullopt;
		if (id->kind != JsonValue::Kind::String && id->kind != JsonValue::Kind::Number) throw Error(rule);
		const auto text = jsonTopLevelMemberJson(json, key);
		if (!text) throw Error(rule);
		return requestIdJson(*text);
	};
	const auto audioMember = [&] {
		const auto audio = decodeBase64(stringMember(v, "audio", true));
		if (!audio) throw Error("'audio' is not base64");
		return *audio;
	};
	if (auto id = idMember("id", kIdRule)) r.id = *id;
	const std::string& emotion = stringMember(v, "emotion", r.kind == LiveRequest::Kind::Emotion);
	const double intensity = numberMember(v, "intensity", 0, Expression::kMaxIntensity).value_or(1);
	if (!emotion.empty()) {
		const std::optional<Emotion> e = Emotion::find(emotion);
		if (!e) throw Error("unknown emotion '" + safeQuote(emotion) + "' (" + emotionList() + ")");
		r.expression = Expression(*e, intensity);
	}
	if (auto ramp = numberMember(v, "ramp", 0, 10)) r.ramp = ticksFromSeconds(*ramp);
	if (r.kind == LiveRequest::Kind::Say) {
		r.text = stringMember(v, "text", true);
		if (r.text.size() > 100000) throw Error("'text' is longer than 100 000 bytes");
		r.lang = stringMember(v, "lang", false);
		r.voice = stringMember(v, "voice", false);
		r.rate = int(numberMember(v, "rate", 80, 450).value_or(0));
		r.pitch = int(numberMember(v, "pitch", 0, 100).value_or(-1));
	} else if (r.kind == LiveRequest::Kind::Speak) {
		if (const JsonValue* more = v.find("more"); more && more->kind != JsonValue::Kind::Null) {
			if (more->kind != JsonValue::Kind::Bool) throw Error("'more' must be true or false");
			r.more = more->boolean;
		}
		if (auto stream = idMember("continue", std::string("'continue': ") + kIdRule)) {
			// A piece of a streamed speak: audio only, in the stream's encoding; its events carry the stream's id.
			r.id = *stream;
			r.continues = true;
			for (const char* k : {"text", "transcript", "visemes", "alignment", "normalized_alignment", "emotion"})
				if (v.find(k)) throw Error(std::string("a speak that continues a stream ('continue') carries its audio only, not '") + k + "': the stream's text came with its first piece");
			const std::string& encoding = stringMember(v, "encoding", false);
			if (!encoding.empty() && encoding != "pcm_s16le") throw Error("a streamed speak's pieces are raw PCM ('encoding': 'pcm_s16le')");
			if (auto rate = numberMember(v, "sample_rate", 8000, 192000)) r.pcmRate = int(*rate);
			r.pcmChannels = int(numberMember(v, "channels", 1, 2).value_or(0));
			if (v.find("audio")) {
				r.audio = audioMember();
			} else if (r.more) {
				throw Error("'audio' is missing (only the last piece of a stream, without 'more', may come without audio)");
			}
			if (r.audio.size() % std::size_t(2 * std::max(1, r.pcmChannels)) != 0) throw Error("'audio' is not a whole number of 16-bit sample frames");
			return r;
		}
		r.audio = audioMember();
		if (r.audio.empty()) throw Error("'audio' is empty (zero-length audio)");
		r.lang = stringMember(v, "lang", false);
		// Raw PCM as TTS services stream it (16-bit little-endian, interleaved), or a file libav reads.
		const std::string& encoding = stringMember(v, "encoding", false);
		if (encoding == "pcm_s16le") {
			const auto rate = numberMember(v, "sample_rate", 8000, 192000);
			if (!rate) throw Error("'encoding': 'pcm_s16le' needs 'sample_rate'");
			r.pcmRate = int(*rate);
			r.pcmChannels = int(numberMember(v, "channels", 1, 2).value_or(1));
			if (r.audio.size() % std::size_t(2 * r.pcmChannels) != 0) throw Error("'audio' is not a whole number of 16-bit sample frames");
		} else if (!encoding.empty() && encoding != "file") {
			throw Error("unknown 'encoding' '" + safeQuote(encoding) + "' (pcm_s16le, or none for a file libav reads)");
		}
		const JsonValue* visemes = v.find("visemes");
		// ElevenLabs answers with both; either may be given (normalized_alignment spells numbers out).
		const JsonValue* alignment = v.find("alignment") ? v.find("alignment") : v.find("normalized_alignment");
		const JsonValue* text = v.find("text");
		if (int(v.find("transcript") != nullptr) + int(visemes != nullptr) + int(alignment != nullptr) + int(text != nullptr) > 1)
			throw Error("a speak request gives its timing as at most one of 'transcript', 'text' (aligned to the audio), 'visemes' (Azure) or "
			            "'alignment' / 'normalized_alignment' (ElevenLabs); with none, the phones are recognised from the audio");
		// The same readers as the command line's (phonetics/timing_formats.h).
		if (visemes) r.timing = azureVisemes(*visemes, "visemes");
		else if (alignment) r.timing = characterAlignment(*alignment, v.find("alignment") ? "alignment" : "normalized_alignment");
		else if (text) {
			r.text = stringMember(v, "text", true);
			if (r.text.size() > 100000) throw Error("'text' is longer than 100 000 bytes");
			if (trim(r.text).empty()) throw Error("'text' is empty");
		} else if (v.find("transcript")) r.transcript = stringMember(v, "transcript", true);
		if (r.more) {
			if (r.pcmRate == 0) throw Error("a streamed speak ('more': true) sends raw PCM: 'encoding': 'pcm_s16le' with 'sample_rate'");
			if (r.timing || !r.transcript.empty())
				throw Error("a streamed speak ('more': true) gives its timing as 'text' (aligned as its audio comes) or not at all (recognised); send timed pieces as speaks of their own");
		}
	}
	return r;
}

std::vector<float> pcmMono(const std::string& bytes, int channels) {
	const std::size_t ch = std::size_t(std::max(1, channels)), frames = bytes.size() / (2 * ch);
	std::vector<float> out(frames);
	const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
	for (std::size_t i = 0; i < frames; ++i) {
		float sum = 0;
		for (std::size_t c = 0; c < ch; ++c) {
			const std::size_t at = 2 * (i * ch + c);
			sum += float(std::int16_t(std::uint16_t(b[at] | (b[at + 1] << 8)))) / 32768.f;
		}
		out[i] = sum / float(ch);
	}
	return out;
}

Utterance prepareUtterance(const LiveRequest& r, const std::string& defaultLang, int sampleRate, const SpeechLimits& limits, bool recognize) {
	const Language* language = nullptr;
	try {
		language = &Language::get(r.lang.empty() ? defaultLang : r.lang);
	} catch (const Error& e) {
		throw Error(e.what());
	}
	const Language& lang = *language;
	Utterance u;
	if (r.kind == LiveRequest::Kind::Say) {
		u = speakText(r.text, lang, r.voice, sampleRate, r.rate, r.pitch, limits);
	} else if (r.pcmRate > 0) {
		// Raw PCM: mono mix, resampled to the session's rate (a WAV header on it, through libav's resampler).
		const std::size_t frames = r.audio.size() / std::size_t(2 * r.pcmChannels);
		std::string wav = wavHeader(r.pcmRate, r.pcmChannels, frames) + r.audio;
		LiveRequest file = r;
		file.pcmRate = 0;
		file.audio = std::move(wav);
		return prepareUtterance(file, defaultLang, sampleRate, limits, recognize);
	} else {
		// libav reads files: the sound goes through a private temporary file, removed at once.
		char path[] = "/tmp/talkhead-speak-XXXXXX";
		const int fd = mkstemp(path);
		if (fd < 0) throw Error("cannot make a temporary file for the audio");
		registerTemporary(path);  // removed on a signal too
		std::size_t done = 0;
		while (done < r.audio.size()) {
			const ssize_t n = ::write(fd, r.audio.data() + done, r.audio.size() - done);
			if (n <= 0) break;
			done += std::size_t(n);
		}
		::close(fd);
		try {
			if (done != r.audio.size()) throw Error("cannot write the audio to a temporary file");
			// The limit bounds decoding itself (issue 45): a small compressed file may hold hours.
			u = utteranceFromAudio(path, r.timing ? std::string() : r.transcript, "transcript", lang, sampleRate, limits.maxSeconds);
			if (!r.timing && r.transcript.empty() && r.text.empty() && !recognize) {
				// The sound alone: the caller recognises it (in parts, perform/stream.h).
			} else if (!r.timing && r.transcript.empty()) {
				// Text aligned to the audio, or (no timing at all) the phones recognised from it (issue 49).
				std::vector<std::string> notes;
				u.phones = r.text.empty() ? recognizedPhones(u.audio, "audio", lang, notes, u.warnings) : alignedPhones(u.audio, r.text, lang, u.warnings);
				u.timing = r.text.empty() ? PhoneTiming::Recognised : PhoneTiming::Aligned;
			} else if (r.timing) {
				Transcript t = *r.timing;
				// The last viseme until the sound ends, and pauses between words and to the sound's end.
				if (t.level == LabelLevel::Viseme) t.intervals.back().end = std::max(t.intervals.back().end, std::max(u.audio.duration(), t.intervals.back().start + ticksFromSeconds(0.05)));
				t.intervals = withPauses(t.intervals, Ticks(0), u.audio.duration());
				u.phones = phoneSegments(t, lang);
			}
		} catch (const std::exception& e) {
			::unlink(path);
			releaseTemporary(path);
			// The temporary name means nothing to the client.
			std::string m = describeException(e);
			const std::string p = std::string(path) + ": ";
			if (m.rfind(p, 0) == 0) m = "audio: " + m.substr(p.size());
			throw Error(m);
		}
		::unlink(path);
		releaseTemporary(path);
		if (u.phones.empty() && (recognize || r.timing || !r.transcript.empty() || !r.text.empty())) throw Error("transcript: no phones");
		if (limits.maxSeconds > 0 && toSeconds(u.duration()) > limits.maxSeconds) {
			char b[160];
			std::snprintf(b, sizeof b, "the sound lasts %.1f s, longer than the %g s allowed", toSeconds(u.duration()), limits.maxSeconds);
			throw Error(b);
		}
	}
	u.id = r.id;
	return u;
}

std::string requestForRecord(const std::string& json, const LiveRequest& r) {
	std::vector<std::string> keys = {"type", "id", "emotion", "intensity", "ramp"};
	if (r.kind == LiveRequest::Kind::Say) keys.insert(keys.end(), {"text", "lang", "voice", "rate", "pitch"});
	if (r.kind == LiveRequest::Kind::Speak)
		keys.insert(keys.end(), {"audio", "lang", "encoding", "sample_rate", "channels", "transcript", "text", "visemes", "alignment", "normalized_alignment", "more", "continue"});
	return jsonKeepMembers(json, keys);
}

SessionScript readSessionScript(const std::string& path) {
	SessionScript out;
	const std::string text = readTextFile(path);
	long no = 0;
	for (const std::string& raw : split(text, '\n')) {
		++no;
		const std::string line(trim(raw));
		if (line.empty()) continue;
		const JsonValue v = parseJson(line, path, no);
		if (v.kind != JsonValue::Kind::Object) throw Error(path, no, "each line is a JSON object");
		const JsonValue* type = v.find("type");
		const JsonValue* frame = v.find("frame");
		auto frameOf = [&]() {
			if (!frame || frame->kind != JsonValue::Kind::Number || !(frame->number >= 0 && frame->number <= 1e8) || frame->number != std::floor(frame->number))
				throw Error(path, no, "'frame' must be a whole number from 0 to 100000000");
			return std::int64_t(frame->number);
		};
		if (type && type->kind == JsonValue::Kind::String && type->string == "session") continue;
		if (type && type->kind == JsonValue::Kind::String && type->string == "part") {
			SessionScript::Step step{frameOf(), "", no};
			step.part = true;
			out.steps.push_back(std::move(step));
			out.hasParts = true;
			continue;
		}
		if (type && type->kind == JsonValue::Kind::String && type->string == "end") {
			out.end = frameOf();
			continue;
		}
		const JsonValue* request = v.find("request");
		if (!request || request->kind != JsonValue::Kind::Object) throw Error(path, no, "a step needs 'frame' and 'request' (an object)");
		// The request's own text, re-serialised by the JSON reader's rules: find it in the line.
		const auto at = line.find("\"request\"");
		const auto open = line.find('{', at);
		std::string body = line.substr(open);
		while (!body.empty() && body.back() != '}') body.pop_back();
		body.pop_back();  // the step's closing brace
		const JsonValue* look = v.find("look");
		if (look && look->kind != JsonValue::Kind::Bool) throw Error(path, no, "'look' must be true or false");
		out.steps.push_back({frameOf(), std::string(trim(body)), no, !look || look->boolean, false});
	}
	std::stable_sort(out.steps.begin(), out.steps.end(), [](const SessionScript::Step& a, const SessionScript::Step& b) { return a.frame < b.frame; });
	return out;
}

bool speaksInParts(const LiveRequest& r) {
	return r.kind == LiveRequest::Kind::Speak && (r.more || r.continues || (!r.timing && r.transcript.empty() && r.text.empty()));
}

void replaySpeakInParts(LiveSession& session, const LiveRequest& r, std::unique_ptr<SpeechStream>& stream, const std::string& defaultLang, bool look,
                        std::deque<HeldPart>* held) {
	const auto enqueue = [&](Utterance part) {
		const std::optional<Expression> expression = part.opens ? r.expression : std::nullopt;
		if (held) {
			held->push_back({std::move(part), expression, r.ramp});
			return;
		}
		if (expression) session.setEmotion(*expression, r.ramp);
		session.enqueue(std::move(part));
	};
	if (r.continues) {
		if (!stream || stream->id() != r.id) throw Error("no streamed speak " + r.id + " is open ('continue' names the id of a speak sent with 'more': true)");
		stream->feed(pcmMono(r.audio, r.pcmChannels ? r.pcmChannels : 1), !r.more, enqueue, nullptr, look);
		if (stream->closed()) stream.reset();
		return;
	}
	const Language& lang = Language::get(r.lang.empty() ? defaultLang : r.lang);
	if (r.more) {
		stream = std::make_unique<SpeechStream>(r.id, r.text, lang, r.pcmRate, session.sampleRate());
		stream->feed(pcmMono(r.audio, r.pcmChannels), false, enqueue);
		return;
	}
	Utterance u = prepareUtterance(r, defaultLang, session.sampleRate(), {}, false);
	SpeechStream whole(r.id, "", lang, session.sampleRate(), session.sampleRate());
	whole.feed(u.audio.samples, true, enqueue);
}

void applyLiveRequest(LiveSession& session, const LiveRequest& r, std::optional<PlannedUtterance> utterance) {
	switch (r.kind) {
	case LiveRequest::Kind::Stop: session.stop(r.id); break;
	case LiveRequest::Kind::Emotion: session.setEmotion(*r.expression, r.ramp); break;
	case LiveRequest::Kind::Say:
	case LiveRequest::Kind::Speak:
		if (r.expression) session.setEmotion(*r.expression, r.ramp);
		if (utterance) session.enqueue(std::move(*utterance));
		break;
	}
}

}  // namespace talkhead
