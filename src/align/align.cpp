// SPDX-License-Identifier: GPL-3.0-or-later
#include "align/align.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "align/features.h"
#include "base/error.h"
#include "base/text.h"
#include "phonetics/espeak.h"
#include "phonetics/language.h"

namespace talkhead {

using align::FeatureMatrix;
using align::FeatureOptions;

namespace {

const Ticks kMs(kTicksPerSecond / 1000);

std::string fixed(double v, int decimals) {
	char buf[64];
	std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
	return buf;
}

double percentile(std::vector<float> v, double p) {
	if (v.empty()) return 0;
	const std::size_t k = std::min(v.size() - 1, std::size_t(p * double(v.size() - 1) + 0.5));
	std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
	return v[k];
}

double median(std::vector<double> v) {
	std::sort(v.begin(), v.end());
	const std::size_t n = v.size();
	return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Frame k's centre in seconds, and back.
double frameCentre(double k, const FeatureOptions& f) { return k * f.hopSeconds + f.windowSeconds / 2; }
double framePosition(double seconds, const FeatureOptions& f) { return (seconds - f.windowSeconds / 2) / f.hopSeconds; }

// The voice-activity decision over the input's frames.
struct Activity {
	std::vector<bool> speech;
	int first = -1, last = -1;  // first and last speech frame
};

Activity detectSpeech(const std::vector<float>& levels, const AlignTuning& t) {
	if (levels.empty()) throw Error("no speech in the audio: it is shorter than one 25 ms frame");
	const double peak = percentile(levels, 0.99), floor = percentile(levels, 0.05);
	if (peak < t.silentBelowDb)
		throw Error("no speech in the audio: it is silent (peak level " + fixed(peak, 0) + " dBFS)");
	if (peak - floor < t.minRangeDb)
		throw Error("no speech in the audio: its level hardly varies (" + fixed(peak - floor, 1) + " dB between quiet and loud frames; steady noise or a tone?)");
	const double threshold = floor + std::max(6.0, t.vadFraction * (peak - floor));
	Activity a;
	a.speech.resize(levels.size());
	for (std::size_t k = 0; k < levels.size(); ++k) a.speech[k] = levels[k] > threshold;
	// Runs shorter than 50 ms are not speech; gaps shorter than 100 ms inside speech are.
	const auto fillRuns = [&](bool value, int shorter) {
		std::size_t k = 0;
		while (k < a.speech.size()) {
			if (a.speech[k] != value) {
				++k;
				continue;
			}
			std::size_t e = k;
			while (e < a.speech.size() && a.speech[e] == value) ++e;
			const bool inner = k > 0 && e < a.speech.size();
			if (int(e - k) < shorter && (value || inner))
				for (std::size_t i = k; i < e; ++i) a.speech[i] = !value;
			k = e;
		}
	};
	fillRuns(true, 5);
	fillRuns(false, 10);
	// An isolated blip under 100 ms before or after everything else (a click, a breath) is not the
	// utterance's edge.
	for (int pass = 0; pass < 2; ++pass) {
		std::vector<std::pair<std::size_t, std::size_t>> runs;
		for (std::size_t k = 0; k < a.speech.size(); ++k)
			if (a.speech[k] && (k == 0 || !a.speech[k - 1])) runs.emplace_back(k, k);
			else if (a.speech[k]) runs.back().second = k;
		if (runs.size() < 2) break;
		for (const auto& r : {runs.front(), runs.back()})
			if (r.second - r.first + 1 < 10)
				for (std::size_t k = r.first; k <= r.second; ++k) a.speech[k] = false;
	}
	// Hysteresis: each stretch of speech grows outwards over frames above a lower threshold (weak onsets
	// and fading ends), by at most 150 ms.
	const double low = floor + std::max(6.0, t.vadLowFraction * (peak - floor));
	{
		std::vector<bool> grown = a.speech;
		for (std::size_t k = 0; k < a.speech.size(); ++k) {
			if (!a.speech[k]) continue;
			if (k == 0 || !a.speech[k - 1])
				for (std::size_t d = 1; d <= 15 && d <= k && levels[k - d] > low; ++d) grown[k - d] = true;
			if (k + 1 == a.speech.size() || !a.speech[k + 1])
				for (std::size_t d = 1; d <= 15 && k + d < a.speech.size() && levels[k + d] > low; ++d) grown[k + d] = true;
		}
		a.speech = std::move(grown);
	}
	for (std::size_t k = 0; k < a.speech.size(); ++k)
		if (a.speech[k]) {
			if (a.first < 0) a.first = int(k);
			a.last = int(k);
		}
	if (a.first < 0) throw Error("no speech in the audio: no stretch of 50 ms stands out from the background");
	return a;
}

// A reference rendition of the text by espeak-ng.
struct Rendition {
	int sampleRate = 0;
	std::vector<float> samples;
	Transcript phones;  // contiguous from 0 to the end of samples; word-initial closures belong to the stop
	struct Word {
		std::string text;
		std::size_t firstPhone, lastPhone;  // indices into phones.intervals
	};
	std::vector<Word> words;
	double speechSeconds = 0;  // first phone start to last phone end
};

Rendition renderText(const std::string& text, const std::string& voice, int rate, const AlignTuning& t) {
	const Speech sp = espeakSpeak(text, voice, rate, -1, t.wordGap10ms);
	Rendition r;
	r.sampleRate = sp.sampleRate;
	const std::size_t pad = std::size_t(t.padSeconds * sp.sampleRate);
	const Ticks padTicks(std::int64_t(pad) * (kTicksPerSecond / sp.sampleRate));
	r.samples.assign(pad, 0.f);
	for (short v : sp.pcm) r.samples.push_back(float(v) / 32768.f);
	r.samples.insert(r.samples.end(), pad, 0.f);
	const Transcript ph = phonesWithClosures(sp);
	r.phones = ph;
	r.phones.intervals.clear();
	r.phones.intervals.push_back({Ticks(0), padTicks, "", 0});
	for (Interval i : ph.intervals) {
		i.start += padTicks;
		i.end += padTicks;
		r.phones.intervals.push_back(i);
	}
	r.phones.intervals.push_back({r.phones.intervals.back().end, r.phones.intervals.back().end + padTicks, "", 0});
	Ticks first{-1}, last{0};
	for (const Interval& i : r.phones.intervals)
		if (!i.label.empty()) {
			if (first < Ticks(0)) first = i.start;
			last = i.end;
		}
	r.speechSeconds = toSeconds(last - first);
	for (const Interval& w : sp.words.intervals) {
		const Ticks a = w.start + padTicks, b = w.end + padTicks;
		std::size_t f = r.phones.intervals.size(), l = 0;
		for (std::size_t k = 0; k < r.phones.intervals.size(); ++k) {
			const Interval& p = r.phones.intervals[k];
			if (p.label.empty() || p.end <= a || p.start >= b) continue;
			f = std::min(f, k);
			l = std::max(l, k);
		}
		if (f <= l) r.words.push_back({w.label, f, l});
	}
	return r;
}

std::vector<float> monoOf(const AudioClip& clip) {
	const std::size_t frames = clip.frameCount();
	std::vector<float> mono(frames);
	const int ch = std::max(1, clip.channels);
	for (std::size_t k = 0; k < frames; ++k) {
		float s = 0;
		for (int c = 0; c < ch; ++c) s += clip.samples[k * std::size_t(ch) + std::size_t(c)];
		mono[k] = s / float(ch);
	}
	return mono;
}

// The input's background, to give the renditions the same: its level and non-speech samples.
struct Channel {
	double speechLevel = 0;    // dBFS, 90th percentile of the speech frames' levels
	int sampleRate = 0;
	std::vector<float> noise;  // the non-speech stretches, joined
};

Channel channelOf(const std::vector<float>& mono, int sampleRate, const std::vector<float>& levels, const Activity& a, const FeatureOptions& fo) {
	Channel c;
	c.sampleRate = sampleRate;
	std::vector<float> sl;
	for (std::size_t k = 0; k < levels.size(); ++k)
		if (a.speech[k]) sl.push_back(levels[k]);
	c.speechLevel = percentile(sl, 0.9);
	const std::size_t hop = std::size_t(std::lround(fo.hopSeconds * sampleRate));
	// Non-speech frames at least 3 frames from speech (no speech edges in the noise).
	for (std::size_t k = 0; k < levels.size(); ++k) {
		bool quiet = true;
		for (std::size_t d = k >= 3 ? k - 3 : 0; d <= k + 3 && d < levels.size(); ++d) quiet = quiet && !a.speech[d];
		if (!quiet) continue;
		const std::size_t s0 = k * hop;
		for (std::size_t i = s0; i < s0 + hop && i < mono.size(); ++i) c.noise.push_back(mono[i]);
	}
	return c;
}

// Scales the rendition to the input's speech level and adds the input's background (resampled linearly to
// the rendition's rate, looped), so that pauses look alike on both sides and the signal-to-noise ratios
// agree.
void matchChannel(Rendition& r, const Channel& c, const FeatureOptions& fo) {
	const std::vector<float> levels = align::frameLevels(r.samples, r.sampleRate, fo);
	std::vector<float> sl;
	for (std::size_t k = 0, p = 0; k < levels.size(); ++k) {
		const Ticks centre = ticksFromSeconds(frameCentre(double(k), fo));
		while (p + 1 < r.phones.intervals.size() && r.phones.intervals[p].end <= centre) ++p;
		if (!r.phones.intervals[p].label.empty()) sl.push_back(levels[k]);
	}
	const float gain = float(std::pow(10.0, (c.speechLevel - percentile(sl, 0.9)) / 20.0));
	for (float& v : r.samples) v *= gain;
	const double minNoise = 0.2;  // seconds of background needed
	if (double(c.noise.size()) < minNoise * c.sampleRate) return;
	const double step = double(c.sampleRate) / double(r.sampleRate);
	const double len = double(c.noise.size() - 1);
	double pos = 0;
	for (float& v : r.samples) {
		const std::size_t i = std::size_t(pos);
		const double f = pos - double(i);
		v += float(c.noise[i] + f * (c.noise[i + 1] - c.noise[i]));
		pos += step;
		if (pos >= len) pos -= len;
	}
}

// One rendition aligned with the input: phone boundaries (seconds, input time) and match costs.
struct RenditionResult {
	std::vector<double> boundaries;  // phones.intervals.size() + 1
	double rank = 0;                 // mean rank of the path's frame among the rendition's (see below)
	std::vector<double> wordRank;    // the same per word
};

RenditionResult alignRendition(const FeatureMatrix& input, const Activity& activity, const Rendition& r, const FeatureOptions& fo,
                               const AlignTuning& t) {
	FeatureMatrix ref = align::mfcc(r.samples, r.sampleRate, fo);
	const int m = ref.frames, n = input.frames;
	if (m == 0) throw Error("the text's rendition is too short to align");
	std::vector<bool> pauseB(static_cast<std::size_t>(m)), speechB(static_cast<std::size_t>(m));
	std::vector<int> phoneOf(std::size_t(m), -1);
	{
		std::size_t p = 0;
		for (int j = 0; j < m; ++j) {
			const Ticks c = ticksFromSeconds(frameCentre(j, fo));
			while (p + 1 < r.phones.intervals.size() && r.phones.intervals[p].end <= c) ++p;
			pauseB[std::size_t(j)] = r.phones.intervals[p].label.empty();
			speechB[std::size_t(j)] = !pauseB[std::size_t(j)];
			phoneOf[std::size_t(j)] = int(p);
		}
	}
	align::normalise(ref, speechB);
	std::vector<bool> pauseA;
	if (t.inputPauses) {
		pauseA.resize(std::size_t(n));
		for (int i = 0; i < n; ++i) pauseA[std::size_t(i)] = !activity.speech[std::size_t(i)];
	}
	align::DtwOptions dopt;
	dopt.maxSlope = t.maxSlope;
	if (double(n) * double(m) > 4e6) dopt.band = std::max(150, int(0.3 * std::max(n, m)));
	const align::DtwResult d = align::dtw(input, ref, pauseA, pauseB, dopt);
	RenditionResult out;
	const align::PathMap map(d.path, m);
	for (std::size_t k = 0; k <= r.phones.intervals.size(); ++k) {
		const Ticks tb = k < r.phones.intervals.size() ? r.phones.intervals[k].start : r.phones.intervals.back().end;
		const double x = map(framePosition(toSeconds(tb), fo));
		out.boundaries.push_back(frameCentre(x, fo));
	}
	// Match quality: for each path cell on speech (both sides), the fraction of the rendition's speech
	// frames that lie closer to the input frame than the one the path chose (static cepstra only: deltas
	// are noisy across speakers). Near 0 when the text fits; towards 0.5 when the path is arbitrary.
	std::vector<int> jb;
	for (int j = 0; j < m; ++j)
		if (speechB[std::size_t(j)]) jb.push_back(j);
	const std::size_t stride = std::max<std::size_t>(1, jb.size() / 100);
	const int dims = std::min(input.dims, fo.cepstra);
	const auto dist = [&](int i, int j) {
		float q = 0;
		for (int k = 0; k < dims; ++k) {
			const float e = input.row(i)[k] - ref.row(j)[k];
			q += e * e;
		}
		return q;
	};
	std::vector<int> wordOfPhone(r.phones.intervals.size(), -1);
	for (std::size_t w = 0; w < r.words.size(); ++w)
		for (std::size_t p = r.words[w].firstPhone; p <= r.words[w].lastPhone; ++p) wordOfPhone[p] = int(w);
	std::vector<double> wsum(r.words.size(), 0.0);
	std::vector<long> wcount(r.words.size(), 0);
	double sum = 0;
	long count = 0;
	for (const auto& [i, j] : d.path) {
		if (pauseB[std::size_t(j)] || !activity.speech[std::size_t(i)]) continue;
		const float c = dist(i, j);
		long closer = 0, all = 0;
		for (std::size_t k = 0; k < jb.size(); k += stride, ++all) closer += dist(i, jb[k]) < c;
		const double rank = double(closer) / double(std::max(1L, all));
		sum += rank;
		++count;
		const int w = wordOfPhone[std::size_t(phoneOf[std::size_t(j)])];
		if (w >= 0) wsum[std::size_t(w)] += rank, ++wcount[std::size_t(w)];
	}
	out.rank = count ? sum / double(count) : 0.5;
	for (std::size_t w = 0; w < r.words.size(); ++w) out.wordRank.push_back(wcount[w] ? wsum[w] / double(wcount[w]) : out.rank);
	return out;
}

double confidenceOf(double rank, const AlignTuning& t) { return std::clamp((t.rankMismatch - rank) / (t.rankMismatch - t.rankMatch), 0.0, 1.0); }

std::vector<std::string> defaultVoices(const std::string& tag) {
	const std::string v = espeakVoiceFor(tag);
	return {v, v + "+m3", v + "+f2"};
}

bool samePhones(const Rendition& a, const Rendition& b) {
	if (a.phones.intervals.size() != b.phones.intervals.size() || a.words.size() != b.words.size()) return false;
	for (std::size_t k = 0; k < a.phones.intervals.size(); ++k)
		if (a.phones.intervals[k].label != b.phones.intervals[k].label) return false;
	for (std::size_t k = 0; k < a.words.size(); ++k)
		if (a.words[k].firstPhone != b.words[k].firstPhone || a.words[k].lastPhone != b.words[k].lastPhone) return false;
	return true;
}

// The phone boundaries: the median over the renditions, then the utterance's edges snapped to the voice
// activity, phones in order and of a minimum length, the ends, and short pauses given to their neighbours.
std::vector<Ticks> phoneBoundaries(const Rendition& ref, const std::vector<RenditionResult>& results, const Activity& activity, const FeatureOptions& fo,
                                   const AlignTuning& t, Ticks audioDuration) {
	const double duration = toSeconds(audioDuration);
	const double vadStart = frameCentre(activity.first, fo), vadEnd = frameCentre(activity.last, fo);
	const std::size_t P = ref.phones.intervals.size();
	std::vector<double> b(P + 1);
	for (std::size_t k = 0; k <= P; ++k) {
		std::vector<double> v;
		for (const auto& r : results) v.push_back(r.boundaries[k]);
		b[k] = std::clamp(median(v), 0.0, duration);
	}
	b[0] = 0;
	b[P] = duration;
	if (t.snapEdgesSeconds > 0) {
		// The utterance's edges: where the voice-activity measure puts them, unless the warping disagrees by
		// more than snapEdgesSeconds (e.g. a noise burst before the speech).
		std::size_t f = 0, l = P;
		while (f < P && ref.phones.intervals[f].label.empty()) ++f;
		while (l > 0 && ref.phones.intervals[l - 1].label.empty()) --l;
		if (f < l) {
			if (std::abs(b[f] - vadStart) <= t.snapEdgesSeconds) b[f] = vadStart;
			if (std::abs(b[l] - vadEnd) <= t.snapEdgesSeconds) b[l] = vadEnd;
		}
	}
	const double minPhone = t.minPhoneSeconds;
	for (std::size_t k = 1; k <= P; ++k) b[k] = std::max(b[k], b[k - 1] + (ref.phones.intervals[k - 1].label.empty() ? 0.0 : minPhone));
	b[P] = std::max(b[P], duration);
	for (std::size_t k = P; k-- > 1;) b[k] = std::min(b[k], b[k + 1] - (ref.phones.intervals[k].label.empty() ? 0.0 : minPhone));
	for (std::size_t k = 1; k < P; ++k) b[k] = std::max(b[k], 0.0);
	// Short pauses (a rendition's word gap that the speaker did not make) go to their neighbours.
	std::vector<Ticks> bt(P + 1);
	for (std::size_t k = 0; k <= P; ++k) bt[k] = ticksFromSeconds(b[k]);
	bt[P] = audioDuration;
	for (std::size_t k = 1; k + 1 < P; ++k) {
		const Interval& p = ref.phones.intervals[k];
		if (!p.label.empty() || bt[k + 1] - bt[k] >= ticksFromSeconds(t.minPauseSeconds)) continue;
		const Ticks mid = bt[k] + (bt[k + 1] - bt[k]) / 2;
		bt[k] = bt[k + 1] = mid;
	}
	return bt;
}

// The speaking rate (words per minute) at which the first voice's rendition lasts as long as the input's speech.
int matchedRate(const std::string& text, const std::string& voice, double inputSpeech, const AlignTuning& t) {
	int rate = 175;
	for (int it = 0; it <= t.rateIterations; ++it) {
		const Rendition probe = renderText(text, voice, rate, t);
		const double next = rate * probe.speechSeconds / std::max(inputSpeech, 0.05);
		const int clamped = int(std::lround(std::clamp(next, 80.0, 450.0)));
		if (clamped == rate) break;
		rate = clamped;
	}
	return rate;
}

// Words: between their first phone's start and last phone's end, pauses between them, each with its confidence.
void addWords(Alignment& al, const Rendition& ref, const std::vector<RenditionResult>& results, const std::vector<Ticks>& bt, const AlignTuning& t,
              Ticks duration) {
	Ticks at{0};
	for (std::size_t w = 0; w < ref.words.size(); ++w) {
		const Ticks s = std::max(at, bt[ref.words[w].firstPhone]), e = bt[ref.words[w].lastPhone + 1];
		if (e <= s) continue;
		if (s > at) al.words.intervals.push_back({at, s, "", 0});
		al.words.intervals.push_back({s, e, ref.words[w].text, long(w + 1)});
		std::vector<double> v;
		for (const auto& r : results) v.push_back(r.wordRank[w]);
		al.wordList.push_back({s, e, ref.words[w].text, confidenceOf(median(v), t)});
		at = e;
	}
	if (at < duration) al.words.intervals.push_back({at, duration, "", 0});
}

}  // namespace

VoiceActivity detectVoiceActivity(const std::vector<float>& levels, const AlignTuning& tuning) {
	Activity a = detectSpeech(levels, tuning);
	return {std::move(a.speech), a.first, a.last};
}

Alignment alignSpeech(const AudioClip& audio, const std::string& text, const AlignOptions& o) {
	if (trim(text).empty()) throw Error("the text is empty: nothing to align");
	if (audio.sampleRate <= 0 || audio.frameCount() == 0) throw Error("no speech in the audio: it is empty");
	const Language& lang = Language::get(o.languageTag);
	const AlignTuning& t = o.tuning;
	FeatureOptions fo;
	fo.deltaDeltas = t.deltaDeltas;
	// The input: features, normalised over its speech frames.
	const std::vector<float> mono = monoOf(audio);
	const std::vector<float> levels = align::frameLevels(mono, audio.sampleRate, fo);
	const Activity activity = detectSpeech(levels, t);
	const Channel channel = channelOf(mono, audio.sampleRate, levels, activity, fo);
	FeatureMatrix input = align::mfcc(mono, audio.sampleRate, fo);
	align::normalise(input, activity.speech);
	const double inputSpeech = frameCentre(activity.last, fo) - frameCentre(activity.first, fo) + fo.hopSeconds;
	// The renditions, at the input's speaking rate.
	std::vector<std::string> voices = o.voices;
	if (voices.empty()) {
		voices = defaultVoices(lang.tag());
		voices.resize(std::size_t(std::clamp(t.renditions, 1, int(voices.size()))));
	}
	const int rate = t.matchRate ? matchedRate(text, voices[0], inputSpeech, t) : 175;
	std::vector<Rendition> renditions;
	std::vector<RenditionResult> results;
	for (const std::string& v : voices) {
		Rendition r = renderText(text, v, rate, t);
		if (t.matchChannel) matchChannel(r, channel, fo);
		if (!renditions.empty() && !samePhones(renditions[0], r)) continue;  // another phone sequence: not comparable
		results.push_back(alignRendition(input, activity, r, fo, t));
		renditions.push_back(std::move(r));
	}
	const Rendition& ref = renditions[0];
	if (ref.words.empty()) throw Error("nothing to align: the text has no speakable words");
	const double duration = toSeconds(audio.duration());
	const std::size_t P = ref.phones.intervals.size();
	const std::vector<Ticks> bt = phoneBoundaries(ref, results, activity, fo, t, audio.duration());
	const double vadStart = frameCentre(activity.first, fo), vadEnd = frameCentre(activity.last, fo);
	Transcript espeakPhonesOut;
	espeakPhonesOut.path = "alignment";
	for (std::size_t k = 0; k < P; ++k)
		if (bt[k + 1] > bt[k]) espeakPhonesOut.intervals.push_back({bt[k], bt[k + 1], ref.phones.intervals[k].label, long(k + 1)});
	// Canonical phones of the language (espeak-ng's IPA names mapped as `talkhead say` maps them).
	Alignment al;
	al.phones.path = "alignment";
	al.phones.format = "textgrid";
	al.phones.level = LabelLevel::Phone;
	for (const PhoneSegment& s : phoneSegments(espeakPhonesOut, lang, UnknownPhone::Nearest, Notation::Espeak)) {
		const std::string label = s.phone == "_" ? "" : s.phone;
		if (label.empty() && !al.phones.intervals.empty() && al.phones.intervals.back().label.empty()) al.phones.intervals.back().end = s.end;
		else al.phones.intervals.push_back({s.start, s.end, label, 0});
	}
	// Words: between their first phone's start and last phone's end.
	al.words.path = "alignment";
	al.words.format = "textgrid";
	al.words.level = LabelLevel::Word;
	double rank = 0;
	for (const auto& r : results) rank += r.rank;
	al.confidence = confidenceOf(rank / double(results.size()), t);
	addWords(al, ref, results, bt, t, audio.duration());
	al.speechStart = ticksFromSeconds(std::max(0.0, vadStart));
	al.speechEnd = ticksFromSeconds(std::min(duration, vadEnd));
	al.renditions = int(results.size());
	if (al.confidence < o.mismatchBelow) throw Error("the text does not match the audio (confidence " + fixed(al.confidence, 2) + ")");
	if (al.confidence < o.doubtfulBelow)
		al.warnings.push_back("the text may not match the audio (confidence " + fixed(al.confidence, 2) + "): check the alignment");
	return al;
}

std::vector<RenderedWord> renderedWords(const std::string& text, const AlignOptions& o, int rate) {
	std::vector<RenderedWord> out;
	if (trim(text).empty()) return out;
	const Language& lang = Language::get(o.languageTag);
	const Rendition r = renderText(text, o.voices.empty() ? defaultVoices(lang.tag())[0] : o.voices[0], rate, o.tuning);
	Ticks first{-1};
	for (const Rendition::Word& w : r.words) {
		const Ticks a = r.phones.intervals[w.firstPhone].start, b = r.phones.intervals[w.lastPhone].end;
		if (first < Ticks(0)) first = a;
		out.push_back({w.text, a - first, b - first});
	}
	return out;
}

Alignment alignSpeechFile(const std::string& path, const std::string& text, const AlignOptions& options) {
	const AudioClip clip = decodeAudio(path, 16000);
	try {
		return alignSpeech(clip, text, options);
	} catch (const Error& e) {
		throw Error(path, 0, e.what());
	}
}

std::string alignmentTextGrid(const Alignment& al, Ticks duration) {
	std::ostringstream o;
	const auto sec = [](Ticks t) { return fixed(toSeconds(t), 6); };
	const auto quoted = [](const std::string& s) {
		std::string q = "\"";
		for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
		return q + "\"";
	};
	Ticks end = duration;
	for (const Transcript* t : {&al.words, &al.phones})
		if (!t->intervals.empty()) end = std::max(end, t->intervals.back().end);
	o << "File type = \"ooTextFile\"\nObject class = \"TextGrid\"\n\nxmin = 0\nxmax = " << sec(end) << "\ntiers? <exists>\nsize = 2\nitem []:\n";
	int n = 0;
	for (const auto& [name, tier] : {std::pair<const char*, const Transcript*>{"words", &al.words}, {"phones", &al.phones}}) {
		const std::vector<Interval> iv = withPauses(tier->intervals, Ticks(0), end);  // contiguous from 0 to the end
		o << "    item [" << ++n << "]:\n        class = \"IntervalTier\"\n        name = \"" << name << "\"\n        xmin = 0\n        xmax = " << sec(end)
		  << "\n        intervals: size = " << iv.size() << "\n";
		for (std::size_t i = 0; i < iv.size(); ++i)
			o << "        intervals [" << i + 1 << "]:\n            xmin = " << sec(iv[i].start) << "\n            xmax = " << sec(iv[i].end)
			  << "\n            text = " << quoted(iv[i].label) << "\n";
	}
	return o.str();
}

std::string alignmentSummary(const Alignment& al) {
	std::size_t phones = 0;
	for (const Interval& i : al.phones.intervals) phones += !i.label.empty();
	std::string s = std::to_string(al.wordList.size()) + " words, " + std::to_string(phones) + " phones, speech " + fixed(toSeconds(al.speechStart), 2) +
	                "–" + fixed(toSeconds(al.speechEnd), 2) + " s, confidence " + fixed(al.confidence, 2);
	const AlignedWord* low = nullptr;
	for (const AlignedWord& w : al.wordList)
		if (!low || w.confidence < low->confidence) low = &w;
	if (low && al.wordList.size() > 1) s += " (lowest: '" + low->text + "' " + fixed(low->confidence, 2) + ")";
	return s;
}

Transcript alignCues(const Transcript& cues, const AudioClip& audio, const std::string& languageTag, const std::string& audioName) {
	Transcript out;
	out.path = cues.path;
	out.format = cues.format;
	out.level = LabelLevel::Phone;
	out.tier = cues.tier;
	for (const std::string& w : cues.warnings)
		if (w.find("spread by espeak-ng's durations") == std::string::npos) out.warnings.push_back(w);  // they are aligned now
	AlignOptions o;
	o.languageTag = languageTag;
	const std::size_t ch = std::size_t(std::max(1, audio.channels)), frames = audio.frameCount();
	for (const Interval& cue : cues.intervals) {
		if (isPauseLabel(cue.label)) {
			out.intervals.push_back({cue.start, cue.end, "", cue.line});
			continue;
		}
		const std::size_t a = std::min(frames, std::size_t(std::llround(toSeconds(cue.start) * audio.sampleRate)));
		const std::size_t b = std::min(frames, std::size_t(std::llround(toSeconds(cue.end) * audio.sampleRate)));
		if (b <= a) throw Error(audioName, 0, "the cue at line " + std::to_string(cue.line) + " of " + cues.path + " lies past the audio's end");
		AudioClip slice;
		slice.sampleRate = audio.sampleRate;
		slice.channels = audio.channels;
		slice.samples.assign(audio.samples.begin() + std::ptrdiff_t(a * ch), audio.samples.begin() + std::ptrdiff_t(b * ch));
		Alignment al;
		try {
			al = alignSpeech(slice, cue.label, o);
		} catch (const Error& e) {
			throw Error(cues.path, cue.line, std::string("aligning the cue '") + safeQuote(cue.label) + "' to " + audioName + ": " + e.what());
		}
		for (const std::string& w : al.warnings) out.warnings.push_back("cue at line " + std::to_string(cue.line) + ": " + w);
		for (Interval p : al.phones.intervals) {
			p.start = std::min(cue.end, cue.start + p.start);
			p.end = std::min(cue.end, cue.start + p.end);
			p.line = cue.line;
			if (p.end > p.start) out.intervals.push_back(p);
		}
	}
	return out;
}

}  // namespace talkhead
