// SPDX-License-Identifier: GPL-3.0-or-later
// The media module's audio (issue 30: it had no tests of its own): a WAV written and decoded back through
// the libav plugin (samples, rate, duration), resampling, shifted sources for stimuli, and errors that
// name the file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "base/error.h"
#include "media/audio.h"
#include "test_support.h"

using namespace talkhead;
using talkhead::test::errorOf;

namespace {
AudioClip tone(int rate, double seconds, double hz) {
	AudioClip c;
	c.sampleRate = rate;
	c.channels = 1;
	for (int i = 0; i < int(rate * seconds); ++i) c.samples.push_back(float(0.5 * std::sin(2 * M_PI * hz * i / rate)));
	return c;
}
std::string tempPath(const std::string& name) { return (std::filesystem::temp_directory_path() / ("talkhead-audio-test-" + name)).string(); }
}  // namespace

TEST(Audio, aWavComesBackAsWritten) {
	const std::string path = tempPath("tone.wav");
	const AudioClip written = tone(16000, 0.5, 440);
	writeWav(path, written);
	const AudioClip read = decodeAudio(path, 16000);
	EXPECT_EQ(read.sampleRate, 16000);
	EXPECT_EQ(read.channels, 1);
	ASSERT_EQ(read.frameCount(), written.frameCount());
	double worst = 0;
	for (std::size_t i = 0; i < read.samples.size(); ++i) worst = std::max(worst, double(std::fabs(read.samples[i] - written.samples[i])));
	EXPECT_LT(worst, 1.0 / 16384);  // 16-bit quantisation
	EXPECT_EQ(audioFileDuration(path, 0), ticksFromSeconds(0.5));
	// Resampled to 48 kHz: three times the frames, the same duration.
	const AudioClip up = decodeAudio(path, 48000);
	EXPECT_NEAR(double(up.frameCount()), 3.0 * written.frameCount(), 64);
	std::filesystem::remove(path);
}

TEST(Audio, shiftedSourcesPadAndTrimWithSilence) {
	const AudioClip c = tone(1000, 1.0, 50);
	auto shifted = shiftedSource(clipSource(c), ticksFromSeconds(0.25), ticksFromSeconds(1.5));
	std::vector<float> out(2000, 1.f);
	const std::size_t n = shifted->read(out.data(), out.size());
	ASSERT_EQ(n, 1500u);
	for (std::size_t i = 0; i < 250; ++i) EXPECT_EQ(out[i], 0.f) << i;
	EXPECT_EQ(out[250], c.samples[0]);
	EXPECT_EQ(out[1249], c.samples[999]);
	EXPECT_EQ(out[1300], 0.f);
	auto early = shiftedSource(clipSource(c), ticksFromSeconds(-0.5), ticksFromSeconds(1.0));
	ASSERT_EQ(early->read(out.data(), out.size()), 1000u);
	EXPECT_EQ(out[0], c.samples[500]);
	EXPECT_EQ(out[600], 0.f);
}

TEST(Audio, badFilesAreErrorsNamingThem) {
	const std::string empty = tempPath("empty.wav");
	writeWav(empty, AudioClip{16000, 1, {}});
	EXPECT_NE(errorOf([&] { decodeAudio(empty); }).find(empty), std::string::npos);
	const std::string junk = tempPath("junk.wav");
	std::ofstream(junk) << "not audio at all";
	const std::string e = errorOf([&] { decodeAudio(junk); });
	EXPECT_NE(e.find(junk), std::string::npos) << e;
	EXPECT_NE(errorOf([] { decodeAudio("/nonexistent/x.wav"); }).find("/nonexistent/x.wav"), std::string::npos);
	std::filesystem::remove(empty);
	std::filesystem::remove(junk);
}

// Issue 45: a length limit refuses long audio from the declared length before decoding, and, where the
// length is not declared (a streamed WAV: sizes 0xFFFFFFFF), as soon as the samples counted pass it.
TEST(Audio, audioLongerThanTheLimitIsRefused) {
	const std::string path = tempPath("three-seconds.wav");
	writeWav(path, tone(8000, 3.0, 300));
	EXPECT_EQ(decodeAudio(path, 8000, 5.0).frameCount(), 24000u);
	const std::string declared = errorOf([&] { decodeAudio(path, 8000, 1.0); });
	EXPECT_NE(declared.find(path + ": lasts 3.0 s (as its header says), longer than the 1 s allowed"), std::string::npos) << declared;
	EXPECT_NE(errorOf([&] { openAudioFile(path, 8000, 2.0); }).find("longer than the 2 s allowed"), std::string::npos);
	// The same samples with the sizes of a WAV written as a stream: nothing declared, so counted.
	std::string bytes;
	{
		std::ifstream in(path, std::ios::binary);
		bytes.assign(std::istreambuf_iterator<char>(in), {});
	}
	const std::size_t data = bytes.find("data");
	ASSERT_NE(data, std::string::npos);
	for (std::size_t at : {std::size_t(4), data + 4}) bytes.replace(at, 4, "\xff\xff\xff\xff", 4);
	const std::string streamed = tempPath("streamed.wav");
	std::ofstream(streamed, std::ios::binary) << bytes;
	EXPECT_EQ(decodeAudio(streamed, 8000, 5.0).frameCount(), 24000u);
	const std::string counted = errorOf([&] { decodeAudio(streamed, 8000, 1.0); });
	EXPECT_NE(counted.find(streamed + ": lasts longer than the 1 s allowed"), std::string::npos) << counted;
	auto source = openAudioFile(streamed, 8000, 1.0);
	std::vector<float> block(4000);
	EXPECT_NE(errorOf([&] {
		          while (source->read(block.data(), 4000) > 0) {
		          }
	          }).find("longer than the 1 s allowed"),
	          std::string::npos);
	std::filesystem::remove(path);
	std::filesystem::remove(streamed);
}
