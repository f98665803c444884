// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstddef>
#include <memory>
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

// The longest audio read unless a caller says otherwise (a server says its own limit).
constexpr double kMaxAudioSeconds = 4 * 3600;

// Decodes any audio libav reads (WAV, MP3, MP2 in MPEG, AAC, …): the first audio stream, resampled to
// `sampleRate` with at most 2 channels. Throws Error naming the file; zero-length audio is an error, and
// so is audio longer than maxSeconds — refused from the container's declared length before decoding
// when it declares one, else as soon as the samples counted pass it, so memory stays bounded by the
// limit, not by what a small file can expand to (issue 45).
AudioClip decodeAudio(const std::string& path, int sampleRate = 48000, double maxSeconds = kMaxAudioSeconds);

// Audio read in order a block at a time: a clip in memory, or a file decoded as it is read (so a render's
// memory does not grow with the audio's length).
class AudioSource {
public:
	virtual ~AudioSource() = default;
	virtual int sampleRate() const = 0;
	virtual int channels() const = 0;
	// Up to `frames` sample frames (interleaved) into `out`; fewer only at the end, 0 after it.
	virtual std::size_t read(float* out, std::size_t frames) = 0;
};
// A source over a clip (which must outlive it).
std::unique_ptr<AudioSource> clipSource(const AudioClip& clip);
// A source decoding `path` as it is read (same decoding and limit as decodeAudio; sampleRate 0 keeps the
// file's own rate). Throws Error naming the file.
std::unique_ptr<AudioSource> openAudioFile(const std::string& path, int sampleRate = 48000, double maxSeconds = kMaxAudioSeconds);
// `inner` shifted by `offset` (positive: that much silence first; negative: its first samples dropped),
// then silence, `total` long in all (issue 14: lead-in, tail and audio-visual offset of stimuli).
std::unique_ptr<AudioSource> shiftedSource(std::unique_ptr<AudioSource> inner, Ticks offset, Ticks total);
// A source reading `inner` (which must outlive it), e.g. to bound a never-ending one with shiftedSource.
std::unique_ptr<AudioSource> borrowedSource(AudioSource& inner);
// The exact duration of an audio file, decoded once without keeping the samples (memory stays flat).
// Zero-length audio is an error, as for decodeAudio.
Ticks audioFileDuration(const std::string& path, int sampleRate = 48000);

// Writes a 16-bit PCM WAV through a temporary name (renamed when complete).
void writeWav(const std::string& path, const AudioClip& clip);

}  // namespace talkhead
