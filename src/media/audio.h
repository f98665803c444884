// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

#include "base/ticks.h"

namespace talkhead {

// Decoded audio: interleaved float samples in [−1, 1].
struct AudioClip {
	int sampleRate = 0;
	int channels = 0;
	std::vector<float> samples;  // frames × channels

	std::size_t frameCount() const { return channels ? samples.size() / std::size_t(channels) : 0; }
	Ticks duration() const { return sampleRate ? Ticks(std::int64_t(frameCount()) * (kTicksPerSecond / sampleRate)) : Ticks(0); }
};

// Decodes any audio libav reads (WAV, MP3, MP2 in MPEG, AAC, …): the first audio stream, resampled to
// `sampleRate` with at most 2 channels. Throws Error naming the file; zero-length audio is an error.
AudioClip decodeAudio(const std::string& path, int sampleRate = 48000);

// Writes a 16-bit PCM WAV through a temporary name (renamed when complete).
void writeWav(const std::string& path, const AudioClip& clip);

}  // namespace talkhead
