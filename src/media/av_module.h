// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The libav plugin: libavformat/libavcodec and the ~130 shared libraries they pull in cost ~60 ms of
// start-up, so decoding audio and writing MP4 live in libtalkhead-av.so, loaded on first use; a y4m
// stream (say … --format y4m -o -) never loads it. Built from the same tree with the same compiler, so
// C++ types cross the boundary; errors come back as strings (the full "PATH: what" message).
#include <cstdint>
#include <functional>
#include <string>

#include "image/yuv.h"
#include "media/audio.h"
#include "media/video_reader.h"
#include "media/video_writer.h"

namespace talkhead {

// 4: audio streamed (openAudio/readAudio, Mp4 takes an AudioSource); 5: readVideoYuv; 6: openMp4Live;
// 7: VideoOptions::container and alpha (WebM, VP9 with alpha); 8: decodeAudio/openAudio take a length limit
constexpr int kAvModuleAbi = 8;

struct AvModule {
	int abi;  // kAvModuleAbi
	// maxSeconds: the longest audio taken (refused from the container's declared length before decoding,
	// and counted as samples come).
	bool (*decodeAudio)(const std::string& path, int sampleRate, double maxSeconds, AudioClip& out, std::string& error);
	// An MP4 encoder (opaque), or nullptr with `error` set.
	// An audio decoder (opaque) that resamples to `sampleRate` (at most 2 channels), or nullptr with `error`.
	void* (*openAudio)(const std::string& path, int sampleRate, double maxSeconds, int& rate, int& channels, std::string& error);
	// Up to `frames` interleaved sample frames; 0 at the end, −1 on error.
	long (*readAudio)(void* decoder, float* out, std::size_t frames, std::string& error);
	void (*closeAudio)(void* decoder);
	// The audio (optional) is pulled from `audio` as the video advances.
	void* (*openMp4)(const std::string& path, const VideoOptions& options, AudioSource* audio, std::string& error);
	bool (*writeMp4)(void* encoder, const YuvImage& frame, std::string& error);
	bool (*finishMp4)(void* encoder, std::string& error);
	void (*closeMp4)(void* encoder);
	// A video decoder (opaque) with the stream's info, or nullptr with `error` set.
	void* (*openVideo)(const std::string& path, VideoInfo& info, std::string& error);
	// The next frame as RGB (resized to info's size) with its time in seconds; 0 at the end, −1 on error.
	int (*readVideo)(void* decoder, Image8& rgb, double& seconds, std::string& error);
	void (*closeVideo)(void* decoder);
	// The next frame as YUV 4:2:0 planes (copied as they are from a 4:2:0 stream of the info's size,
	// converted otherwise); 0 at the end, −1 on error.
	int (*readVideoYuv)(void* decoder, YuvImage& yuv, double& seconds, std::string& error);
	// A live fragmented MP4 encoder (Mp4LiveWriter): the bytes go to `write` as they are made; `codecs` gets
	// the RFC 6381 codec string. writeMp4/finishMp4/closeMp4 as for openMp4.
	void* (*openMp4Live)(const std::function<bool(const std::uint8_t*, std::size_t)>& write, const VideoOptions& options, AudioSource* audio,
	                     std::string& codecs, std::string& error);
};

// The loaded plugin (throws Error when it cannot be loaded).
const AvModule& avModule();

}  // namespace talkhead

extern "C" const void* talkhead_av_module();
