// SPDX-License-Identifier: GPL-3.0-or-later
// Speech-to-text services' JSON (issue 50): AssemblyAI, Amazon Transcribe, Google Speech-to-Text, Rev.ai,
// Vosk, Speechmatics, whisper.cpp, ElevenLabs Scribe, Azure batch synthesis and recognition — each as its
// writer writes it, with its own unit, speakers and language.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "base/error.h"
#include "base/text.h"
#include "phonetics/timing_readers.h"

namespace talkhead {

namespace {

using timing::allHave;
using timing::anyHave;
using timing::array;
using timing::number;
using timing::object;
using timing::string;

bool isObjectPtr(const JsonValue* v) { return v && v->kind == JsonValue::Kind::Object; }

struct AsrWord {
	double start = 0, end = 0;  // seconds
	std::string text, speaker;
	long index = 0;
};

// Words of one speaker (chosen as timing::chooseSpeaker says) as a word-level transcript.
Transcript wordTranscript(std::vector<AsrWord> words, const std::string& path, const ReadOptions& o, const std::string& what = "speaker") {
	Transcript tr;
	tr.level = LabelLevel::Word;
	std::vector<std::string> speakers;
	for (const AsrWord& w : words)
		if (!w.speaker.empty() && std::find(speakers.begin(), speakers.end(), w.speaker) == speakers.end()) speakers.push_back(w.speaker);
	tr.speakers = speakers;
	tr.speaker = timing::chooseSpeaker(speakers, o, path, what);
	for (const AsrWord& w : words) {
		if ((speakers.size() > 1 || !o.tier.empty()) && w.speaker != tr.speaker) continue;
		const std::string where = "word " + std::to_string(w.index + 1) + " ('" + safeQuote(w.text, 30) + "')";
		if (w.end < w.start) throw Error(path, 0, where + " ends before it starts");
		tr.intervals.push_back({timing::secondsAt(w.start, path, where), timing::secondsAt(w.end, path, where), std::string(trim(w.text)), w.index + 1});
	}
	if (tr.intervals.empty()) throw Error(path, 0, "no timed word in this file");
	return tr;
}

std::string speakerName(const JsonValue* v) {
	if (!v) return "";
	if (v->kind == JsonValue::Kind::String) return v->string;
	if (v->kind == JsonValue::Kind::Number) {
		char b[32];
		std::snprintf(b, sizeof b, "%g", v->number);
		return b;
	}
	return "";
}

const JsonValue& root(const TimingSample& s) { return *s.json(); }

// ---- AssemblyAI: words[] with start/end in milliseconds, audio_duration in seconds --------------------
Transcript assemblyai(const TimingSample& s, const ReadOptions& o) {
	const JsonValue& j = root(s);
	std::vector<AsrWord> words;
	long k = 0;
	for (const JsonValue& w : array(j, "words")->array) {
		const auto a = number(w.find("start")), b = number(w.find("end"));
		const std::string* t = string(w.find("text"));
		if (!a || !b || !t) throw Error(s.path(), 0, "words[" + std::to_string(k) + "] needs text, start and end (milliseconds)");
		words.push_back({*a / 1000, *b / 1000, *t, speakerName(w.find("speaker")), k++});
	}
	Transcript tr = wordTranscript(words, s.path(), o);
	tr.unit = "ms";
	if (const auto d = number(j.find("audio_duration"))) tr.statedDuration = *d;
	return tr;
}

// ---- Amazon Transcribe: results.items[] (pronunciation/punctuation), times as strings in seconds ------
Transcript amazon(const TimingSample& s, const ReadOptions& o) {
	const JsonValue& results = *object(root(s), "results");
	const JsonValue& items = *array(results, "items");
	std::vector<AsrWord> words;
	long k = 0;
	// Older jobs name the speakers in results.speaker_labels.segments[].items[] (start_time → speaker_label).
	std::map<std::string, std::string> speakerAt;
	if (const JsonValue* sl = object(results, "speaker_labels"))
		if (const JsonValue* segs = array(*sl, "segments"))
			for (const JsonValue& g : segs->array)
				if (const JsonValue* its = array(g, "items"))
					for (const JsonValue& it : its->array)
						if (const std::string* t = string(it.find("start_time")))
							if (const std::string* l = string(it.find("speaker_label"))) speakerAt[*t] = *l;
	for (const JsonValue& it : items.array) {
		++k;
		const std::string* type = string(it.find("type"));
		if (!type || *type != "pronunciation") continue;  // punctuation items carry no time
		const JsonValue* alts = array(it, "alternatives");
		const std::string* text = alts && !alts->array.empty() ? string(alts->array[0].find("content")) : nullptr;
		const auto a = number(it.find("start_time")), b = number(it.find("end_time"));
		if (!text || !a || !b) throw Error(s.path(), 0, "results.items[" + std::to_string(k - 1) + "] needs start_time, end_time and alternatives[0].content");
		std::string speaker = speakerName(it.find("speaker_label"));
		if (speaker.empty())
			if (const std::string* t = string(it.find("start_time")); t && speakerAt.count(*t)) speaker = speakerAt[*t];
		words.push_back({*a, *b, *text, speaker, k - 1});
	}
	return wordTranscript(words, s.path(), o);
}

// ---- Google Speech-to-Text: results[].alternatives[0].words[], "1.200s" offsets (v1), startOffset (v2) --
Transcript googleStt(const TimingSample& s, const ReadOptions& o) {
	const JsonValue* j = &root(s);
	if (const JsonValue* r = object(*j, "response")) j = r;  // a long-running operation's answer
	std::vector<AsrWord> words;
	long k = 0;
	// With diarization, v1 repeats every word with its speakerTag in the last result: read that one alone.
	const JsonValue& results = *array(*j, "results");
	const JsonValue* only = nullptr;
	for (const JsonValue& r : results.array)
		if (const JsonValue* alts = array(r, "alternatives"); alts && !alts->array.empty())
			if (const JsonValue* w = array(alts->array[0], "words"); w && anyHave(*w, "speakerTag")) only = &r;
	for (const JsonValue& r : results.array) {
		if (only && &r != only) continue;
		const JsonValue* alts = array(r, "alternatives");
		if (!alts || alts->array.empty()) continue;
		const JsonValue* ws = array(alts->array[0], "words");
		if (!ws) continue;
		for (const JsonValue& w : ws->array) {
			const JsonValue* a = w.find("startTime") ? w.find("startTime") : w.find("startOffset");
			const JsonValue* b = w.find("endTime") ? w.find("endTime") : w.find("endOffset");
			const std::string* t = string(w.find("word"));
			// proto3 JSON leaves out a zero duration: a missing startOffset is 0 s.
			const auto sa = a ? number(a, true) : std::optional<double>(0.0), sb = b ? number(b, true) : std::optional<double>(0.0);
			if (!t || !sa || !sb) throw Error(s.path(), 0, "words[" + std::to_string(k) + "] needs word, startTime and endTime (\"1.200s\")");
			words.push_back({*sa, *sb, *t, speakerName(w.find("speakerTag") ? w.find("speakerTag") : w.find("speakerLabel")), k++});
		}
	}
	if (words.empty()) throw Error(s.path(), 0, "a Google Speech-to-Text answer without word times: ask for enableWordTimeOffsets (v1) or enable_word_time_offsets (v2)");
	return wordTranscript(words, s.path(), o);
}

// ---- Rev.ai: monologues[].elements[] (text with ts/end_ts, punct without) ------------------------------
Transcript revai(const TimingSample& s, const ReadOptions& o) {
	std::vector<AsrWord> words;
	long k = 0;
	for (const JsonValue& m : array(root(s), "monologues")->array) {
		const std::string speaker = speakerName(m.find("speaker"));
		const JsonValue* el = array(m, "elements");
		if (!el) continue;
		for (const JsonValue& e : el->array) {
			const std::string* type = string(e.find("type"));
			if (!type || *type != "text") continue;
			const auto a = number(e.find("ts")), b = number(e.find("end_ts"));
			const std::string* t = string(e.find("value"));
			if (!t || !a || !b) throw Error(s.path(), 0, "monologues' element " + std::to_string(k) + " needs value, ts and end_ts");
			words.push_back({*a, *b, *t, speaker, k++});
		}
	}
	return wordTranscript(words, s.path(), o);
}

// ---- Vosk: {"result": [{conf, start, end, word}], "text"} objects, partials between them -------------
// Vosk with SetMaxAlternatives: {"alternatives": [{"confidence", "result": […], "text"}]}: the first is read.
const JsonValue* voskBest(const JsonValue& v) {
	if (const JsonValue* alts = array(v, "alternatives"); alts && !alts->array.empty() && isObjectPtr(&alts->array[0])) return &alts->array[0];
	return &v;
}

Transcript vosk(const TimingSample& s, const ReadOptions& o) {
	std::vector<const JsonValue*> objects;
	if (s.json()) {
		if (s.json()->kind == JsonValue::Kind::Array)
			for (const JsonValue& v : s.json()->array) objects.push_back(&v);
		else objects.push_back(s.json());
	} else
		for (const auto& [line, v] : s.jsonStream()) objects.push_back(&v);
	std::vector<AsrWord> words;
	long k = 0;
	for (const JsonValue* v : objects) {
		const JsonValue* r = isObjectPtr(v) ? array(*voskBest(*v), "result") : nullptr;
		if (!r) continue;  // {"partial": …}, {"text": ""}
		for (const JsonValue& w : r->array) {
			const auto a = number(w.find("start")), b = number(w.find("end"));
			const std::string* t = string(w.find("word"));
			if (!t || !a || !b) throw Error(s.path(), 0, "result word " + std::to_string(k) + " needs word, start and end");
			words.push_back({*a, *b, *t, "", k++});
		}
	}
	if (words.empty()) throw Error(s.path(), 0, "Vosk output without word times: call SetWords(True) on the recogniser (only \"text\" or \"partial\" here)");
	return wordTranscript(words, s.path(), o);
}

bool voskObject(const JsonValue& v0) {
	if (v0.kind != JsonValue::Kind::Object) return false;
	const JsonValue& v = *voskBest(v0);
	if (const JsonValue* r = array(v, "result")) return allHave(*r, {"word", "start", "end"});
	return (v.find("partial") || v.find("text")) && v.object.size() <= 3;
}

// ---- Speechmatics: results[] of type word/punctuation with start_time/end_time and alternatives[0] ----
Transcript speechmatics(const TimingSample& s, const ReadOptions& o) {
	std::vector<AsrWord> words;
	long k = 0;
	for (const JsonValue& r : array(root(s), "results")->array) {
		const std::string* type = string(r.find("type"));
		if (!type || *type != "word") continue;
		const JsonValue* alts = array(r, "alternatives");
		const JsonValue* best = alts && !alts->array.empty() ? &alts->array[0] : nullptr;
		const std::string* t = best ? string(best->find("content")) : nullptr;
		const auto a = number(r.find("start_time")), b = number(r.find("end_time"));
		if (!t || !a || !b) throw Error(s.path(), 0, "results[" + std::to_string(k) + "] needs start_time, end_time and alternatives[0].content");
		words.push_back({*a, *b, *t, best ? speakerName(best->find("speaker")) : "", k++});
	}
	return wordTranscript(words, s.path(), o);
}

// ---- whisper.cpp -ojf: transcription[].tokens[] with offsets in ms; a token starting with a space begins
// a word, the others (punctuation, word pieces) join the word before; special tokens ([_BEG_], [_TT_150],
// <|endoftext|>) are left out. Without tokens (-oj): each segment's text over its offsets.
bool specialToken(const std::string& t) {
	const std::string_view v = trim(t);
	return (startsWith(v, "[_") && endsWith(v, "]")) || (startsWith(v, "<|") && endsWith(v, "|>"));
}

Transcript whispercpp(const TimingSample& s, const ReadOptions& o) {
	std::vector<AsrWord> words;
	long k = 0;
	bool sentences = false;
	for (const JsonValue& seg : array(root(s), "transcription")->array) {
		const JsonValue* off = object(seg, "offsets");
		const JsonValue* tokens = array(seg, "tokens");
		if (!tokens) {
			const auto a = off ? number(off->find("from")) : std::nullopt, b = off ? number(off->find("to")) : std::nullopt;
			const std::string* t = string(seg.find("text"));
			if (!a || !b || !t) throw Error(s.path(), 0, "transcription[" + std::to_string(k) + "] needs offsets.from, offsets.to (ms) and text");
			words.push_back({*a / 1000, *b / 1000, *t, "", k++});
			sentences = true;
			continue;
		}
		for (const JsonValue& tok : tokens->array) {
			const std::string* t = string(tok.find("text"));
			const JsonValue* to = object(tok, "offsets");
			const auto a = to ? number(to->find("from")) : std::nullopt, b = to ? number(to->find("to")) : std::nullopt;
			if (!t || !a || !b) throw Error(s.path(), 0, "a token of transcription[] needs text and offsets (ms)");
			if (specialToken(*t) || trim(*t).empty()) continue;
			const bool starts = !t->empty() && (*t)[0] == ' ';
			const bool punctuation = std::all_of(t->begin(), t->end(), [](char c) { return std::ispunct(static_cast<unsigned char>(c)) || c == ' '; });
			if (!starts && !words.empty()) {
				words.back().text += *t;  // a piece of the word before, or its punctuation
				if (!punctuation) words.back().end = std::max(words.back().end, *b / 1000);
				continue;
			}
			if (punctuation) continue;
			words.push_back({*a / 1000, *b / 1000, std::string(trim(*t)), "", k++});
		}
	}
	Transcript tr = wordTranscript(words, s.path(), o);
	tr.unit = "ms";
	if (sentences) tr.warnings.push_back("segments without tokens: each segment's words are spread over it (whisper-cli -ojf gives word times)");
	return tr;
}

// ---- ElevenLabs Scribe (speech-to-text): words[] of type word/spacing/audio_event, seconds -------------
Transcript scribe(const TimingSample& s, const ReadOptions& o) {
	std::vector<AsrWord> words;
	long k = 0, events = 0;
	for (const JsonValue& w : array(root(s), "words")->array) {
		const std::string* type = string(w.find("type"));
		const std::string* t = string(w.find("text"));
		const auto a = number(w.find("start")), b = number(w.find("end"));
		++k;
		if (type && *type == "spacing") continue;
		if (type && *type == "audio_event") {  // (laughter): a pause
			++events;
			continue;
		}
		if (!t || !a || !b) throw Error(s.path(), 0, "words[" + std::to_string(k - 1) + "] needs text, start and end");
		words.push_back({*a, *b, *t, speakerName(w.find("speaker_id")), k - 1});
	}
	Transcript tr = wordTranscript(words, s.path(), o);
	if (events) tr.warnings.push_back(std::to_string(events) + " audio event" + (events > 1 ? "s" : "") + " ((laughter)) not spoken: pauses");
	return tr;
}

// ---- Azure: batch synthesis word boundaries (ms) and batch transcription results (ticks) ---------------
Transcript azureBatchWords(const TimingSample& s, const ReadOptions& o) {
	std::vector<AsrWord> words;
	long k = 0;
	for (const JsonValue& w : s.json()->array) {
		const std::string* t = string(w.find("Text"));
		const auto a = number(w.find("AudioOffset")), d = number(w.find("Duration"));
		if (!t || !a || !d) throw Error(s.path(), 0, "[" + std::to_string(k) + "] needs Text, AudioOffset and Duration (milliseconds)");
		const bool punctuation = std::all_of(t->begin(), t->end(), [](char c) { return std::ispunct(static_cast<unsigned char>(c)) || c == ' '; });
		if (!punctuation) words.push_back({*a / 1000, (*a + *d) / 1000, *t, "", k});
		++k;
	}
	Transcript tr = wordTranscript(words, s.path(), o);
	tr.unit = "ms";
	return tr;
}

// ISO 8601 durations "PT1.23S", "PT1M2.5S".
std::optional<double> isoDuration(const std::string* s) {
	if (!s || !startsWith(*s, "PT")) return std::nullopt;
	double total = 0, v = 0;
	std::string num;
	for (std::size_t i = 2; i < s->size(); ++i) {
		const char c = (*s)[i];
		if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
			num += c;
			continue;
		}
		if (!parseDouble(num, v)) return std::nullopt;
		if (c == 'H') total += v * 3600;
		else if (c == 'M') total += v * 60;
		else if (c == 'S') total += v;
		else return std::nullopt;
		num.clear();
	}
	return num.empty() ? std::optional<double>(total) : std::nullopt;
}

Transcript azureRecognition(const TimingSample& s, const ReadOptions& o) {
	std::vector<AsrWord> words;
	long k = 0;
	for (const JsonValue& p : array(root(s), "recognizedPhrases")->array) {
		std::string speaker = speakerName(p.find("speaker"));
		if (const JsonValue* ch = p.find("channel"); ch && speaker.empty()) speaker = "channel " + speakerName(ch);
		const JsonValue* best = array(p, "nBest");
		const JsonValue* ws = best && !best->array.empty() ? array(best->array[0], "words") : nullptr;
		if (!ws) continue;
		for (const JsonValue& w : ws->array) {
			const std::string* t = string(w.find("word"));
			std::optional<double> a, d;
			if (const auto ticks = number(w.find("offsetInTicks"))) a = *ticks / 1e7;
			else a = isoDuration(string(w.find("offset")));
			if (const auto ticks = number(w.find("durationInTicks"))) d = *ticks / 1e7;
			else d = isoDuration(string(w.find("duration")));
			if (!t || !a || !d) throw Error(s.path(), 0, "a word of recognizedPhrases needs word, offsetInTicks and durationInTicks");
			words.push_back({*a, *a + *d, *t, speaker, k++});
		}
	}
	if (words.empty()) throw Error(s.path(), 0, "Azure recognition results without word times: ask for wordLevelTimestampsEnabled");
	Transcript tr = wordTranscript(words, s.path(), o);
	tr.unit = "100 ns";
	if (const auto d = isoDuration(string(root(s).find("duration")))) tr.statedDuration = *d;
	return tr;
}

// ---- YouTube's timed text JSON (json3, as youtube-dl/yt-dlp save it): events[] with tStartMs/dDurationMs and
// segs[] with utf8 and tOffsetMs (auto-captions: one word a seg) -----------------------------------------------
Transcript youtubeJson3(const TimingSample& s, const ReadOptions& o) {
	std::vector<AsrWord> words;
	long k = 0;
	for (const JsonValue& e : array(root(s), "events")->array) {
		const JsonValue* segs = array(e, "segs");
		const auto start = number(e.find("tStartMs"));
		if (!segs || !start) continue;  // window and style events carry no text
		const double dur = number(e.find("dDurationMs")).value_or(0);
		std::vector<std::pair<double, std::string>> pieces;
		for (const JsonValue& g : segs->array) {
			const std::string* t = string(g.find("utf8"));
			if (!t || trim(*t).empty()) continue;  // "\n" between lines
			pieces.emplace_back(*start + number(g.find("tOffsetMs")).value_or(0), std::string(trim(*t)));
		}
		for (std::size_t i = 0; i < pieces.size(); ++i) {
			const double end = i + 1 < pieces.size() ? pieces[i + 1].first : *start + dur;
			words.push_back({pieces[i].first / 1000, std::max(end, pieces[i].first) / 1000, pieces[i].second, "", k++});
		}
	}
	Transcript tr = wordTranscript(words, s.path(), o);
	tr.unit = "ms";
	// Rolling auto-captions repeat a line in an event that lasts as long as the next: only new words are here.
	for (std::size_t i = 0; i + 1 < tr.intervals.size(); ++i)
		if (tr.intervals[i].end > tr.intervals[i + 1].start) tr.intervals[i].end = std::max(tr.intervals[i].start, tr.intervals[i + 1].start);
	return tr;
}

// ---- IBM Watson Speech to Text: results[].alternatives[0].timestamps [["word", start, end], …] -------------
Transcript watson(const TimingSample& s, const ReadOptions& o) {
	std::vector<AsrWord> words;
	long k = 0;
	std::map<long, std::string> speakerAt;  // speaker_labels: {from, to, speaker}, keyed by the word's start in ms
	if (const JsonValue* labels = array(root(s), "speaker_labels"))
		for (const JsonValue& l : labels->array)
			if (const auto from = number(l.find("from"))) speakerAt[std::lround(*from * 1000)] = speakerName(l.find("speaker"));
	for (const JsonValue& r : array(root(s), "results")->array) {
		const JsonValue* alts = array(r, "alternatives");
		const JsonValue* ts = alts && !alts->array.empty() ? array(alts->array[0], "timestamps") : nullptr;
		if (!ts) continue;
		for (const JsonValue& t : ts->array) {
			const std::string* w = t.kind == JsonValue::Kind::Array && t.array.size() == 3 ? string(&t.array[0]) : nullptr;
			const auto a = w ? number(&t.array[1]) : std::nullopt, b = w ? number(&t.array[2]) : std::nullopt;
			if (!w || !a || !b) throw Error(s.path(), 0, "a timestamp of results[].alternatives[0] is not [\"word\", start, end]");
			const auto sp = speakerAt.find(std::lround(*a * 1000));
			words.push_back({*a, *b, *w, sp == speakerAt.end() ? "" : sp->second, k++});
		}
	}
	if (words.empty()) throw Error(s.path(), 0, "a Watson answer without word times: ask for timestamps=true");
	return wordTranscript(words, s.path(), o);
}

// ---- Azure Speech SDK detailed results: {"NBest": [{"Words": [{"Word", "Offset", "Duration"}]}], "Offset"} in
// 100-ns units (one result, or an array of them as a script collects them) ------------------------------------
Transcript azureDetailed(const TimingSample& s, const ReadOptions& o) {
	std::vector<const JsonValue*> results;
	if (s.json()->kind == JsonValue::Kind::Array)
		for (const JsonValue& r : s.json()->array) results.push_back(&r);
	else results.push_back(s.json());
	std::vector<AsrWord> words;
	long k = 0;
	for (const JsonValue* r : results) {
		const JsonValue* best = isObjectPtr(r) ? array(*r, "NBest") : nullptr;
		const JsonValue* ws = best && !best->array.empty() ? array(best->array[0], "Words") : nullptr;
		if (!ws) continue;
		for (const JsonValue& w : ws->array) {
			const std::string* t = string(w.find("Word"));
			const auto a = number(w.find("Offset")), d = number(w.find("Duration"));
			if (!t || !a || !d) throw Error(s.path(), 0, "a word of NBest[0].Words needs Word, Offset and Duration (100 ns)");
			words.push_back({*a / 1e7, (*a + *d) / 1e7, *t, "", k++});
		}
	}
	if (words.empty()) throw Error(s.path(), 0, "Azure results without word times: set the output format to detailed with word-level timestamps (RequestWordLevelTimestamps)");
	Transcript tr = wordTranscript(words, s.path(), o);
	tr.unit = "100 ns";
	return tr;
}


}  // namespace

void registerAsrTimingFormats(std::vector<TimingFormat>& v) {
	v.push_back(timing::makeFormat("assemblyai", "AssemblyAI transcript (GET /v2/transcript)", {".json"}, "words", "times in ms; audio_duration; language_code; speakers", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      if (!j || !array(*j, "words")) return false;
		                      return j->find("audio_duration") || j->find("acoustic_model") || j->find("language_model") || j->find("audio_url") || j->find("speech_model");
	                      },
	                      assemblyai));
	v.push_back(timing::makeFormat("amazon", "Amazon Transcribe job output (results.items[])", {".json"}, "words", "times in s (strings); speakers (speaker_label)", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      const JsonValue* r = j ? object(*j, "results") : nullptr;
		                      const JsonValue* items = r ? array(*r, "items") : nullptr;
		                      return items && allHave(*items, {"type", "alternatives"});
	                      },
	                      amazon));
	v.push_back(timing::makeFormat("google-stt", "Google Cloud Speech-to-Text v1/v2 (results[].alternatives[].words[])", {".json"}, "words",
	                      "times as \"1.200s\" strings; languageCode; speakerTag", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      if (j && object(*j, "response")) j = object(*j, "response");
		                      const JsonValue* r = j ? array(*j, "results") : nullptr;
		                      if (!r || !allHave(*r, {"alternatives"})) return false;
		                      for (const JsonValue& x : r->array)
			                      if (const JsonValue* a = array(x, "alternatives"); a && !a->array.empty() && array(a->array[0], "words")) {
				                      const JsonValue& w = *array(a->array[0], "words");
				                      return anyHave(w, "startTime") || anyHave(w, "endTime") || anyHave(w, "startOffset") || anyHave(w, "endOffset");
			                      }
		                      return anyHave(*r, "resultEndTime") || anyHave(*r, "resultEndOffset");
	                      },
	                      googleStt));
	v.push_back(timing::makeFormat("revai", "Rev.ai transcript (monologues[].elements[])", {".json"}, "words", "times in s; speakers (monologues)", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      const JsonValue* m = j ? array(*j, "monologues") : nullptr;
		                      return m && allHave(*m, {"elements"});
	                      },
	                      revai));
	v.push_back(timing::makeFormat("vosk", "Vosk recogniser results ({\"result\": [{word, start, end, conf}]}, one or a stream)", {".json"}, "words", "times in s", 3,
	                      [](const TimingSample& s) {
		                      bool words = false;
		                      auto one = [&](const JsonValue& x) {
			                      if (!voskObject(x)) return false;
			                      words |= array(*voskBest(x), "result") != nullptr;
			                      return true;
		                      };
		                      if (const JsonValue* j = s.json()) {
			                      if (j->kind == JsonValue::Kind::Array) return !j->array.empty() && std::all_of(j->array.begin(), j->array.end(), one) && words;
			                      return one(*j) && words;
		                      }
		                      const auto& st = s.jsonStream();
		                      return !st.empty() && std::all_of(st.begin(), st.end(), [&](const auto& p) { return one(p.second); });
	                      },
	                      vosk));
	v.push_back(timing::makeFormat("speechmatics", "Speechmatics json-v2 transcript (results[] of words)", {".json"}, "words", "times in s; language; speakers", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      const JsonValue* r = j ? array(*j, "results") : nullptr;
		                      return r && allHave(*r, {"type", "start_time", "end_time"}) && anyHave(*r, "alternatives");
	                      },
	                      speechmatics));
	v.push_back(timing::makeFormat("whispercpp", "whisper.cpp JSON (whisper-cli -oj / -ojf: transcription[], offsets in ms)", {".json"}, "words (tokens) or segments",
	                      "times in ms (offsets); result.language", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      const JsonValue* t = j ? array(*j, "transcription") : nullptr;
		                      return t && allHave(*t, {"offsets"});
	                      },
	                      whispercpp));
	v.push_back(timing::makeFormat("scribe", "ElevenLabs Speech-to-Text (Scribe) answer", {".json"}, "words", "times in s; language_code; speaker_id; audio events as pauses", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      const JsonValue* w = j ? array(*j, "words") : nullptr;
		                      if (!w || !allHave(*w, {"type", "start", "end"})) return false;
		                      return std::all_of(w->array.begin(), w->array.end(), [](const JsonValue& e) {
			                      const std::string* t = string(e.find("type"));
			                      return t && (*t == "word" || *t == "spacing" || *t == "audio_event");
		                      });
	                      },
	                      scribe));
	v.push_back(timing::makeFormat("azure-batch-words", "Azure batch synthesis word boundaries ([n].word.json, milliseconds)", {".json"}, "words", "times in ms (AudioOffset, Duration)", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = s.json();
		                      if (!j || !allHave(*j, {"Text", "AudioOffset", "Duration"}) || anyHave(*j, "BoundaryType")) return false;
		                      return std::all_of(j->array.begin(), j->array.end(), [](const JsonValue& e) {
			                      return e.find("AudioOffset")->kind == JsonValue::Kind::Number && e.find("Duration")->kind == JsonValue::Kind::Number;
		                      });
	                      },
	                      azureBatchWords));
	v.push_back(timing::makeFormat("youtube-json3", "YouTube timed text JSON (json3: events[].segs[])", {".json"}, "words", "times in ms (tStartMs, tOffsetMs)", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      const JsonValue* e = j ? array(*j, "events") : nullptr;
		                      return e && anyHave(*e, "tStartMs");
	                      },
	                      youtubeJson3));
	v.push_back(timing::makeFormat("watson", "IBM Watson Speech to Text (results[].alternatives[].timestamps)", {".json"}, "words", "times in s; speaker_labels", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      const JsonValue* r = j ? array(*j, "results") : nullptr;
		                      if (!r || r->array.empty()) return false;
		                      for (const JsonValue& x : r->array)
			                      if (const JsonValue* a = array(x, "alternatives"); a && anyHave(*a, "timestamps")) return true;
		                      return false;
	                      },
	                      watson));
	v.push_back(timing::makeFormat("azure-detailed", "Azure Speech SDK detailed recognition results (NBest[].Words[], 100 ns)", {".json"}, "words", "times in 100 ns (Offset, Duration)", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = s.json();
		                      if (!j) return false;
		                      if (j->kind == JsonValue::Kind::Array) return anyHave(*j, "NBest");
		                      return j->kind == JsonValue::Kind::Object && array(*j, "NBest");
	                      },
	                      azureDetailed));
	v.push_back(timing::makeFormat("azure-stt", "Azure Speech batch transcription (recognizedPhrases[])", {".json"}, "words", "times in 100 ns (offsetInTicks); speakers; channels", 3,
	                      [](const TimingSample& s) {
		                      const JsonValue* j = timing::jsonObject(s);
		                      return j && array(*j, "recognizedPhrases");
	                      },
	                      azureRecognition));
}

}  // namespace talkhead
