// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/audio.h"


#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/plugin.h"
#include "media/av_module.h"

namespace talkhead {

AudioClip decodeAudio(const std::string& path, int sampleRate) {
	AudioClip clip;
	std::string error;
	if (!avModule().decodeAudio(path, sampleRate, clip, error)) throw Error(error);
	return clip;
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

}  // namespace talkhead
