// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/stream.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <unistd.h>

#include "align/align.h"
#include "align/features.h"
#include "align/recognize.h"
#include "base/error.h"
#include "base/interrupt.h"
#include "base/text.h"
#include "perform/plan.h"
#include "phonetics/espeak.h"

namespace talkhead {

namespace {

Ticks ticksAt(std::size_t samples, int rate) { return Ticks(std::int64_t(std::llround(double(samples) * double(kTicksPerSecond) / double(rate)))); }
std::size_t samplesAt(Ticks t, int rate) { return std::size_t(std::max<long long>(0, std::llround(toSeconds(t) * rate))); }

// Samples [a, b) of `mono` (at `from` Hz) at `to` Hz, as libav resamples them: 0.1 s of context on each side
// goes through the resampler too and is dropped, so a part's edges sound as the whole would.
std::vector<float> resampledSpan(const std::vector<float>& mono, int from, std::size_t a, std::size_t b, int to) {
	const std::size_t outA = std::size_t(std::llround(double(a) * to / from)), outB = std::size_t(std::llround(double(b) * to / from));
	std::vector<float> out(outB - outA, 0.f);
	if (from == to) {
		std::copy(mono.begin() + std::ptrdiff_t(a), mono.begin() + std::ptrdiff_t(b), out.begin());
		return out;
	}
	const std::size_t context = std::size_t(from / 10);
	const std::size_t s0 = a > context ? a - context : 0, s1 = std::min(mono.size(), b + context);
	AudioClip span;
	span.sampleRate = from, span.channels = 1;
	span.samples.assign(mono.begin() + std::ptrdiff_t(s0), mono.begin() + std::ptrdiff_t(s1));
	char path[] = "/tmp/talkhead-stream-XXXXXX.wav";
	const int fd = mkstemps(path, 4);
	if (fd < 0) throw Error("cannot make a temporary file for the audio");
	::close(fd);
	registerTemporary(path);
	AudioClip resampled;
	try {
		writeWav(path, span);
		resampled = decodeAudio(path, to);
	} catch (...) {
		::unlink(path);
		releaseTemporary(path);
		throw;
	}
	::unlink(path);
	releaseTemporary(path);
	const double shift = double(s0) * to / from;  // output sample index of the span's first sample
	const std::size_t ch = std::size_t(std::max(1, resampled.channels));
	for (std::size_t k = 0; k < out.size(); ++k) {
		const long long j = std::llround(double(outA + k) - shift);
		if (j >= 0 && std::size_t(j) < resampled.frameCount()) out[k] = resampled.samples[std::size_t(j) * ch];
	}
	return out;
}

// The first `count` words of `text` (as espeak-ng's word events write them, found in order) and the rest.
std::pair<std::string, std::string> splitAfterWords(const std::string& text, const std::vector<std::string>& words, std::size_t count) {
	std::size_t at = 0;
	for (std::size_t k = 0; k < count && k < words.size(); ++k) {
		const std::size_t f = text.find(words[k], at);
		if (f == std::string::npos) break;
		at = f + words[k].size();
	}
	return {text.substr(0, at), text.substr(at)};
}

// At most `words` whitespace-separated words of `text` (what could be said in the audio at hand).
std::string firstWords(const std::string& text, std::size_t words) {
	std::size_t at = 0, n = 0;
	while (at < text.size() && n < words) {
		while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
		if (at >= text.size()) break;
		while (at < text.size() && !std::isspace(static_cast<unsigned char>(text[at]))) ++at;
		++n;
	}
	return text.substr(0, at);
}

}  // namespace

SpeechStream::SpeechStream(std::string id, std::string text, const Language& language, int inputRate, int sampleRate, SpeechStreamOptions options)
    : id_(std::move(id)), text_(std::move(text)), language_(language), inputRate_(inputRate), sampleRate_(sampleRate), o_(options), recognizing_(trim(text_).empty()) {
	if (inputRate_ < 8000 || inputRate_ > 192000) throw Error("a streamed speak's sample rate must be 8000–192000 Hz");
}

Ticks SpeechStream::received() const { return ticksAt(audio_.size(), inputRate_); }

AudioClip SpeechStream::inputSpan(Ticks from, Ticks to) const {
	AudioClip c;
	c.sampleRate = inputRate_, c.channels = 1;
	const std::size_t a = std::min(audio_.size(), samplesAt(from, inputRate_)), b = std::min(audio_.size(), samplesAt(to, inputRate_));
	c.samples.assign(audio_.begin() + std::ptrdiff_t(a), audio_.begin() + std::ptrdiff_t(std::max(a, b)));
	return c;
}

void SpeechStream::give(Ticks end, std::vector<PhoneSegment> phones, std::vector<std::string> warnings, bool closes, const Emit& emit) {
	const std::size_t a = samplesAt(given_, inputRate_), b = std::max(a, std::min(audio_.size(), samplesAt(end, inputRate_)));
	Utterance u;
	u.id = id_;
	u.audio.sampleRate = sampleRate_, u.audio.channels = 1;
	u.audio.samples = resampledSpan(audio_, inputRate_, a, b, sampleRate_);
	const Ticks length = u.audio.duration();
	// The phones within the part: the last ends where its sound does.
	for (PhoneSegment& p : phones) p.start = std::min(p.start, length), p.end = std::min(p.end, length);
	phones.erase(std::remove_if(phones.begin(), phones.end(), [](const PhoneSegment& p) { return p.end <= p.start; }), phones.end());
	if (!phones.empty()) phones.back().end = length;
	u.phones = std::move(phones);
	u.timing = recognizing_ ? PhoneTiming::Recognised : PhoneTiming::Aligned;  // recognised, or the text aligned as the audio arrives
	u.warnings = std::move(warnings);
	u.opens = parts_ == 0;
	u.closes = closes;
	given_ = ticksAt(b, inputRate_);
	++parts_;
	if (closes) closed_ = true;
	// The first parts wait until they hold `lead` seconds (or the stream ends), so that playing them does not
	// catch up with the words still to be aligned. Once the whole audio is there nothing waits: the parts still
	// to come are made faster than these play (recognised: utterances at most twice as long as the one before,
	// decoded at ≥ 5× real time per decoder, D101).
	held_.push_back(std::move(u));
	if (!closes && !flowing_ && !complete_ && toSeconds(given_) < o_.lead) return;
	flowing_ = true;
	for (Utterance& h : held_) emit(std::move(h));
	held_.clear();
}

void SpeechStream::feed(const std::vector<float>& piece, bool last, const Emit& emit, const std::atomic<bool>* cancel, bool look) {
	if (closed_) throw Error("the streamed speak has ended");
	audio_.insert(audio_.end(), piece.begin(), piece.end());
	complete_ = complete_ || last;
	if (!look && !last) return;
	try {
		if (recognizing_) recognize(last, emit, cancel);
		else alignWords(last, emit);
	} catch (...) {
		closed_ = true;
		throw;
	}
}

void SpeechStream::alignWords(bool last, const Emit& emit) {
	AlignOptions ao;
	ao.languageTag = language_.tag();
	const Ticks end = received();
	// The phones of an alignment of [origin_, …) from given_ to `to`, from 0 of the part. They begin with the
	// first word not given yet: this alignment may end a word given already after the cut (where the one that
	// gave it ended it), and its tail would say that word's last phones again; the first new phone starts at
	// the cut instead.
	const auto partPhones = [&](const Alignment& al, Ticks to) {
		Transcript t = al.phones;
		t.intervals.clear();
		const Ticks from = given_ - origin_;
		const Ticks next = givenWords_ > 0 && givenWords_ < al.wordList.size() ? al.wordList[givenWords_].start : from;
		const Ticks keep = std::max(from, next);
		for (Interval iv : al.phones.intervals) {
			if (iv.end <= keep) continue;
			if (iv.start >= to) break;
			iv.start = t.intervals.empty() ? from : std::max(iv.start, from);
			iv.start -= from;
			iv.end = std::min(iv.end, to) - from;
			if (iv.end > iv.start) t.intervals.push_back(iv);
		}
		return phoneSegments(t, language_, UnknownPhone::Error, Notation::Ipa);
	};
	const AudioClip rest = inputSpan(origin_, end);
	if (last) {
		// The text from the origin against the audio from it: the phones after what was given.
		std::vector<PhoneSegment> phones;
		std::vector<std::string> warnings;
		if (!trim(text_).empty() && rest.frameCount() > 0) {
			try {
				const Alignment al = alignSpeech(rest, text_, ao);
				phones = partPhones(al, rest.duration());
				warnings = al.warnings;
			} catch (const Error& e) {
				// Punctuation left over is nothing to say; words left over that the audio does not hold are an error.
				if (std::string(e.what()).find("no speakable words") == std::string::npos) throw Error("the streamed speak's end: " + std::string(e.what()));
			}
		}
		text_.clear();
		give(end, std::move(phones), std::move(warnings), true, emit);
		return;
	}
	// Before the lead is reached, a look that cannot reach it is wasted: what it gives ends `margin` before
	// the audio so far, and is held until the parts hold `lead` seconds. In a burst (a TTS faster than real
	// time) such looks held up the one that could give the first part (bench/serve.sh).
	if (!flowing_ && toSeconds(end) - o_.margin < o_.lead) return;
	const double haveSeconds = toSeconds(end - given_);
	const bool firstLook = lastLook_ == 0;
	if (haveSeconds < o_.firstLook || (!firstLook && double(audio_.size() - lastLook_) / inputRate_ < o_.step)) return;
	lastLook_ = audio_.size();
	const Ticks limit = rest.duration() - ticksFromSeconds(o_.margin);
	const std::vector<RenderedWord> words = renderedWords(firstWords(text_, std::size_t(std::ceil((toSeconds(rest.duration()) + 2) * 4))), ao);
	if (words.size() <= givenWords_) {
		// Every word given: what comes is silence (or breath) until the last piece.
		if (limit > given_ - origin_) give(origin_ + limit, {}, {}, false, emit);
		return;
	}
	// Where the speech so far begins (voice activity, as the aligner finds it).
	double speechStart = -1;
	try {
		const VoiceActivity va = detectVoiceActivity(align::frameLevels(rest.samples, rest.sampleRate));
		speechStart = 0.01 * va.first;
	} catch (const Error&) {
	}
	if (speechStart < 0) {
		// Silence before the speech: given out as a pause, so that the utterance starts with its sound.
		if (parts_ == 0 && limit > given_ - origin_ + ticksFromSeconds(o_.margin)) give(origin_ + limit, {}, {}, false, emit);
		return;
	}
	// How many words have begun, from espeak-ng's durations at the pace measured so far; that many, one more
	// and two more are aligned with the audio from the origin (the last, cut short, only shapes the others'
	// ends), and the most confident alignment is kept.
	const double spoken = (toSeconds(rest.duration()) - speechStart) * pace_;
	std::size_t begun = 0;
	while (begun < words.size() && toSeconds(words[begun].start) <= spoken) ++begun;
	AlignOptions partial = ao;
	partial.mismatchBelow = 0;
	std::optional<Alignment> best;
	std::size_t count = 0;
	for (std::size_t c = std::max(begun, givenWords_ + 2); c <= std::min(words.size(), std::max(begun, givenWords_ + 2) + 2); ++c) {
		std::vector<std::string> t;
		for (std::size_t k = 0; k < c; ++k) t.push_back(words[k].text);
		Alignment al = alignSpeech(rest, splitAfterWords(text_, t, c).first, partial);
		if (al.wordList.size() != c) continue;  // a word came out empty
		if (!best || al.confidence > best->confidence) best = std::move(al), count = c;
	}
	if (!best || best->confidence < o_.sure) return;
	const Alignment& al = *best;
	// The words given: those that end `margin` before what has arrived, when the alignment is sure of them.
	std::size_t k = givenWords_;
	double sum = 0;
	while (k + 1 < count && al.wordList[k].end <= limit) ++k;
	for (std::size_t w = 0; w < k; ++w) sum += al.wordList[w].confidence;
	if (k > 0 && sum / double(k) < o_.sure) k = givenWords_;
	if (k == givenWords_) return;  // not sure yet: more audio, or the last piece, decides
	// The cut: in the pause after the last word given, or at its end.
	const Ticks cut = al.wordList[k - 1].end + (al.wordList[k].start - al.wordList[k - 1].end) / 2;
	if (cut <= given_ - origin_) return;
	// The pace: espeak-ng's seconds per second of this speaker's, over the words aligned.
	const double inputSeconds = toSeconds(al.wordList[k - 1].end - al.wordList[0].start);
	if (inputSeconds > 0.3) pace_ = std::clamp(toSeconds(words[k - 1].end - words[0].start) / inputSeconds, 0.5, 2.0);
	std::vector<PhoneSegment> phones = partPhones(al, cut);
	givenWords_ = k;
	give(origin_ + cut, std::move(phones), al.warnings, false, emit);
	// A new origin when the one before lies far back (an alignment's cost grows with its length).
	if (toSeconds(given_ - origin_) >= o_.keepAligned) {
		std::vector<std::string> said;
		for (std::size_t w = 0; w < k; ++w) said.push_back(al.wordList[w].text);
		text_ = splitAfterWords(text_, said, k).second;
		origin_ = given_;
		givenWords_ = 0;
	}
}

void SpeechStream::recognize(bool last, const Emit& emit, const std::atomic<bool>* cancel) {
	const std::size_t have = audio_.size() - std::min(audio_.size(), samplesAt(given_, inputRate_));
	if (!last && (double(audio_.size() - lastLook_) / inputRate_ < o_.recognizeEvery || double(have) / inputRate_ < o_.recognizeEvery)) return;
	lastLook_ = audio_.size();
	const Ticks from = given_, end = received();
	const AudioClip rest = inputSpan(from, end);
	if (rest.frameCount() == 0) {
		if (last) give(end, {}, {}, true, emit);
		return;
	}
	RecognizeOptions ro;
	ro.firstUtteranceSeconds = parts_ == 0 ? o_.firstRecognized : 0;
	// Streamed and not the last piece: only utterances that end this far before what has arrived are over.
	const Ticks settled = last ? rest.duration() : rest.duration() - ticksFromSeconds(0.6);
	ro.progress = [&](Ticks upTo, const std::vector<Interval>& phones, const std::vector<double>&) {
		if (cancel && cancel->load()) return false;
		if (upTo >= settled) return true;  // not over yet, or the last part (given below)
		Transcript t;
		t.level = LabelLevel::Phone;
		t.format = "recognized";
		const Ticks start = given_ - from;
		for (Interval iv : phones) {
			iv.start = std::max(Ticks(0), iv.start - start), iv.end -= start;
			if (iv.end > iv.start) t.intervals.push_back(iv);
		}
		t.intervals = withPauses(t.intervals, Ticks(0), upTo - start);
		toLanguage(t, language_);
		give(from + upTo, phoneSegments(t, language_, UnknownPhone::Silence, Notation::Ipa), {}, false, emit);
		return true;
	};
	Recognition rec;
	try {
		rec = recognizePhonesClip(rest, "audio", ro);
	} catch (const Error&) {
		if (cancel && cancel->load()) throw SpeechCancelled();
		throw;
	}
	if (cancel && cancel->load()) throw SpeechCancelled();
	if (!last) return;
	// The rest: the phones after the last part given.
	Transcript t;
	t.level = LabelLevel::Phone;
	t.format = "recognized";
	const Ticks start = given_ - from;
	for (Interval iv : rec.phones.intervals) {
		if (iv.label.empty() || iv.end <= start) continue;
		iv.start = std::max(Ticks(0), iv.start - start), iv.end -= start;
		t.intervals.push_back(iv);
	}
	t.intervals = withPauses(t.intervals, Ticks(0), end - given_);
	toLanguage(t, language_);
	std::vector<std::string> warnings = rec.warnings;
	if (language_.tag() != "en-US") warnings.push_back("the phones are en-US's (the only phone recogniser talkhead has), in " + language_.tag() + "'s nearest phones");
	give(end, phoneSegments(t, language_, UnknownPhone::Silence, Notation::Ipa), std::move(warnings), true, emit);
}

}  // namespace talkhead
