// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/audio.h"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/plugin.h"
#include "media/av_module.h"

namespace talkhead {

AudioClip decodeAudio(const std::string& path, int sampleRate, double maxSeconds) {
	AudioClip clip;
	std::string error;
	if (!avModule().decodeAudio(path, sampleRate, maxSeconds, clip, error)) throw Error(error);
	return clip;
}

namespace {

class ClipSource final : public AudioSource {
public:
	explicit ClipSource(const AudioClip& c) : clip_(c) {}
	int sampleRate() const override { return clip_.sampleRate; }
	int channels() const override { return clip_.channels; }
	std::size_t read(float* out, std::size_t frames) override {
		const std::size_t n = std::min(frames, clip_.frameCount() - pos_);
		if (n == 0) return 0;  // an empty clip has no data() to copy from
		std::memcpy(out, clip_.samples.data() + pos_ * std::size_t(clip_.channels), n * std::size_t(clip_.channels) * sizeof(float));
		pos_ += n;
		return n;
	}

private:
	const AudioClip& clip_;
	std::size_t pos_ = 0;
};

class FileSource final : public AudioSource {
public:
	FileSource(const std::string& path, int rate, double maxSeconds) : av_(avModule()) {
		std::string error;
		handle_ = av_.openAudio(path, rate, maxSeconds, rate_, channels_, error);
		if (!handle_) throw Error(error);
	}
	~FileSource() override { av_.closeAudio(handle_); }
	int sampleRate() const override { return rate_; }
	int channels() const override { return channels_; }
	std::size_t read(float* out, std::size_t frames) override {
		std::string error;
		const long n = av_.readAudio(handle_, out, frames, error);
		if (n < 0) throw Error(error);
		return std::size_t(n);
	}

private:
	const AvModule& av_;
	void* handle_ = nullptr;
	int rate_ = 0, channels_ = 0;
};

}  // namespace

std::unique_ptr<AudioSource> clipSource(const AudioClip& clip) { return std::make_unique<ClipSource>(clip); }
std::unique_ptr<AudioSource> openAudioFile(const std::string& path, int sampleRate, double maxSeconds) {
	return std::make_unique<FileSource>(path, sampleRate, maxSeconds);
}

Ticks audioFileDuration(const std::string& path, int sampleRate) {
	auto src = openAudioFile(path, sampleRate);
	std::vector<float> block(std::size_t(8192) * std::size_t(src->channels()));
	std::int64_t frames = 0;
	for (std::size_t n; (n = src->read(block.data(), 8192)) > 0;) frames += std::int64_t(n);
	if (frames == 0) throw Error(path, 0, "the audio has no samples (zero length)");
	return Ticks(frames * (kTicksPerSecond / src->sampleRate()));
}

const AvModule& avModule() {
	static const auto* m = static_cast<const AvModule*>(loadPlugin("libtalkhead-av.so", "talkhead_av_module", kAvModuleAbi));
	return *m;
}

void writeWav(const std::string& path, const AudioClip& clip) {
	const std::uint32_t dataBytes = std::uint32_t(clip.samples.size() * 2);
	std::string b;
	b.reserve(44 + dataBytes);
	auto u32 = [&](std::uint32_t v) { b.append(reinterpret_cast<const char*>(&v), 4); };
	auto u16 = [&](std::uint16_t v) { b.append(reinterpret_cast<const char*>(&v), 2); };
	b += "RIFF";
	u32(36 + dataBytes);
	b += "WAVEfmt ";
	u32(16);
	u16(1);
	u16(std::uint16_t(clip.channels));
	u32(std::uint32_t(clip.sampleRate));
	u32(std::uint32_t(clip.sampleRate * clip.channels * 2));
	u16(std::uint16_t(clip.channels * 2));
	u16(16);
	b += "data";
	u32(dataBytes);
	for (float f : clip.samples) {
		const float c = f < -1.f ? -1.f : (f > 1.f ? 1.f : f);
		u16(std::uint16_t(std::int16_t(std::lround(c * 32767.f))));
	}
	writeFileAtomically(path, b);
}

namespace {
class ShiftedSource final : public AudioSource {
public:
	ShiftedSource(std::unique_ptr<AudioSource> inner, Ticks offset, Ticks total) : inner_(std::move(inner)) {
		const std::int64_t rate = inner_->sampleRate();
		auto frames = [&](Ticks t) {  // rounded to the nearest frame, either sign
			const __int128 q = __int128(t.count()) * rate;
			return std::int64_t(q >= 0 ? (q + kTicksPerSecond / 2) / kTicksPerSecond : -((-q + kTicksPerSecond / 2) / kTicksPerSecond));
		};
		silenceFirst_ = std::max<std::int64_t>(0, frames(offset));
		skip_ = std::max<std::int64_t>(0, -frames(offset));
		left_ = std::max<std::int64_t>(0, frames(total));
	}
	int sampleRate() const override { return inner_->sampleRate(); }
	int channels() const override { return inner_->channels(); }
	std::size_t read(float* out, std::size_t frames) override {
		const std::size_t ch = std::size_t(channels());
		std::size_t done = 0;
		while (skip_ > 0) {  // a negative offset: the inner source's first samples go
			std::vector<float> drop(std::size_t(std::min<std::int64_t>(skip_, 4096)) * ch);
			const std::size_t n = inner_->read(drop.data(), drop.size() / ch);
			if (n == 0) {
				skip_ = 0;
				innerDone_ = true;
				break;
			}
			skip_ -= std::int64_t(n);
		}
		while (done < frames && left_ > 0) {
			std::size_t want = std::min<std::size_t>(frames - done, std::size_t(left_));
			std::size_t got = 0;
			if (silenceFirst_ > 0) {
				got = std::min<std::size_t>(want, std::size_t(silenceFirst_));
				std::fill(out + done * ch, out + (done + got) * ch, 0.f);
				silenceFirst_ -= std::int64_t(got);
			} else if (!innerDone_) {
				got = inner_->read(out + done * ch, want);
				if (got == 0) innerDone_ = true;
			} else {
				got = want;  // silence to the end
				std::fill(out + done * ch, out + (done + got) * ch, 0.f);
			}
			done += got;
			left_ -= std::int64_t(got);
		}
		return done;
	}

private:
	std::unique_ptr<AudioSource> inner_;
	std::int64_t silenceFirst_ = 0, skip_ = 0, left_ = 0;
	bool innerDone_ = false;
};
}  // namespace

std::unique_ptr<AudioSource> borrowedSource(AudioSource& inner) {
	class Borrowed : public AudioSource {
	public:
		explicit Borrowed(AudioSource& s) : s_(s) {}
		int sampleRate() const override { return s_.sampleRate(); }
		int channels() const override { return s_.channels(); }
		std::size_t read(float* out, std::size_t frames) override { return s_.read(out, frames); }

	private:
		AudioSource& s_;
	};
	return std::make_unique<Borrowed>(inner);
}

std::unique_ptr<AudioSource> shiftedSource(std::unique_ptr<AudioSource> inner, Ticks offset, Ticks total) {
	return std::make_unique<ShiftedSource>(std::move(inner), offset, total);
}

}  // namespace talkhead
