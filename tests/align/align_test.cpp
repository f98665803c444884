// SPDX-License-Identifier: GPL-3.0-or-later
// Forced alignment (issue 10 §2): features and DTW against known answers; espeak-ng speech of other
// voices, rates and pitches aligned within bounds; the GRID clip against its hand alignment; errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "align/align.h"
#include "align/features.h"
#include "base/error.h"
#include "base/text.h"
#include "phonetics/espeak.h"
#include "phonetics/language.h"
#include "phonetics/transcript.h"
#include "test_support.h"

using namespace talkhead;
using namespace talkhead::align;

namespace {

double percentileOf(std::vector<double> v, double p) {
	if (v.empty()) return 0;
	std::sort(v.begin(), v.end());
	const double x = p * double(v.size() - 1);
	const std::size_t k = std::size_t(x);
	return k + 1 < v.size() ? v[k] + (x - double(k)) * (v[k + 1] - v[k]) : v[k];
}

// Tuning from TALKHEAD_ALIGN_TUNE ("name=value,…"), for bench/align.sh experiments.
AlignOptions optionsFor(const std::string& tag) {
	AlignOptions o;
	o.languageTag = tag;
	if (const char* env = std::getenv("TALKHEAD_ALIGN_TUNE")) {
		for (const std::string& kv : split(env, ',')) {
			const auto eq = kv.find('=');
			if (eq == std::string::npos) continue;
			const std::string k = kv.substr(0, eq);
			double v = 0;
			if (!parseDouble(kv.substr(eq + 1), v)) continue;
			AlignTuning& t = o.tuning;
			if (k == "wordGap") t.wordGap10ms = int(v);
			else if (k == "pad") t.padSeconds = v;
			else if (k == "maxSlope") t.maxSlope = int(v);
			else if (k == "inputPauses") t.inputPauses = v != 0;
			else if (k == "channel") t.matchChannel = v != 0;
			else if (k == "vad") t.vadFraction = v;
			else if (k == "vadLow") t.vadLowFraction = v;
			else if (k == "snap") t.snapEdgesSeconds = v;
			else if (k == "dd") t.deltaDeltas = v != 0;
			else if (k == "matchRate") t.matchRate = v != 0;
			else if (k == "rateIterations") t.rateIterations = int(v);
			else if (k == "renditions") t.renditions = int(v);
		}
	}
	return o;
}

AudioClip clipOf(const Speech& sp, double noiseDb) {
	AudioClip c;
	c.sampleRate = sp.sampleRate;
	c.channels = 1;
	std::uint32_t seed = 99;
	const double amp = std::pow(10.0, noiseDb / 20.0) * std::sqrt(3.0);
	for (short v : sp.pcm) {
		seed = seed * 1664525u + 1013904223u;
		c.samples.push_back(float(v) / 32768.f + float(amp * (2.0 * double(seed >> 8) / double(1u << 24) - 1.0)));
	}
	return c;
}

// Boundary errors between two phone transcripts of the same text: the spoken phones are paired by a
// longest common subsequence of labels (espeak-ng drops a zero-length phone now and then, e.g. a linking
// [ɹ]); each paired phone's start, and its end where a pause or the end follows, is compared.
std::vector<double> boundaryErrors(const Transcript& got, const Transcript& truth, std::size_t& unpaired) {
	struct P {
		std::string label;
		double start, end;
		bool endsBeforePause;
	};
	const auto spoken = [](const Transcript& t) {
		std::vector<P> v;
		for (std::size_t k = 0; k < t.intervals.size(); ++k)
			if (!t.intervals[k].label.empty())
				v.push_back({t.intervals[k].label, toSeconds(t.intervals[k].start), toSeconds(t.intervals[k].end),
				             k + 1 == t.intervals.size() || t.intervals[k + 1].label.empty()});
		return v;
	};
	const auto a = spoken(got), b = spoken(truth);
	std::vector<std::vector<int>> L(a.size() + 1, std::vector<int>(b.size() + 1, 0));
	for (std::size_t i = a.size(); i-- > 0;)
		for (std::size_t j = b.size(); j-- > 0;) L[i][j] = a[i].label == b[j].label ? L[i + 1][j + 1] + 1 : std::max(L[i + 1][j], L[i][j + 1]);
	std::vector<double> e;
	std::size_t i = 0, j = 0;
	while (i < a.size() && j < b.size()) {
		if (a[i].label == b[j].label) {
			e.push_back(std::abs(a[i].start - b[j].start));
			if (a[i].endsBeforePause && b[j].endsBeforePause) e.push_back(std::abs(a[i].end - b[j].end));
			++i, ++j;
		} else if (L[i + 1][j] >= L[i][j + 1]) {
			++i;
		} else {
			++j;
		}
	}
	unpaired = a.size() + b.size() - 2 * std::size_t(L[0][0]);
	return e;
}

Transcript canonical(const Transcript& espeakPhones, const Language& lang, Ticks end) {
	Transcript t;
	for (const PhoneSegment& s : phoneSegments(espeakPhones, lang, UnknownPhone::Nearest, Notation::Espeak)) {
		const std::string label = s.phone == "_" ? "" : s.phone;
		if (label.empty() && !t.intervals.empty() && t.intervals.back().label.empty()) t.intervals.back().end = s.end;
		else t.intervals.push_back({s.start, s.end, label, 0});
	}
	if (!t.intervals.empty()) t.intervals.back().end = end;
	return t;
}

struct SelfResult {
	std::vector<double> errors;  // seconds
	int utterances = 0;
	std::size_t unpaired = 0, phones = 0;
	double audioSeconds = 0, alignSeconds = 0;
};

const std::vector<std::string> kEnglish = {
    "The quick brown fox jumps over the lazy dog.",
    "Please call Stella and ask her to bring these things with her from the store.",
    "She sells sea shells by the sea shore.",
    "We were away a year ago.",
    "Peter Piper picked a peck of pickled peppers.",
    "How much wood would a woodchuck chuck?",
    "The rainbow is a division of white light into many beautiful colors.",
    "I never said she stole my money.",
    "Can you keep a secret until tomorrow morning?",
    "My grandmother baked fresh bread every Sunday.",
    "Bob bought a big blue boat last month.",
    "Turn left at the second traffic light, then go straight ahead.",
};
const std::vector<std::string> kPortuguese = {
    "Que notícia excelente!",
    "O rato roeu a roupa do rei de Roma.",
    "Amanhã vamos à praia com os meus primos.",
    "A vida é bela quando o sol brilha.",
    "Eu gosto muito de pão com manteiga.",
    "O menino comprou um livro novo na livraria.",
    "Você pode me ajudar com esta mala pesada?",
    "Choveu bastante durante a noite inteira.",
    "Minha mãe faz um bolo de chocolate delicioso.",
    "Os pássaros cantam cedo na floresta.",
    "Ela trabalha no hospital desde o ano passado.",
    "Paulo pintou a parede de azul.",
};

struct TestVoice {
	const char* variant;
	int rate, pitch, wordGap;  // wordGap: pauses between words (10 ms units), as a hesitant speaker makes
};
// Reference renditions use the language's voice, +m3 and +f2 at the input's rate and pitch 50.
const std::vector<TestVoice> kTestVoices = {{"+m1", 130, 35, 0}, {"+f4", 210, 75, 0}, {"+klatt", 160, 60, 0}, {"+m6", 240, 45, 0}, {"+f1", 180, 55, 20}};

SelfResult selfAligned(const std::string& tag, const std::vector<std::string>& sentences) {
	SelfResult r;
	const Language& lang = Language::get(tag);
	for (std::size_t s = 0; s < sentences.size(); ++s) {
		for (std::size_t v = 0; v < 2; ++v) {
			const TestVoice& tv = kTestVoices[(s + v * 7) % kTestVoices.size()];
			const Speech sp = espeakSpeak(sentences[s], espeakVoiceFor(tag) + tv.variant, tv.rate, tv.pitch, tv.wordGap);
			const AudioClip clip = clipOf(sp, -50);
			const Transcript truth = canonical(phonesWithClosures(sp), lang, clip.duration());
			const auto t0 = std::chrono::steady_clock::now();
			const Alignment al = alignSpeech(clip, sentences[s], optionsFor(tag));
			r.alignSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
			r.audioSeconds += toSeconds(clip.duration());
			++r.utterances;
			std::size_t unpaired = 0;
			const auto e = boundaryErrors(al.phones, truth, unpaired);
			r.errors.insert(r.errors.end(), e.begin(), e.end());
			r.unpaired += unpaired;

		}
	}
	return r;
}

// GRID word alignment: "start end word" in 40 µs units.
std::vector<double> gridWordBoundaries(const std::string& path) {
	std::ifstream in(path);
	std::vector<double> b;
	std::string line;
	std::vector<std::tuple<double, double, std::string>> rows;
	while (std::getline(in, line)) {
		const auto f = splitWhitespace(line);
		if (f.size() != 3) continue;
		rows.emplace_back(std::stod(f[0]) / 25000.0, std::stod(f[1]) / 25000.0, f[2]);
	}
	// Every word start and end (a boundary shared by two words once).
	for (std::size_t k = 0; k < rows.size(); ++k) {
		if (std::get<2>(rows[k]) == "sil") continue;
		if (b.empty() || std::abs(b.back() - std::get<0>(rows[k])) > 1e-9) b.push_back(std::get<0>(rows[k]));
		b.push_back(std::get<1>(rows[k]));
	}
	return b;
}

// The boundary between two words is the middle of any pause the alignment put between them.
std::vector<double> alignedWordBoundaries(const Alignment& al) {
	std::vector<double> b;
	for (std::size_t k = 0; k < al.wordList.size(); ++k) {
		const double s = toSeconds(al.wordList[k].start), e = toSeconds(al.wordList[k].end);
		if (k == 0) b.push_back(s);
		else b.back() = 0.5 * (b.back() + s);  // b.back() is the previous word's end
		b.push_back(e);
	}
	return b;
}

std::string gridClip() { return test::sharedData() + "/grid/id2_vcd_swwp2s.mpg"; }

}  // namespace

TEST(AlignFeatures, framesAndMfccShape) {
	FeatureOptions fo;
	EXPECT_EQ(frameCountFor(399, 16000, fo), 0);
	EXPECT_EQ(frameCountFor(400, 16000, fo), 1);
	EXPECT_EQ(frameCountFor(16000, 16000, fo), 98);
	std::vector<float> tone(16000);
	for (std::size_t k = 0; k < tone.size(); ++k) tone[k] = 0.5f * float(std::sin(2 * M_PI * 1000.0 * double(k) / 16000.0));
	const FeatureMatrix f = mfcc(tone, 16000, fo);
	EXPECT_EQ(f.frames, 98);
	EXPECT_EQ(f.dims, 26);
	// A steady tone: the same cepstrum in every frame, zero deltas.
	for (int d = 0; d < 13; ++d) EXPECT_NEAR(f.row(50)[d], f.row(20)[d], 1e-2);
	for (int d = 13; d < 26; ++d) EXPECT_NEAR(f.row(50)[d], 0.0, 1e-2);
	// The same tone at another sample rate gives nearly the same cepstrum (filters placed in Hz).
	std::vector<float> tone22(22050);
	for (std::size_t k = 0; k < tone22.size(); ++k) tone22[k] = 0.5f * float(std::sin(2 * M_PI * 1000.0 * double(k) / 22050.0));
	const FeatureMatrix g = mfcc(tone22, 22050, fo);
	for (int d = 1; d < 13; ++d) EXPECT_NEAR(g.row(50)[d], f.row(50)[d], 0.35) << "c" << d;
	// Levels: a 0.5-amplitude sine is 0.125 mean square = −9 dBFS.
	const auto lv = frameLevels(tone, 16000, fo);
	EXPECT_NEAR(lv[10], -9.03, 0.1);
	// Normalisation: zero mean and unit variance over the chosen frames.
	FeatureMatrix h = mfcc(tone, 16000, fo);
	for (int k = 0; k < h.frames; ++k) h.row(k)[0] = float(k);
	normalise(h);
	double mean = 0, sq = 0;
	for (int k = 0; k < h.frames; ++k) mean += h.row(k)[0], sq += h.row(k)[0] * h.row(k)[0];
	EXPECT_NEAR(mean / h.frames, 0.0, 1e-5);
	EXPECT_NEAR(sq / h.frames, 1.0, 1e-4);
}

TEST(AlignDtw, recoversATimeStretch) {
	// A smooth random 3-dimensional trajectory and a copy stretched by 1.6 (linear interpolation).
	FeatureMatrix a, b;
	a.dims = b.dims = 3;
	a.frames = 200;
	std::uint32_t seed = 7;
	auto rnd = [&seed] {
		seed = seed * 1664525u + 1013904223u;
		return double(seed >> 8) / double(1u << 24) - 0.5;
	};
	std::vector<double> x(3, 0.0), v(3, 0.0);
	for (int k = 0; k < a.frames; ++k)
		for (int d = 0; d < 3; ++d) {
			v[std::size_t(d)] = 0.8 * v[std::size_t(d)] + rnd();
			x[std::size_t(d)] += v[std::size_t(d)];
			a.data.push_back(float(x[std::size_t(d)]));
		}
	const double s = 1.6;
	b.frames = int((a.frames - 1) * s) + 1;
	for (int j = 0; j < b.frames; ++j) {
		const double p = j / s;
		const int k = std::min(a.frames - 2, int(p));
		for (int d = 0; d < 3; ++d) b.data.push_back(float(a.row(k)[d] + (p - k) * (a.row(k + 1)[d] - a.row(k)[d])));
	}
	const DtwResult r = dtw(a, b, {}, {});
	ASSERT_EQ(r.path.front(), std::make_pair(0, 0));
	ASSERT_EQ(r.path.back(), std::make_pair(a.frames - 1, b.frames - 1));
	for (std::size_t k = 1; k < r.path.size(); ++k) {
		EXPECT_GE(r.path[k].first, r.path[k - 1].first);
		EXPECT_GE(r.path[k].second, r.path[k - 1].second);
	}
	const PathMap map(r.path, b.frames);
	double worst = 0;
	for (int j = 0; j < b.frames; ++j) worst = std::max(worst, std::abs(map(j) - j / s));
	EXPECT_LE(worst, 1.0);
	// With a band the answer is the same.
	DtwOptions banded;
	banded.band = 80;
	const DtwResult rb = dtw(a, b, {}, {}, banded);
	EXPECT_NEAR(rb.cost, r.cost, 1e-6);
	// A slope limit of 1 cannot stretch by 1.6.
	DtwOptions stiff;
	stiff.maxSlope = 1;
	EXPECT_THROW(dtw(a, b, {}, {}, stiff), std::invalid_argument);
}

TEST(AlignDtw, pausesOfTheReferenceStretchAndVanish) {
	// a: 10 frames of 1, 30 frames of 0 (a long pause), 10 frames of 2. b: 10 × 1, 3 × 0, 10 × 2.
	FeatureMatrix a, b;
	a.dims = b.dims = 1;
	for (int k = 0; k < 50; ++k) a.data.push_back(k < 10 ? 1.f : k < 40 ? 0.f : 2.f);
	for (int k = 0; k < 23; ++k) b.data.push_back(k < 10 ? 1.f : k < 13 ? 0.f : 2.f);
	a.frames = 50;
	b.frames = 23;
	std::vector<bool> pauseB(23, false);
	for (int k = 10; k < 13; ++k) pauseB[std::size_t(k)] = true;
	const DtwResult r = dtw(a, b, {}, pauseB);
	EXPECT_NEAR(r.cost, 0.0, 1e-6);
	const PathMap map(r.path, 23);
	EXPECT_NEAR(map(9.5), 9.5, 0.01);    // the pause's start
	EXPECT_NEAR(map(12.5), 39.5, 0.01);  // and end
	// The reference's pause where the input has none costs nothing either.
	FeatureMatrix c;
	c.dims = 1;
	for (int k = 0; k < 20; ++k) c.data.push_back(k < 10 ? 1.f : 2.f);
	c.frames = 20;
	EXPECT_NEAR(dtw(c, b, {}, pauseB).cost, 0.0, 1e-6);
}

TEST(AlignEspeak, otherVoicesRatesAndPitchesAlignWithinBounds) {
	for (const auto& [tag, sentences] : {std::pair<std::string, const std::vector<std::string>*>{"en-US", &kEnglish}, {"pt-BR", &kPortuguese}}) {
		const SelfResult r = selfAligned(tag, *sentences);
		const double med = percentileOf(r.errors, 0.5) * 1000, p90 = percentileOf(r.errors, 0.9) * 1000;
		std::printf("[ espeak %s ] %d utterances (%zu phones unpaired), %zu phone boundaries: median %.1f ms, p90 %.1f ms, "
		            "within 20 ms %.0f %%, speed %.3f x audio\n",
		            tag.c_str(), r.utterances, r.unpaired, r.errors.size(), med, p90,
		            100.0 * double(std::count_if(r.errors.begin(), r.errors.end(), [](double e) { return e <= 0.02; })) / double(std::max<std::size_t>(1, r.errors.size())),
		            r.alignSeconds / r.audioSeconds);
		EXPECT_LE(r.unpaired, r.errors.size() / 20) << tag;
		EXPECT_GE(r.errors.size(), 200u) << tag;
		EXPECT_LE(med, 25.0) << tag;
		EXPECT_LE(p90, 60.0) << tag;
	}
}

TEST(AlignGrid, wordBoundariesOfTheHandAlignedClip) {
	if (!std::filesystem::exists(gridClip())) GTEST_SKIP() << "GRID data not found in " << test::sharedData() << "/grid";
	const Alignment al = alignSpeechFile(gridClip(), "set white with p two soon", optionsFor("en-US"));
	const auto truth = gridWordBoundaries(test::sharedData() + "/grid/swwp2s.align");
	const auto got = alignedWordBoundaries(al);
	ASSERT_EQ(truth.size(), 7u);
	ASSERT_EQ(got.size(), truth.size());
	std::vector<double> e;
	std::string list;
	for (std::size_t k = 0; k < got.size(); ++k) {
		e.push_back(std::abs(got[k] - truth[k]));
		list += " " + std::to_string(int(std::lround((got[k] - truth[k]) * 1000)));
	}
	const double med = percentileOf(e, 0.5) * 1000, p90 = percentileOf(e, 0.9) * 1000;
	std::printf("[ GRID swwp2s ] word boundary errors (ms):%s; median %.1f ms, p90 %.1f ms, confidence %.2f\n", list.c_str(), med, p90, al.confidence);
	EXPECT_LE(med, 40.0);
	EXPECT_LE(p90, 80.0);
	EXPECT_GE(al.confidence, 0.5);
}

TEST(AlignErrors, emptyTextSilenceNoiseAndAnotherText) {
	AudioClip silence;
	silence.sampleRate = 16000;
	silence.channels = 1;
	silence.samples.assign(32000, 0.f);
	EXPECT_NE(test::errorOf([&] { alignSpeech(silence, "  ", optionsFor("en-US")); }).find("the text is empty"), std::string::npos);
	EXPECT_NE(test::errorOf([&] { alignSpeech(silence, "hello", optionsFor("en-US")); }).find("no speech in the audio: it is silent"), std::string::npos);
	AudioClip noise = silence;
	std::uint32_t seed = 5;
	for (float& v : noise.samples) {
		seed = seed * 1664525u + 1013904223u;
		v = 0.2f * (float(seed >> 8) / float(1u << 24) - 0.5f);
	}
	EXPECT_NE(test::errorOf([&] { alignSpeech(noise, "hello", optionsFor("en-US")); }).find("no speech in the audio"), std::string::npos);
	// Stereo speech (channels are averaged) aligns; another sentence does not.
	const Speech sp = espeakSpeak("Please call Stella and ask her to bring these things.", "en-us+f4", 190, 70);
	const AudioClip mono = clipOf(sp, -50);
	AudioClip stereo = mono;
	stereo.channels = 2;
	stereo.samples.clear();
	for (float v : mono.samples) stereo.samples.insert(stereo.samples.end(), {v, v});
	const Alignment al = alignSpeech(stereo, "Please call Stella and ask her to bring these things.", optionsFor("en-US"));
	EXPECT_GE(al.confidence, 0.6);
	EXPECT_EQ(al.wordList.size(), 10u);
	EXPECT_EQ(al.words.intervals.back().end, stereo.duration());
	EXPECT_EQ(al.phones.intervals.back().end, stereo.duration());
	const std::string e = test::errorOf([&] { alignSpeech(mono, "My grandmother baked fresh bread every Sunday morning.", optionsFor("en-US")); });
	EXPECT_NE(e.find("the text does not match the audio (confidence"), std::string::npos) << e;
	// The TextGrid: two interval tiers, words first; the reader picks "phones".
	const std::string grid = alignmentTextGrid(al, stereo.duration());
	EXPECT_NE(grid.find("name = \"words\""), std::string::npos);
	const Transcript back = parseTranscript(grid, "a.TextGrid");
	ASSERT_EQ(back.intervals.size(), al.phones.intervals.size());
	for (std::size_t k = 0; k < back.intervals.size(); ++k) EXPECT_EQ(back.intervals[k].label, al.phones.intervals[k].label);
}
