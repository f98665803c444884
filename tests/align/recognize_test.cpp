// SPDX-License-Identifier: GPL-3.0-or-later
// Phones recognised from audio alone (issue 49, D95): grid-s4's shipped GRID clips (in the repository)
// against their official word alignments; the same result whatever decoded before it and on any number
// of threads; a clip at another rate and channel count; silence, nothing, too short; a missing model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "align/recognize.h"
#include "base/error.h"
#include "media/audio.h"
#include "test_support.h"

using namespace talkhead;

namespace {

const std::string kFaceDir = std::string(TALKHEAD_TEST_DATA_DIR) + "/../../models/faces/grid-s4";
const char* const kClips[] = {"bgim8s", "bginza", "lbaq3p", "lriq4s", "pbbc4a", "prwj7p"};

struct Word {
	double start, end;
	std::string text;
};

// A GRID .align file: "start end word" in 1/25000 s; sil and sp left out.
std::vector<Word> gridWords(const std::string& path) {
	std::ifstream in(path);
	std::vector<Word> words;
	long a, b;
	std::string w;
	while (in >> a >> b >> w)
		if (w != "sil" && w != "sp") words.push_back({a / 25000.0, b / 25000.0, w});
	return words;
}

bool sameIntervals(const Recognition& a, const Recognition& b) {
	if (a.phones.intervals.size() != b.phones.intervals.size()) return false;
	for (std::size_t k = 0; k < a.phones.intervals.size(); ++k)
		if (a.phones.intervals[k].start != b.phones.intervals[k].start || a.phones.intervals[k].end != b.phones.intervals[k].end ||
		    a.phones.intervals[k].label != b.phones.intervals[k].label)
			return false;
	return true;
}

}  // namespace

TEST(Recognize, gridS4ClipsAgainstTheirOfficialWordAlignments) {
	std::vector<double> edges, nearest;
	int bilabials = 0, bilabialWords = 0;
	for (const char* name : kClips) {
		const Recognition r = recognizePhonesFile(kFaceDir + "/s4hq_" + name + ".mpg");
		const auto words = gridWords(kFaceDir + "/s4_" + std::string(name) + ".align");
		ASSERT_FALSE(words.empty());
		// Contiguous over the whole audio, speech inside it, every phone sure (speech's rate).
		ASSERT_FALSE(r.phones.intervals.empty());
		EXPECT_EQ(r.phones.intervals.front().start, Ticks(0));
		EXPECT_EQ(r.phones.intervals.back().end, r.duration);
		for (std::size_t k = 1; k < r.phones.intervals.size(); ++k) EXPECT_EQ(r.phones.intervals[k].start, r.phones.intervals[k - 1].end);
		EXPECT_GE(r.meanConfidence, 0.9) << name;
		EXPECT_TRUE(r.warnings.empty()) << name;
		std::vector<const Interval*> spoken;
		std::vector<double> bounds;
		for (const Interval& iv : r.phones.intervals) {
			if (!iv.label.empty()) spoken.push_back(&iv);
			bounds.push_back(toSeconds(iv.start));
		}
		bounds.push_back(toSeconds(r.duration));
		ASSERT_GE(spoken.size(), 8u) << name;
		edges.push_back(std::abs(toSeconds(spoken.front()->start) - words.front().start));
		edges.push_back(std::abs(toSeconds(spoken.back()->end) - words.back().end));
		for (const Word& w : words)
			for (double t : {w.start, w.end}) {
				double d = 1e9;
				for (double b : bounds) d = std::min(d, std::abs(b - t));
				nearest.push_back(d);
			}
		for (const Word& w : words) {
			if (w.text != "bin" && w.text != "blue" && w.text != "by" && w.text != "place" && w.text != "please" && w.text != "b" && w.text != "p") continue;
			++bilabialWords;
			bilabials += std::any_of(spoken.begin(), spoken.end(), [&](const Interval* iv) {
				return (iv->label == "p" || iv->label == "b" || iv->label == "m") && std::abs(toSeconds(iv->start) - w.start) <= 0.08;
			});
		}
	}
	std::sort(edges.begin(), edges.end());
	std::sort(nearest.begin(), nearest.end());
	const double median = nearest[nearest.size() / 2];
	std::printf("[ grid-s4 ] speech edges worst %.0f ms; word boundary to nearest recognised boundary median %.0f ms; bilabial-initial words %d/%d\n",
	            edges.back() * 1000, median * 1000, bilabials, bilabialWords);
	// Measured (D95): edges at most 160 ms off, median 10 ms, 4 of 9 bilabial-initial words.
	EXPECT_LE(edges.back(), 0.25);
	EXPECT_LE(median, 0.03);
	EXPECT_GE(bilabials, 3);
}

TEST(Recognize, theSameWhateverCameBeforeAndOnAnyNumberOfThreads) {
	const std::string a = kFaceDir + "/s4hq_bgim8s.mpg", b = kFaceDir + "/s4hq_pbbc4a.mpg";
	RecognizeOptions one;
	one.threads = 1;
	const Recognition first = recognizePhonesFile(a, one);
	recognizePhonesFile(b, one);
	EXPECT_TRUE(sameIntervals(first, recognizePhonesFile(a, one)));
	RecognizeOptions two;
	two.threads = 2;
	EXPECT_TRUE(sameIntervals(first, recognizePhonesFile(a, two)));
	// Two clips joined by a pause: each part is an utterance of its own; the first part as alone.
	const AudioClip ca = decodeAudio(a, 16000), cb = decodeAudio(b, 16000);
	AudioClip joined = ca;
	joined.samples.resize(joined.samples.size() / std::size_t(ca.channels), 0.f);
	joined.channels = 1;
	for (std::size_t i = 0; i < joined.samples.size(); ++i) {
		double s = 0;
		for (int c = 0; c < ca.channels; ++c) s += ca.samples[i * std::size_t(ca.channels) + std::size_t(c)];
		joined.samples[i] = float(s / ca.channels);
	}
	joined.samples.resize(joined.samples.size() + 16000, 0.f);
	for (std::size_t i = 0; i < cb.frameCount(); ++i) {
		double s = 0;
		for (int c = 0; c < cb.channels; ++c) s += cb.samples[i * std::size_t(cb.channels) + std::size_t(c)];
		joined.samples.push_back(float(s / cb.channels));
	}
	const Recognition both = recognizePhonesClip(joined, "joined", two);
	EXPECT_GE(both.utterances, 2);
	int phonesA = 0, phonesBoth = 0;
	for (const Interval& iv : first.phones.intervals) phonesA += !iv.label.empty();
	for (const Interval& iv : both.phones.intervals) phonesBoth += !iv.label.empty() && iv.end <= first.duration;
	EXPECT_NEAR(phonesBoth, phonesA, 2);
}

TEST(Recognize, aClipAtAnotherRateAndInStereoReadsAsTheFile) {
	const std::string path = kFaceDir + "/s4hq_lbaq3p.mpg";
	const Recognition file = recognizePhonesFile(path);
	const AudioClip stereo48 = decodeAudio(path, 48000);
	const Recognition clip = recognizePhonesClip(stereo48, "clip");
	EXPECT_EQ(clip.duration, stereo48.duration());
	EXPECT_LE(std::abs((clip.duration - file.duration).count()), kTicksPerSecond / 16000);
	std::string a, b;
	for (const Interval& iv : file.phones.intervals) a += iv.label + " ";
	for (const Interval& iv : clip.phones.intervals) b += iv.label + " ";
	// Resampled by another resampler: nearly the same phones.
	int same = 0, n = 0;
	for (const Interval& iv : file.phones.intervals) {
		if (iv.label.empty()) continue;
		++n;
		const Ticks mid = iv.start + (iv.end - iv.start) / 2;
		for (const Interval& jv : clip.phones.intervals)
			if (jv.start <= mid && mid < jv.end) same += jv.label == iv.label;
	}
	EXPECT_GE(double(same), 0.7 * n) << a << "\n" << b;
}

TEST(Recognize, silenceIsAStillFaceAndNothingIsAnError) {
	AudioClip silence;
	silence.sampleRate = 16000;
	silence.channels = 1;
	silence.samples.assign(32000, 0.f);
	const Recognition r = recognizePhonesClip(silence, "quiet.wav");
	ASSERT_EQ(r.phones.intervals.size(), 1u);
	EXPECT_TRUE(r.phones.intervals[0].label.empty());
	EXPECT_EQ(r.phones.intervals[0].end, r.duration);
	ASSERT_EQ(r.warnings.size(), 1u);
	EXPECT_NE(r.warnings[0].find("quiet.wav: no speech in the audio: it is silent"), std::string::npos) << r.warnings[0];
	AudioClip none = silence;
	none.samples.clear();
	EXPECT_NE(test::errorOf([&] { recognizePhonesClip(none, "none.wav"); }).find("none.wav: the audio has no samples"), std::string::npos);
	AudioClip tiny = silence;
	tiny.samples.assign(160, 0.1f);
	EXPECT_NE(test::errorOf([&] { recognizePhonesClip(tiny, "tiny.wav"); }).find("tiny.wav: the audio is shorter than 25 ms"), std::string::npos);
	EXPECT_NE(test::errorOf([&] { recognizePhonesFile("/nonexistent/a.wav"); }).find("/nonexistent/a.wav: no such file"), std::string::npos);
}

TEST(Recognize, aMissingModelNamesItsDebianPackage) {
	RecognizeOptions o;
	o.modelDir = test::tempDir("no-sphinx-model");
	const std::string e = test::errorOf([&] { recognizePhonesFile(kFaceDir + "/s4hq_bgim8s.mpg", o); });
	EXPECT_NE(e.find("pocketsphinx-en-us"), std::string::npos) << e;
	EXPECT_NE(e.find(o.modelDir), std::string::npos) << e;
}
