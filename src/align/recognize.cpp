// SPDX-License-Identifier: GPL-3.0-or-later
#include "align/recognize.h"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <cmath>
#include <numeric>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "align/align.h"
#include "align/features.h"
#include "align/sphinx_module.h"
#include "base/error.h"
#include "base/plugin.h"
#include "base/text.h"
#include "phonetics/language.h"

namespace talkhead {

namespace {

constexpr int kSphinxRate = 16000;   // what the acoustic model was trained on
constexpr int kLevelHop = 160;       // 10 ms: the voice activity's and the decoder's frame
constexpr int kLevelWindow = 400;    // 25 ms
constexpr double kFrameSeconds = 0.01;

const SphinxModule& sphinxModule() {
	static const SphinxModule* m = [] {
		try {
			return static_cast<const SphinxModule*>(loadPlugin("libtalkhead-sphinx.so", "talkhead_sphinx_module", kSphinxModuleAbi));
		} catch (const Error& e) {
			throw Error(std::string(e.what()) + " (recognising speech needs the Debian packages libpocketsphinx3 and pocketsphinx-en-us)");
		}
	}();
	return *m;
}

std::string sphinxModelDir(const RecognizeOptions& o) {
	if (!o.modelDir.empty()) return o.modelDir;
	if (const char* env = std::getenv("TALKHEAD_SPHINX_MODEL"); env && *env) return env;
	return "/usr/share/pocketsphinx/model/en-us";
}

// The decoder, opened once per process and settings (loading the model takes ~0.3 s).
struct SphinxDecoder {
	void* handle = nullptr;
	SphinxConfig config;
};

// Decoder `slot` (one per thread) for these settings.
void* sphinxHandle(const RecognizeOptions& o, int slot) {
	static std::mutex mutex;
	// Kept for the process, as the plugin is; never destroyed, so that the handles stay reachable at exit
	// (a destroyed list would leave them to LeakSanitizer as leaks).
	static auto* const decoders = new std::vector<std::pair<int, SphinxDecoder>>();
	auto& open = *decoders;
	const std::lock_guard<std::mutex> lock(mutex);
	SphinxConfig c;
	c.modelDir = sphinxModelDir(o);
	c.beam = o.beam;
	c.phoneBeam = o.phoneBeam;
	c.languageWeight = o.languageWeight;
	for (const auto& [s, d] : open)
		if (s == slot && d.config.modelDir == c.modelDir && d.config.beam == c.beam && d.config.phoneBeam == c.phoneBeam && d.config.languageWeight == c.languageWeight)
			return d.handle;
	std::string error;
	void* h = sphinxModule().open(c, error);
	if (!h) throw Error(error);
	open.push_back({slot, {h, c}});
	return h;
}

// How many decoders run at once: as asked, else up to 2 as the machine has cores.
int decoderCount(const RecognizeOptions& o) {
	return o.threads > 0 ? o.threads : int(std::min(2u, std::max(1u, std::thread::hardware_concurrency())));
}

// `frames` interleaved sample frames of `channels` channels, averaged into `out`.
void mixDown(const float* in, std::size_t frames, int channels, float* out) {
	for (std::size_t i = 0; i < frames; ++i) {
		double s = 0;
		for (int c = 0; c < channels; ++c) s += in[i * std::size_t(channels) + std::size_t(c)];
		out[i] = float(s / channels);
	}
}

// A source's samples as mono at 16 kHz, a block at a time.
class MonoStream {
public:
	explicit MonoStream(std::unique_ptr<AudioSource> s, const std::string& name) : source_(std::move(s)) {
		if (!source_) throw Error(name + ": no audio");
		if (source_->sampleRate() != kSphinxRate) throw std::logic_error("recognizePhones: the source is not at 16 kHz");
		channels_ = std::max(1, source_->channels());
	}
	// Up to n samples; fewer only at the end.
	std::size_t read(float* out, std::size_t n) {
		buffer_.resize(n * std::size_t(channels_));
		const std::size_t got = source_->read(buffer_.data(), n);
		mixDown(buffer_.data(), got, channels_, out);
		return got;
	}

private:
	std::unique_ptr<AudioSource> source_;
	int channels_ = 1;
	std::vector<float> buffer_;
};

// Pass 1: the level of every 10-ms frame (25-ms window, as align::frameLevels) and the sample count.
std::vector<float> streamLevels(MonoStream& in, std::size_t& samples) {
	std::vector<float> levels, window;
	std::vector<float> block(16000);
	samples = 0;
	std::size_t head = 0;  // index in `window` of the next frame's first sample
	for (;;) {
		const std::size_t got = in.read(block.data(), block.size());
		if (got == 0) break;
		samples += got;
		window.insert(window.end(), block.begin(), block.begin() + std::ptrdiff_t(got));
		while (window.size() - head >= kLevelWindow) {
			double mean = 0, sum = 0;
			for (int n = 0; n < kLevelWindow; ++n) mean += window[head + std::size_t(n)];
			mean /= kLevelWindow;
			for (int n = 0; n < kLevelWindow; ++n) {
				const double x = window[head + std::size_t(n)] - mean;
				sum += x * x;
			}
			levels.push_back(float(10 * std::log10(std::max(sum / kLevelWindow, 1e-12))));
			head += kLevelHop;
		}
		window.erase(window.begin(), window.begin() + std::ptrdiff_t(head));
		head = 0;
	}
	return levels;
}

// Utterances [first, last) in samples: the stretches of speech, padded, joined across short pauses, and
// cut at their quietest frame when longer than the longest the decoder is given.
std::vector<std::pair<std::size_t, std::size_t>> utterancesOf(const std::vector<bool>& speech, const std::vector<float>& levels, std::size_t samples,
                                                               const RecognizeOptions& o) {
	std::vector<std::pair<long, long>> runs;  // frames [a, b)
	for (std::size_t k = 0; k < speech.size(); ++k)
		if (speech[k] && (k == 0 || !speech[k - 1])) runs.emplace_back(long(k), long(k) + 1);
		else if (speech[k]) runs.back().second = long(k) + 1;
	const long pad = std::lround(o.paddingSeconds / kFrameSeconds), join = std::lround(o.joinPausesSeconds / kFrameSeconds);
	std::vector<std::pair<long, long>> merged;
	for (auto r : runs) {
		r.first = std::max(0L, r.first - pad);
		r.second = std::min(long(levels.size()), r.second + pad);
		if (!merged.empty() && r.first - merged.back().second < join) merged.back().second = r.second;
		else merged.push_back(r);
	}
	// The longest the next utterance may be: longestUtteranceSeconds, or (live) firstUtteranceSeconds doubling up to it.
	const auto longestNext = [&](std::size_t made) {
		double s = o.longestUtteranceSeconds;
		if (o.firstUtteranceSeconds > 0) s = std::min(s, o.firstUtteranceSeconds * std::pow(2.0, double(std::min<std::size_t>(made, 16))));
		return std::max(o.firstUtteranceSeconds > 0 ? 30L : 100L, std::lround(s / kFrameSeconds));
	};
	std::vector<std::pair<std::size_t, std::size_t>> out;
	for (auto [a, b] : merged) {
		for (long longest = longestNext(out.size()); b - a > longest; longest = longestNext(out.size())) {
			// The quietest frame in the last third of the allowed length.
			long cut = a + longest, best = cut;
			for (long k = a + longest * 2 / 3; k < a + longest; ++k)
				if (levels[std::size_t(k)] < levels[std::size_t(best)]) best = k;
			cut = best;
			out.emplace_back(std::size_t(a) * kLevelHop, std::size_t(cut) * kLevelHop);
			a = cut;
		}
		out.emplace_back(std::size_t(a) * kLevelHop, std::min(samples, std::size_t(b) * kLevelHop + kLevelWindow));
	}
	return out;
}

std::string withDecimals(double v, int decimals) {
	char b[64];
	std::snprintf(b, sizeof b, "%.*f", decimals, v);
	return b;
}

// How much the spectrum changes in an utterance's voice: the median over its voice frames of the length of
// the cepstral deltas c1…c12 (align's MFCC + Δ). Speech changes all the time (1.27–2.36 on GRID, CREMA-D and
// real-inputs-3 recordings), a melody of steady notes (0.88) and noise bursts (0.69) hardly between onsets.
double spectralChange(const std::vector<std::int16_t>& samples, const std::vector<bool>& speech, std::size_t firstFrame) {
	std::vector<float> x(samples.size());
	for (std::size_t i = 0; i < samples.size(); ++i) x[i] = float(samples[i]) / 32768.0f;
	const align::FeatureMatrix f = align::mfcc(x, kSphinxRate);
	std::vector<double> d;
	for (int k = 0; k < f.frames; ++k) {
		const std::size_t at = firstFrame + std::size_t(k);
		if (at >= speech.size() || !speech[at]) continue;
		double s = 0;
		for (int j = 14; j < 26 && j < f.dims; ++j) s += double(f.row(k)[j]) * double(f.row(k)[j]);
		d.push_back(std::sqrt(s));
	}
	if (d.empty()) return 0;
	std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(d.size() / 2), d.end());
	return d[d.size() / 2];
}

Ticks frameTicks(long frame) { return Ticks(std::int64_t(frame) * (kTicksPerSecond / 100)); }

bool isPauseLabel(const std::string& p) { return p.empty() || p == "SIL" || p == "sil" || (p.size() > 1 && p.front() == '+' && p.back() == '+'); }

// A clip's mono samples resampled to 16 kHz: a windowed-sinc low-pass at 0.45 of the lower rate, evaluated
// at each output instant (Blackman window, 16 zero crossings each side).
AudioClip clipAt16k(const AudioClip& clip) {
	if (clip.sampleRate == kSphinxRate) return clip;
	if (clip.sampleRate <= 0 || clip.channels <= 0) throw Error("the audio has no sample rate");
	const std::size_t n = clip.frameCount();
	std::vector<float> mono(n);
	mixDown(clip.samples.data(), n, clip.channels, mono.data());
	const double ratio = double(clip.sampleRate) / kSphinxRate;         // input samples per output sample
	const double cutoff = 0.45 * std::min(1.0, 1.0 / ratio);            // of the input rate
	const int half = int(std::ceil(16 / (2 * cutoff)));                 // taps each side, in input samples
	constexpr double kPi = 3.14159265358979323846;
	const auto tap = [&](double x) {  // the windowed sinc at x input samples from the output sample
		const double arg = 2 * cutoff * x;
		const double sinc = std::abs(arg) < 1e-9 ? 1.0 : std::sin(kPi * arg) / (kPi * arg);
		return sinc * (0.42 + 0.5 * std::cos(kPi * x / half) + 0.08 * std::cos(2 * kPi * x / half));
	};
	// Output sample j lies at input position j·P/Q (P/Q = rate/16000 reduced): its fractional part takes only
	// Q values, so each one's taps are computed once (22 050 Hz: 320 of them) rather than per sample.
	const std::int64_t g = std::gcd(std::int64_t(clip.sampleRate), std::int64_t(kSphinxRate));
	const std::int64_t P = clip.sampleRate / g, Q = kSphinxRate / g;
	AudioClip out;
	out.sampleRate = kSphinxRate;
	out.channels = 1;
	out.samples.resize(std::size_t(std::int64_t(n) * Q / P));
	const std::size_t width = std::size_t(2 * half);
	// A rate with too many phases (an odd one: 22 051 Hz has 16 000) has its taps computed per sample.
	const bool table = std::size_t(Q) * width <= (std::size_t(1) << 20);
	std::vector<double> taps(table ? std::size_t(Q) * width : width);
	const auto phase = [&](std::int64_t q, double* w) {
		for (std::size_t k = 0; k < width; ++k) w[k] = tap(double(long(k) - half + 1) - double(q) / double(Q));
	};
	if (table)
		for (std::int64_t q = 0; q < Q; ++q) phase(q, taps.data() + std::size_t(q) * width);
	for (std::size_t j = 0; j < out.samples.size(); ++j) {
		const std::int64_t at = std::int64_t(j) * P;
		const long c = long(at / Q);
		const double* w = taps.data();
		if (table) w += std::size_t(at % Q) * width;
		else phase(at % Q, taps.data());
		double sum = 0, weight = 0;
		for (std::size_t k = 0; k < width; ++k) {
			const long i = c - half + 1 + long(k);
			if (i < 0 || i >= long(n)) continue;
			sum += mono[std::size_t(i)] * w[k];
			weight += w[k];
		}
		out.samples[j] = float(weight != 0 ? sum / weight : 0);
	}
	return out;
}

}  // namespace

Recognition recognizePhones(const std::function<std::unique_ptr<AudioSource>()>& open, const std::string& name, const RecognizeOptions& o) {
	Recognition rec;
	rec.phones.path = name;
	rec.phones.format = "recognized";
	rec.phones.level = LabelLevel::Phone;
	// Pass 1: levels, voice activity, utterances.
	std::size_t samples = 0;
	std::vector<float> levels;
	{
		MonoStream in(open(), name);
		levels = streamLevels(in, samples);
	}
	if (samples == 0) throw Error(name + ": the audio has no samples");
	if (levels.empty()) throw Error(name + ": the audio is shorter than 25 ms: nothing to recognise");
	rec.duration = Ticks(std::int64_t(samples) * (kTicksPerSecond / kSphinxRate));
	VoiceActivity activity;
	try {
		activity = detectVoiceActivity(levels);
	} catch (const Error& e) {
		// Silence or a steady sound: a still face, said in one line.
		rec.phones.intervals = withPauses({}, Ticks(0), rec.duration);
		rec.confidence.assign(rec.phones.intervals.size(), 1.0);
		rec.warnings.push_back(name + ": " + e.what() + ": the face stays still");
		return rec;
	}
	long speechFrames = 0;
	for (bool s : activity.speech) speechFrames += s;
	rec.speechSeconds = frameTicks(speechFrames);
	const auto utterances = utterancesOf(activity.speech, levels, samples, o);
	rec.utterances = int(utterances.size());
	// Pass 2: the utterances read in order and decoded as they arrive, on up to `threads` decoders (each
	// utterance alone: the result does not depend on which decoder took it or what it decoded before).
	const int threads = std::max(1, std::min<int>(int(utterances.size()), decoderCount(o)));
	std::vector<void*> decoders;
	for (int t = 0; t < threads; ++t) decoders.push_back(sphinxHandle(o, t));
	std::vector<std::vector<SphinxPhone>> decoded(utterances.size());
	std::vector<double> change(utterances.size(), 0.0);  // per utterance: median |Δ cepstrum| over its voice frames
	const Language& en = Language::get("en-US");
	const auto confidenceOf = [&](double rate) { return std::clamp((rate - o.unsureRate) / (o.sureRate - o.unsureRate), 0.0, 1.0); };
	// One utterance's phones (absolute times, no pauses) and their confidence; the count of phones left out
	// when it is not speech.
	const auto phonesOf = [&](std::size_t u, std::vector<Interval>& spoken, std::vector<double>& spokenConfidence, double& confSum, double& confWeight) -> long {
		const auto [first, last] = utterances[u];
		const std::vector<SphinxPhone>& phones = decoded[u];
		const long offset = long(first / kLevelHop);
		// The utterance's rate: phones per second of its voice activity.
		long voiced = 0, count = 0;
		for (long k = offset; k < long(last / kLevelHop) && k < long(activity.speech.size()); ++k) voiced += activity.speech[std::size_t(k)];
		for (const SphinxPhone& p : phones) count += !isPauseLabel(p.phone) && p.end > p.start;
		const double byRate = confidenceOf(voiced > 0 ? double(count) / (double(voiced) * kFrameSeconds) : 0.0);
		const double bySpectrum = std::clamp((change[u] - o.steadyChange) / (o.speechChange - o.steadyChange), 0.0, 1.0);
		const double c = std::min(byRate, bySpectrum);
		if (bySpectrum < o.dropBelow) return count;  // not speech (a melody, a noise): left out, the face stays still there
		for (const SphinxPhone& p : phones) {
			if (isPauseLabel(p.phone) || p.end <= p.start) continue;
			const auto ipa = en.normalize(p.phone, Notation::Arpabet);
			if (!ipa) continue;  // a filler the table does not know: a pause
			const Ticks a = frameTicks(offset + p.start), b = std::min(rec.duration, frameTicks(offset + p.end));
			if (b <= a) continue;
			// A diphthong or affricate the table splits shares the phone's frames.
			const std::int64_t parts = std::int64_t(ipa->size());
			for (std::int64_t k = 0; k < parts; ++k) {
				Interval iv;
				iv.start = a + (b - a) * k / parts;
				iv.end = a + (b - a) * (k + 1) / parts;
				iv.label = (*ipa)[std::size_t(k)];
				spoken.push_back(iv);
				spokenConfidence.push_back(c);
			}
			const double w = toSeconds(b - a);
			confSum += c * w;
			confWeight += w;
		}
		return 0;
	};
	// Progress (a live speak): each utterance reported in order once it and those before it are decoded.
	std::mutex progressMutex;
	std::vector<char> decodedYet(utterances.size(), 0);
	std::size_t reported = 0;
	const auto report = [&](std::size_t u) -> bool {
		if (!o.progress) return true;
		const std::lock_guard<std::mutex> lock(progressMutex);
		decodedYet[u] = 1;
		for (; reported < utterances.size() && decodedYet[reported]; ++reported) {
			std::vector<Interval> spoken;
			std::vector<double> conf;
			double sum = 0, weight = 0;
			phonesOf(reported, spoken, conf, sum, weight);
			const Ticks upTo = Ticks(std::int64_t(utterances[reported].second) * (kTicksPerSecond / kSphinxRate));
			if (!o.progress(upTo, spoken, conf)) return false;
		}
		return true;
	};
	{
		std::mutex m;
		std::condition_variable changed;
		std::deque<std::pair<std::size_t, std::vector<std::int16_t>>> queue;  // at most 2 per decoder wait
		bool done = false, firstDecoded = false;
		std::string failure;
		std::vector<std::thread> workers;
		for (int t = 0; t < threads; ++t)
			workers.emplace_back([&, t] {
				for (;;) {
					std::pair<std::size_t, std::vector<std::int16_t>> job;
					{
						std::unique_lock<std::mutex> lock(m);
						changed.wait(lock, [&] { return !queue.empty() || done || !failure.empty(); });
						if (!failure.empty() || queue.empty()) return;
						job = std::move(queue.front());
						queue.pop_front();
					}
					changed.notify_all();
					std::string error;
					std::vector<SphinxPhone> phones;
					if (!sphinxModule().decode(decoders[std::size_t(t)], job.second.data(), job.second.size(), phones, error)) {
						const std::lock_guard<std::mutex> lock(m);
						if (failure.empty()) failure = error.empty() ? "decoding failed" : error;
						changed.notify_all();
						return;
					}
					decoded[job.first] = std::move(phones);
					if (job.first == 0) {
						const std::lock_guard<std::mutex> lock(m);
						firstDecoded = true;
						changed.notify_all();
					}
					bool goOn = false;
					try {
						goOn = report(job.first);
					} catch (...) {
					}
					if (!goOn) {
						const std::lock_guard<std::mutex> lock(m);
						if (failure.empty()) failure = "stopped";
						changed.notify_all();
						return;
					}
				}
			});
		const auto finish = [&] {
			{
				const std::lock_guard<std::mutex> lock(m);
				done = true;
			}
			changed.notify_all();
			for (auto& w : workers) w.join();
		};
		try {
			MonoStream in(open(), name);
			std::vector<float> block(16000);
			std::size_t at = 0;  // samples read so far
			for (std::size_t u = 0; u < utterances.size(); ++u) {
				const auto [first, last] = utterances[u];
				std::vector<std::int16_t> utt;
				utt.reserve(last - first);
				while (at < last) {
					const std::size_t got = in.read(block.data(), std::min(block.size(), last - at));
					if (got == 0) break;
					for (std::size_t i = 0; i < got; ++i)
						if (at + i >= first) utt.push_back(std::int16_t(std::lround(std::clamp(block[i], -1.0f, 1.0f) * 32767.0f)));
					at += got;
				}
				change[u] = spectralChange(utt, activity.speech, first / kLevelHop);
				std::unique_lock<std::mutex> lock(m);
				// Live, the first utterance is decoded alone: its phones are what the face waits for.
				changed.wait(lock, [&] { return (queue.size() < std::size_t(2 * threads) && (u == 0 || firstDecoded || !o.progress)) || !failure.empty(); });
				if (!failure.empty()) break;
				queue.emplace_back(u, std::move(utt));
				lock.unlock();
				changed.notify_all();
			}
		} catch (...) {
			{
				const std::lock_guard<std::mutex> lock(m);
				if (failure.empty()) failure = "stopped";
			}
			finish();
			throw;
		}
		finish();
		if (!failure.empty()) throw Error(name + ": " + failure);
	}
	std::vector<Interval> spoken;
	std::vector<double> spokenConfidence;
	double confSum = 0, confWeight = 0;
	long dropped = 0;
	for (std::size_t u = 0; u < utterances.size(); ++u) dropped += phonesOf(u, spoken, spokenConfidence, confSum, confWeight);
	// Contiguous over the whole audio: pauses between.
	rec.phones.intervals = withPauses(spoken, Ticks(0), rec.duration);
	std::size_t k = 0;
	for (const Interval& iv : rec.phones.intervals) {
		if (iv.label.empty()) {
			rec.confidence.push_back(1.0);
			continue;
		}
		while (k < spoken.size() && !(spoken[k].start == iv.start && spoken[k].label == iv.label)) ++k;
		rec.confidence.push_back(k < spoken.size() ? spokenConfidence[k] : 0.0);
	}
	rec.meanConfidence = confWeight > 0 ? confSum / confWeight : 0;
	if (dropped > 0)
		rec.warnings.push_back(name + ": " + std::to_string(dropped) + " phones left out where the sound does not change as speech does (music, a tone, noise?): the face stays still there");
	if (spoken.empty() && dropped == 0) rec.warnings.push_back(name + ": no phones recognised in its speech: the face stays still");
	else if (!spoken.empty() && rec.meanConfidence < o.doubtfulBelow)
		rec.warnings.push_back(name + ": the recognition is doubtful (mean confidence " + withDecimals(rec.meanConfidence, 2) +
		                       "): music, noise or a voice the en-US model does not know? The mouth follows it loosely");
	return rec;
}

void warmRecognizer(const RecognizeOptions& o) {
	const int threads = decoderCount(o);
	for (int t = 0; t < threads; ++t) sphinxHandle(o, t);
}

Recognition recognizePhonesFile(const std::string& path, const RecognizeOptions& options) {
	if (!std::filesystem::exists(path)) throw Error(path + ": no such file");
	return recognizePhones([&] { return openAudioFile(path, kSphinxRate); }, path, options);
}

Recognition recognizePhonesClip(const AudioClip& clip, const std::string& name, const RecognizeOptions& options) {
	const AudioClip at16 = clipAt16k(clip);
	Recognition r = recognizePhones([&] { return clipSource(at16); }, name, options);
	// The clip's own length (resampling rounds it to a whole 16-kHz sample).
	const Ticks exact = clip.duration();
	if (!r.phones.intervals.empty() && r.duration != exact) {
		auto& iv = r.phones.intervals;
		while (iv.size() > 1 && iv.back().start >= exact) {
			iv.pop_back();
			r.confidence.pop_back();
		}
		iv.back().end = exact;
		r.duration = exact;
	}
	return r;
}

std::string recognitionSummary(const Recognition& r) {
	int phones = 0;
	Ticks first{-1}, last{0};
	for (const Interval& iv : r.phones.intervals)
		if (!iv.label.empty()) {
			++phones;
			if (first < Ticks(0)) first = iv.start;
			last = iv.end;
		}
	std::string s = "recognised from the audio (no timing given): " + std::to_string(phones) + " phones";
	if (phones) s += ", speech " + withDecimals(toSeconds(first), 2) + "–" + withDecimals(toSeconds(last), 2) + " s";
	s += ", mean confidence " + withDecimals(r.meanConfidence, 2);
	return s;
}

}  // namespace talkhead
