// SPDX-License-Identifier: GPL-3.0-or-later
// libespeak-ng lives in this translation unit only (PRIVATE to the phonetics module).
#include "phonetics/espeak.h"

#include <espeak-ng/espeak_ng.h>
#include <espeak-ng/speak_lib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/language.h"

namespace talkhead {

namespace {

std::mutex& espeakMutex() {
	static std::mutex m;  // espeak-ng keeps global state: one synthesis at a time
	return m;
}

struct Collector {
	std::vector<std::pair<std::string, int>> phonemes;  // name, audio position (ms)
	struct Word {
		int textPosition, length, audioPosition;  // characters (1-based), characters, ms
	};
	std::vector<Word> words;
	long samples = 0;
	std::vector<short>* pcm = nullptr;  // where to keep the audio (speak), or nullptr (phonemes only)
	long maxSamples = 0;                         // 0: no bound (SpeechLimits)
	const std::atomic<bool>* cancel = nullptr;
	bool cancelled = false, tooLong = false;     // why the synthesis was stopped
};

Collector* g_current = nullptr;  // the synthesis in progress (guarded by espeakMutex)

int onSynth(short* wav, int count, espeak_EVENT* events) {
	Collector* c = g_current;
	if (!c) return 0;
	if (count > 0) {
		c->samples += count;
		if (c->pcm && count > 0) c->pcm->insert(c->pcm->end(), wav, wav + count);
	}
	// Returning 1 stops the synthesis (espeak-ng calls back every few milliseconds of audio).
	if (c->cancel && c->cancel->load(std::memory_order_relaxed)) return c->cancelled = true, 1;
	if (c->maxSamples > 0 && c->samples > c->maxSamples) return c->tooLong = true, 1;
	for (espeak_EVENT* e = events; e && e->type != espeakEVENT_LIST_TERMINATED; ++e) {
		if (e->type == espeakEVENT_PHONEME) {
			char name[9] = {};
			std::memcpy(name, e->id.string, 8);
			// "(en)" … "(fr)": espeak-ng switching language for a word it reads as foreign, not a phone;
			// dropped, so that the phone before it lasts until the next one (no silence inside a word).
			if (name[0] == '(') continue;
			c->phonemes.emplace_back(name, e->audio_position);
		} else if (e->type == espeakEVENT_WORD) {
			c->words.push_back({e->text_position, e->length, e->audio_position});
		}
	}
	return 0;
}

// Under espeakMutex. A failure is not remembered (out of file descriptors now need not mean later), and never
// ends the process: espeak_Initialize calls exit(1) when its data cannot be loaded unless told not to
// (issue 28 item 6), so espeak-ng's own initialisation is tried first and its status read.
int initialise() {
	static int rate = 0;
	if (rate > 0) return rate;
	espeak_ng_InitializePath(nullptr);
	espeak_ng_ERROR_CONTEXT context = nullptr;
	const espeak_ng_STATUS status = espeak_ng_Initialize(&context);
	espeak_ng_ClearErrorContext(&context);
	if (status != ENS_OK) {
		char message[256] = {};
		espeak_ng_GetStatusCodeMessage(status, message, sizeof message - 1);
		// System errors come back as their errno; the hint only where it is the likely cause.
		const std::string hint = status == EMFILE || status == ENFILE ? " (the process is out of file descriptors)"
		                         : status == ENOENT                   ? " (is the espeak-ng-data package installed?)"
		                                                              : "";
		throw Error(std::string("cannot initialise espeak-ng: ") + message + hint);
	}
	const int r = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 0, nullptr,
	                                espeakINITIALIZE_PHONEME_EVENTS | espeakINITIALIZE_PHONEME_IPA | espeakINITIALIZE_DONT_EXIT);
	if (r <= 0) throw Error("cannot initialise espeak-ng (is the espeak-ng-data package installed?)");
	espeak_SetSynthCallback(onSynth);
	return rate = r;
}

// The names espeak-ng accepts for a voice (lower case) and its variants (as written), listed once.
struct VoiceNames {
	std::set<std::string> voices, variants;
};
const VoiceNames& voiceNames() {  // under espeakMutex, after initialise()
	static VoiceNames names = [] {
		VoiceNames n;
		auto base = [](const char* id) {
			const std::string s = id ? id : "";
			return s.substr(s.rfind('/') == std::string::npos ? 0 : s.rfind('/') + 1);
		};
		if (const espeak_VOICE** list = espeak_ListVoices(nullptr))
			for (; *list; ++list) {
				const espeak_VOICE* v = *list;
				if (v->name) n.voices.insert(toLower(v->name));
				if (v->identifier) n.voices.insert(toLower(base(v->identifier)));
				// languages: [priority byte, name, NUL]…, ended by a zero priority byte.
				for (const char* l = v->languages; l && *l; l += std::strlen(l + 1) + 2) n.voices.insert(toLower(l + 1));
			}
		espeak_VOICE spec{};
		spec.languages = "variant";
		if (const espeak_VOICE** list = espeak_ListVoices(&spec))
			for (; *list; ++list)
				if ((*list)->identifier) n.variants.insert(base((*list)->identifier));
		return n;
	}();
	return names;
}

bool voiceCharacters(const std::string& s) {
	return !s.empty() && s.size() <= 32 && std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; });
}

// checkedEspeakVoice under espeakMutex.
std::string checkVoice(const std::string& voice) {
	initialise();
	const auto plus = voice.find('+');
	const std::string name = voice.substr(0, plus);
	const std::string shown = "'" + safeQuote(voice.size() > 60 ? voice.substr(0, 60) + "…" : voice) + "'";
	if (!voiceCharacters(name)) throw Error("espeak-ng has no voice " + shown + " (a voice name is letters, digits, - and _, at most 32; espeak-ng --voices lists them)");
	if (!startsWith(toLower(name), "mb-") && !voiceNames().voices.count(toLower(name)))
		throw Error("espeak-ng has no voice " + shown + " (espeak-ng --voices lists them)");
	if (plus == std::string::npos) return name;
	std::string variant = voice.substr(plus + 1);
	if (!voiceCharacters(variant)) throw Error("espeak-ng has no voice variant " + shown + " (espeak-ng --voices=variant lists them)");
	if (std::all_of(variant.begin(), variant.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) variant = "m" + variant;
	if (!voiceNames().variants.count(variant)) throw Error("espeak-ng has no voice variant " + shown + " (espeak-ng --voices=variant lists them)");
	return name + "+" + variant;
}

class SpeechTooLong : public Error {
public:
	explicit SpeechTooLong(double limit) : Error(message(limit)) {}
	static std::string message(double limit) {
		char b[160];
		std::snprintf(b, sizeof b, "the speech is longer than %g s (the limit on speech at once)", limit);
		return b;
	}
};

bool isPause(const std::string& ipa) { return ipa.empty() || ipa == "_" || ipa == "_:" || ipa == "_!" || ipa == "||" || ipa == "|"; }

}  // namespace

std::string espeakVoiceFor(const std::string& tag) {
	// espeak-ng names Mandarin cmn (its "zh" is a language of that voice, not a voice name).
	const std::string t = toLower(tag);
	if (t == "zh" || t == "zh-cn" || t == "zh-hans" || t == "zho") return "cmn";
	return t;
}

std::string checkedEspeakVoice(const std::string& voice) {
	std::lock_guard<std::mutex> lock(espeakMutex());
	return checkVoice(voice);
}

std::optional<VoiceLanguage> espeakVoiceLanguage(const std::string& voice) {
	const std::string name = voice.substr(0, voice.find('+'));  // without a variant (en-us+f3)
	if (name.empty()) return std::nullopt;
	std::lock_guard<std::mutex> lock(espeakMutex());
	try {
		checkVoice(name);
	} catch (const Error&) {
		return std::nullopt;
	}
	if (startsWith(name, "mb-")) {
		// MBROLA voices: espeak-ng's voice file says the language; loading the voice would need MBROLA.
		const char* data = nullptr;
		espeak_Info(&data);
		if (!data) return std::nullopt;
		std::ifstream in(std::string(data) + "/voices/mb/" + name);
		for (std::string line; std::getline(in, line);) {
			const auto w = splitWhitespace(line);
			if (w.size() >= 2 && w[0] == "language") return VoiceLanguage{toLower(w[1]), ""};
		}
		return std::nullopt;
	}
	if (espeak_SetVoiceByName(name.c_str()) != EE_OK) return std::nullopt;
	const espeak_VOICE* v = espeak_GetCurrentVoice();
	// languages: a priority byte, then the language name, NUL-terminated (the first is the main one).
	if (!v || !v->languages || !v->languages[0] || !v->languages[1]) return std::nullopt;
	return VoiceLanguage{toLower(std::string(v->languages + 1)), v->name ? std::string(v->name) : ""};
}

namespace {
void setVoice(const std::string& unchecked) {
	const std::string voice = checkVoice(unchecked);
	if (startsWith(voice, "mb-")) {
		// Check for MBROLA first: espeak-ng would print its own multi-line complaint.
		const std::string name = voice.substr(3);
		std::error_code ec;
		bool found = std::filesystem::exists("/usr/bin/mbrola", ec);
		bool voiceFound = false;
		for (const std::string& p : {"/usr/share/mbrola/" + name + "/" + name, "/usr/share/mbrola/" + name, "/usr/share/mbrola/voices/" + name})
			voiceFound |= std::filesystem::is_regular_file(p, ec);
		if (!found || !voiceFound)
			throw Error("espeak-ng cannot use the MBROLA voice '" + voice + "': install MBROLA and that voice (Debian contrib/non-free: enable them in " +
			            "/etc/apt/sources.list, then apt-get install mbrola mbrola-" + name + ")");
	}
	if (espeak_SetVoiceByName(voice.c_str()) == EE_OK) return;
	throw Error("espeak-ng has no voice '" + voice + "' (espeak-ng --voices lists them)");
}
}  // namespace

namespace {
// The substring of UTF-8 `text` at 1-based character position `pos`, `length` characters long.
std::string utf8Substring(const std::string& text, int pos, int length) {
	std::size_t i = 0, start = std::string::npos;
	int ch = 0;
	for (; i <= text.size(); ++i) {
		if (i < text.size() && (static_cast<unsigned char>(text[i]) & 0xC0) == 0x80) continue;  // continuation byte
		++ch;
		if (ch == pos) start = i;
		if (ch == pos + length) break;
	}
	if (start == std::string::npos || start >= text.size()) return "";
	return text.substr(start, std::min(i, text.size()) - start);
}
}  // namespace

namespace {
// libespeak-ng overflows a stack buffer (abort: "stack smashing detected", the espeak-ng CLI too) on a long
// token such as "x." and ~170 letters — a URL in say text or a word-level transcript (issue 15 item 1).
// Tokens longer than 48 code points are cut into pieces of 32 (they are read letter by letter anyway).
std::string splitLongTokens(const std::string& text) {
	auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
	auto isLead = [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; };  // not a UTF-8 continuation
	std::string out;
	out.reserve(text.size() + text.size() / 32);
	for (std::size_t i = 0; i < text.size();) {
		if (isSpace(text[i])) {
			out += text[i++];
			continue;
		}
		std::size_t j = i;
		int points = 0;
		while (j < text.size() && !isSpace(text[j])) points += isLead(text[j++]);
		if (points <= 48) {
			out.append(text, i, j - i);
		} else {
			int run = 0;
			for (std::size_t k = i; k < j; ++k) {
				if (isLead(text[k]) && run++ == 32) {
					out += ' ';
					run = 1;
				}
				out += text[k];
			}
		}
		i = j;
	}
	return out;
}
}  // namespace

// What libespeak-ng is given is valid UTF-8 (malformed sequences — a lone continuation byte, an overlong or
// truncated sequence, a surrogate — become spaces: libespeak-ng 1.51 reads freed memory on some, found by
// the words_espeak fuzz target), and for Latin-script voices (the languages with viseme tables but for
// --generic-visemes ones) characters outside Latin, its extensions, punctuation, currency and
// letter-like symbols become spaces too: libespeak-ng reads freed memory on some of those as well (U+0D00,
// Malayalam; ASan; a release build silently says "nothing to say"), issue 15 item 2, and a Latin voice
// cannot say them anyway. Returns how many were replaced.
static int dropForeignScript(std::string& text, const std::string& voice) {
	const std::string v = toLower(voice);
	bool latin = false;
	for (const char* p : {"pt", "en", "es", "fr", "de", "it", "mb-br", "mb-us", "mb-en", "mb-es", "mb-fr", "mb-de", "mb-it"})
		latin |= v.rfind(p, 0) == 0;
	std::string out;
	int dropped = 0;
	for (std::size_t i = 0; i < text.size();) {
		const unsigned char c = static_cast<unsigned char>(text[i]);
		// Strict UTF-8 (RFC 3629): the lead byte gives the length and the smallest code point allowed.
		std::size_t n = 0;
		std::uint32_t cp = 0, least = 0;
		if (c < 0x80) n = 1, cp = c;
		else if (c >= 0xC2 && c <= 0xDF) n = 2, cp = c & 0x1F, least = 0x80;
		else if (c >= 0xE0 && c <= 0xEF) n = 3, cp = c & 0x0F, least = 0x800;
		else if (c >= 0xF0 && c <= 0xF4) n = 4, cp = c & 0x07, least = 0x10000;
		bool valid = n > 0 && i + n <= text.size();
		for (std::size_t k = 1; valid && k < n; ++k) {
			const unsigned char b = static_cast<unsigned char>(text[i + k]);
			valid = (b & 0xC0) == 0x80;
			cp = (cp << 6) | (b & 0x3F);
		}
		valid = valid && cp >= least && cp <= 0x10FFFF && !(cp >= 0xD800 && cp <= 0xDFFF);
		if (!valid) {  // one byte at a time: the next may start a good sequence
			out += ' ', ++dropped;
			++i;
			continue;
		}
		const bool keep = !latin || cp < 0x0250 || (cp >= 0x1E00 && cp <= 0x1EFF) || (cp >= 0x2000 && cp <= 0x20CF) || (cp >= 0x2100 && cp <= 0x214F) ||
		                  (cp >= 0x0300 && cp <= 0x036F);
		if (keep) out.append(text, i, n);
		else out += ' ', ++dropped;
		i += n;
	}
	text = std::move(out);
	return dropped;
}

Speech espeakSpeak(const std::string& rawText, const std::string& voice, int rateWpm, int pitch, int wordGap10ms, const SpeechLimits& limits) {
	std::string text = splitLongTokens(rawText);
	const int dropped = dropForeignScript(text, voice);
	if (trim(text).empty()) throw Error("nothing to say: the text is empty");
	std::lock_guard<std::mutex> lock(espeakMutex());
	const int rate = initialise();
	setVoice(voice);
	espeak_SetParameter(espeakRATE, rateWpm > 0 ? rateWpm : 175, 0);
	espeak_SetParameter(espeakPITCH, pitch >= 0 ? pitch : 50, 0);
	espeak_SetParameter(espeakWORDGAP, std::max(0, wordGap10ms), 0);
	Speech sp;
	sp.sampleRate = rate;
	if (dropped > 0)
		sp.warnings.push_back(std::to_string(dropped) + (dropped > 1 ? " characters" : " character") + " outside the " + voice + " voice's script (or not UTF-8) " +
		                      (dropped > 1 ? "were" : "was") + " left out (read as spaces)");
	Collector c;
	c.pcm = &sp.pcm;
	c.cancel = limits.cancel;
	c.maxSamples = limits.maxSeconds > 0 ? long(limits.maxSeconds * rate) : 0;
	g_current = &c;
	const std::string z = text + '\0';
	const espeak_ERROR err = espeak_Synth(z.data(), z.size(), 0, POS_CHARACTER, 0, espeakCHARS_UTF8, nullptr, nullptr);
	espeak_Synchronize();
	g_current = nullptr;
	espeak_SetParameter(espeakRATE, 175, 0);
	espeak_SetParameter(espeakPITCH, 50, 0);
	espeak_SetParameter(espeakWORDGAP, 0, 0);
	if (c.cancelled) throw SpeechCancelled();
	if (c.tooLong) throw SpeechTooLong(limits.maxSeconds);
	if (err != EE_OK) throw Error("espeak-ng could not synthesise the text");
	const std::int64_t ticksPerSample = kTicksPerSecond / rate;
	const Ticks end(std::int64_t(sp.pcm.size()) * ticksPerSample);
	bool speech = false;
	sp.phones.path = "espeak-ng";
	sp.phones.format = "espeak";
	Ticks t(0);
	for (std::size_t i = 0; i < c.phonemes.size(); ++i) {
		const Ticks start = std::min(end, Ticks(std::int64_t(c.phonemes[i].second) * (kTicksPerSecond / 1000)));
		const Ticks next = i + 1 < c.phonemes.size() ? std::min(end, Ticks(std::int64_t(c.phonemes[i + 1].second) * (kTicksPerSecond / 1000))) : end;
		if (start > t) sp.phones.intervals.push_back({t, start, "", 0});  // silence before the phoneme
		const Ticks a = std::max(t, start);
		if (next <= a) continue;
		const std::string name = isPause(c.phonemes[i].first) ? "" : c.phonemes[i].first;
		speech |= !name.empty();
		sp.phones.intervals.push_back({a, next, name, long(i + 1)});
		t = next;
	}
	if (t < end) sp.phones.intervals.push_back({t, end, "", 0});
	if (!speech || sp.pcm.empty()) throw Error("nothing to say: the text has no speakable words");
	// Words: from each word event to the end of the last phone that starts before the next word event (at
	// most that event: a stop's closure before its phoneme event belongs to the next word).
	sp.words.path = "espeak-ng";
	sp.words.format = "espeak";
	sp.words.level = LabelLevel::Word;
	const auto ms = [&](int v) { return std::min(end, Ticks(std::int64_t(v) * (kTicksPerSecond / 1000))); };
	std::size_t p = 0;
	for (std::size_t k = 0; k < c.words.size(); ++k) {
		const Ticks start = std::max(ms(c.words[k].audioPosition), sp.words.intervals.empty() ? Ticks(0) : sp.words.intervals.back().end);
		const Ticks next = k + 1 < c.words.size() ? ms(c.words[k + 1].audioPosition) : end;
		Ticks last{-1};
		for (; p < sp.phones.intervals.size() && sp.phones.intervals[p].start < next; ++p)
			if (!sp.phones.intervals[p].label.empty() && sp.phones.intervals[p].end > start) last = std::min(sp.phones.intervals[p].end, next);
		if (last <= start) continue;  // a word that says nothing
		sp.words.intervals.push_back({start, last, utf8Substring(text, c.words[k].textPosition, c.words[k].length), long(c.words[k].textPosition)});
	}
	// A pause event inside a word (espeak-ng marks the hiatus of "Maria", "tia", "rio" with a 38–64 ms pause)
	// is not a silence: the mouth goes on from one vowel to the next. It joins the phone before it.
	std::vector<Interval> merged;
	std::size_t w = 0;
	for (std::size_t i = 0; i < sp.phones.intervals.size(); ++i) {
		const Interval& iv = sp.phones.intervals[i];
		while (w < sp.words.intervals.size() && sp.words.intervals[w].end <= iv.start) ++w;
		const bool inside = iv.label.empty() && w < sp.words.intervals.size() && iv.start > sp.words.intervals[w].start && iv.end < sp.words.intervals[w].end &&
		                    !merged.empty() && !merged.back().label.empty() && i + 1 < sp.phones.intervals.size() && !sp.phones.intervals[i + 1].label.empty();
		if (inside) merged.back().end = iv.end;
		else merged.push_back(iv);
	}
	sp.phones.intervals = std::move(merged);
	return sp;
}

Transcript phonesWithClosures(const Speech& sp) {
	std::vector<Interval> ph = sp.phones.intervals;
	for (const Interval& w : sp.words.intervals) {
		std::size_t q = 0;  // the word's first phone: the first one starting at or after the word event
		const Ticks slack(kTicksPerSecond / 200);  // 5 ms of rounding between the two events
		while (q < ph.size() && (ph[q].label.empty() || ph[q].start + slack < w.start)) ++q;
		if (q >= ph.size() || ph[q].start >= w.end || ph[q].start <= w.start) continue;
		for (std::size_t r = 0; r < q; ++r) {
			ph[r].end = std::min(ph[r].end, w.start);
			ph[r].start = std::min(ph[r].start, ph[r].end);
		}
		ph[q].start = w.start;
	}
	Transcript t = sp.phones;
	t.intervals.clear();
	for (Interval& i : ph)
		if (i.end > i.start) t.intervals.push_back(std::move(i));
	return t;
}

std::vector<SpokenPhone> espeakPhones(const std::string& rawText, const std::string& voice) {
	std::string text = splitLongTokens(rawText);
	dropForeignScript(text, voice);
	std::lock_guard<std::mutex> lock(espeakMutex());
	const int rate = initialise();
	if (espeak_SetVoiceByName(checkVoice(voice).c_str()) != EE_OK) throw Error("espeak-ng has no voice '" + safeQuote(voice) + "'");
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

std::map<std::string, std::string> espeakPhonemeNames(const std::vector<std::string>& words, const std::string& voice) {
	// The whole list through espeak_TextToPhonemes (fast: no sound), one word kept per phoneme it names;
	// then each kept word spoken, for the names its phoneme events carry (what espeakSpeak reads, and not
	// always spelled alike: "nʲ" there is "n" "ʲ" here, French "y-" is "y").
	std::map<std::string, std::string> examples;
	{
		std::lock_guard<std::mutex> lock(espeakMutex());
		initialise();
		if (espeak_SetVoiceByName(checkVoice(voice).c_str()) != EE_OK) throw Error("espeak-ng has no voice '" + safeQuote(voice) + "'");
		const int mode = espeakPHONEMES_IPA | (int(' ') << 8);  // IPA names, a space between phonemes
		for (const std::string& raw : words) {
			std::string w = splitLongTokens(raw);
			dropForeignScript(w, voice);
			if (trim(w).empty()) continue;
			const std::string z = w + '\0';
			const void* p = z.data();
			while (p) {
				const char* ph = espeak_TextToPhonemes(&p, espeakCHARS_UTF8, mode);
				if (!ph) break;
				for (const std::string& name : splitWhitespace(ph)) examples.emplace(name, raw);
			}
		}
	}
	std::set<std::string> spoken;
	for (const auto& [name, word] : examples) spoken.insert(word);
	std::map<std::string, std::string> names;
	for (const std::string& word : spoken)
		for (const SpokenPhone& p : espeakPhones(word, voice)) names.emplace(p.ipa, word);
	return names;
}

std::vector<Interval> expandWords(const Transcript& words, const std::string& tag) {
	const std::string voice = espeakVoiceFor(tag);
	std::vector<Interval> out;
	for (const Interval& w : words.intervals) {
		const std::string l = toLower(w.label);
		if (isPauseLabel(l)) {  // also <unk>, spn, {LG}: MFA and Buckeye non-speech
			out.push_back({w.start, w.end, "", w.line});
			continue;
		}
		std::vector<SpokenPhone> ph = espeakPhones(w.label, voice);
		if (ph.empty()) {
			out.push_back({w.start, w.end, "", w.line});
			continue;
		}
		// The word's span shared in proportion to espeak-ng's durations, in 128-bit arithmetic: a 100-s word
		// times a second of phones overflows 64 bits (issue 15 item 3: times ran backwards, exit 0). Phones
		// without durations share the span equally.
		std::int64_t total = 0;
		for (const auto& p : ph) total += std::max<std::int64_t>(0, p.duration.count());
		const bool equal = total <= 0;
		if (equal) total = std::int64_t(ph.size());
		const __int128 span = std::max<std::int64_t>(0, (w.end - w.start).count());
		std::int64_t acc = 0;
		for (const auto& p : ph) {
			const Ticks a = w.start + Ticks(std::int64_t(span * acc / total));
			acc += equal ? 1 : std::max<std::int64_t>(0, p.duration.count());
			const Ticks b = w.start + Ticks(std::int64_t(span * acc / total));
			out.push_back({a, b, p.ipa, w.line});
		}
	}
	return out;
}

}  // namespace talkhead

namespace talkhead {

namespace {

// Appends one spoken segment of an SSML text at `at`; returns where the speech now ends. The segment's words
// also go to `words`.
Ticks appendSegment(Speech& out, const Speech& sp, Ticks at, bool breakBefore, bool breakAfter, std::vector<Interval>& words) {
	// Next to a <break> the segment's own edge silence goes, so the pause is the break's length: from
	// its first word's start, to its last phone's end.
	const Ticks spEnd = ticksFromSeconds(double(sp.pcm.size()) / sp.sampleRate);
	Ticks from{0}, to = spEnd;
	if (breakBefore && !sp.words.intervals.empty()) from = sp.words.intervals.front().start;
	if (breakAfter)
		for (auto it = sp.phones.intervals.rbegin(); it != sp.phones.intervals.rend(); ++it)
			if (!it->label.empty()) {
				to = it->end;
				break;
			}
	const std::size_t a = std::size_t(std::llround(toSeconds(from) * sp.sampleRate)), b = std::min(sp.pcm.size(), std::size_t(std::llround(toSeconds(to) * sp.sampleRate)));
	const Ticks offset = at - from;
	out.pcm.insert(out.pcm.end(), sp.pcm.begin() + long(std::min(a, b)), sp.pcm.begin() + long(b));
	const Ticks end = ticksFromSeconds(double(out.pcm.size()) / out.sampleRate);
	for (Interval iv : sp.phones.intervals) {
		iv.start = std::max(iv.start, from) + offset;
		iv.end = std::min(iv.end, to) + offset;
		if (iv.end <= iv.start) continue;
		if (iv.label.empty() && !out.phones.intervals.empty() && out.phones.intervals.back().label.empty()) out.phones.intervals.back().end = iv.end;
		else out.phones.intervals.push_back(iv);
	}
	if (!out.phones.intervals.empty()) out.phones.intervals.back().end = end;
	for (Interval w : sp.words.intervals) {
		w.start = std::max(w.start, from) + offset;
		w.end = std::min(w.end, to) + offset;
		words.push_back(w);
		out.words.intervals.push_back(w);
	}
	return end;
}

}  // namespace

Speech espeakSpeakSsml(const SsmlText& ssml, const std::string& voice, std::vector<Ticks>& eventTimes, int rateWpm, int pitch, const SpeechLimits& limits) {
	// The breaks are known before anything is spoken: too many seconds of them are refused at once (a text
	// of <break time="60s"/> would otherwise make hours of silence, issue 28 item 5).
	double breaks = 0;
	for (const SsmlText::Segment& seg : ssml.segments) breaks += toSeconds(seg.pauseAfter);
	const auto refuse = [](const char* what, double value, double limit) {
		char b[200];
		std::snprintf(b, sizeof b, "%s add up to %.1f s, more than the %g s allowed", what, value, limit);
		throw Error(b);
	};
	if (limits.maxBreakSeconds > 0 && breaks > limits.maxBreakSeconds) refuse("the text's breaks", breaks, limits.maxBreakSeconds);
	if (limits.maxSeconds > 0 && breaks > limits.maxSeconds) refuse("the text's breaks", breaks, limits.maxSeconds);
	Speech out;
	out.phones.path = out.words.path = "espeak-ng";
	out.phones.format = out.words.format = "espeak";
	out.words.level = LabelLevel::Word;
	std::vector<Ticks> segmentStart(ssml.segments.size()), segmentEnd(ssml.segments.size());
	std::vector<std::vector<Interval>> segmentWords(ssml.segments.size());
	Ticks at{0};
	auto addPause = [&](Ticks length) {
		if (length <= Ticks(0)) return;
		const std::size_t samples = std::size_t(std::llround(toSeconds(length) * (out.sampleRate > 0 ? out.sampleRate : 22050)));
		if (out.sampleRate <= 0) out.sampleRate = 22050;  // fixed up by the first spoken segment (espeak-ng's rate)
		out.pcm.insert(out.pcm.end(), samples, 0);
		const Ticks end = ticksFromSeconds(double(out.pcm.size()) / out.sampleRate);
		if (!out.phones.intervals.empty() && out.phones.intervals.back().label.empty()) out.phones.intervals.back().end = end;
		else out.phones.intervals.push_back(Interval{at, end, "", 0});
		at = end;
	};
	bool anySpeech = false;
	for (std::size_t s = 0; s < ssml.segments.size(); ++s) {
		const SsmlText::Segment& seg = ssml.segments[s];
		segmentStart[s] = at;
		if (!trim(seg.text).empty()) {
			SpeechLimits left = limits;
			if (limits.maxSeconds > 0) {  // what the segments before and the breaks still to come leave
				double rest = 0;
				for (std::size_t k = s; k < ssml.segments.size(); ++k) rest += toSeconds(ssml.segments[k].pauseAfter);
				left.maxSeconds = limits.maxSeconds - toSeconds(at) - rest;
				if (left.maxSeconds <= 0) throw Error(SpeechTooLong::message(limits.maxSeconds));
			}
			Speech sp;
			try {
				sp = espeakSpeak(seg.text, voice, rateWpm, pitch, 0, left);
			} catch (const SpeechTooLong&) {
				throw Error(SpeechTooLong::message(limits.maxSeconds));
			}
			for (auto& w : sp.warnings) out.warnings.push_back(w);
			if (out.sampleRate > 0 && out.sampleRate != sp.sampleRate && !out.pcm.empty()) {
				// A leading pause was laid at an assumed rate: redo it at espeak-ng's.
				const double seconds = double(out.pcm.size()) / out.sampleRate;
				out.pcm.assign(std::size_t(std::llround(seconds * sp.sampleRate)), 0);
			}
			out.sampleRate = sp.sampleRate;
			at = appendSegment(out, sp, at, s > 0 && ssml.segments[s - 1].pauseAfter > Ticks(0), seg.pauseAfter > Ticks(0), segmentWords[s]);
			anySpeech = true;
		}
		segmentEnd[s] = at;
		addPause(seg.pauseAfter);
	}
	if (!anySpeech) throw Error("nothing to say: the text is empty");
	// Each event at the start of the first word at or after its place in its segment's text, else at the end
	// of that segment's speech.
	eventTimes.clear();
	for (const SsmlText::Event& e : ssml.events) {
		Ticks t = segmentEnd[e.segment];
		const std::string& text = ssml.segments[e.segment].text;
		std::size_t characters = 0;  // espeak-ng counts characters, the event's offset is in bytes
		for (std::size_t k = 0; k < e.offset && k < text.size(); ++k) characters += (static_cast<unsigned char>(text[k]) & 0xC0) != 0x80;
		for (const Interval& w : segmentWords[e.segment])
			if (std::size_t(w.line) > characters) {  // 1-based character position > 0-based offset: at or after
				t = w.start;
				break;
			}
		eventTimes.push_back(t);
	}
	return out;
}

namespace {
std::string primaryLanguage(const std::string& tag) { return toLower(tag.substr(0, tag.find('-'))); }
}  // namespace

std::string voiceLanguageMismatch(const std::string& voice, const Language& lang) {
	const auto v = espeakVoiceLanguage(voice);
	if (!v || primaryLanguage(v->language) == primaryLanguage(lang.tag())) return "";
	static const std::map<std::string, std::string> names = {{"pt", "Portuguese"}, {"en", "English"}, {"es", "Spanish"}, {"fr", "French"},
	                                                         {"de", "German"},     {"it", "Italian"}, {"nl", "Dutch"}};
	const std::string primary = primaryLanguage(v->language);
	const auto n = names.find(primary);
	const std::string name = n != names.end() ? n->second : !v->name.empty() ? v->name : v->language;
	std::string table;
	for (const auto& a : Language::available())
		if (toLower(a) == v->language) table = a;
	for (const auto& a : Language::available())
		if (table.empty() && primaryLanguage(a) == primary) table = a;
	return "voice '" + voice + "' speaks " + name + " (" + v->language + ") but {{lang}} is " + lang.tag() + "; add {{lang}} " +
	       (table.empty() ? primary + " {{generic-visemes}}" : table);
}

}  // namespace talkhead
