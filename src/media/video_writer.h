// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "base/frame_rate.h"
#include "image/image.h"
#include "image/yuv.h"
#include "media/audio.h"

namespace talkhead {

// Mp4: H.264 (libx264) + AAC. WebM: VP9 (libvpx, constant quality; with alpha when VideoOptions::alpha)
// + Vorbis (libvorbis: any sample rate, no resampling).
enum class VideoContainer { Mp4, WebM };

struct VideoOptions {
	int width = 1280, height = 720;
	FrameRate rate;               // frames per second, exact (30000/1001 allowed)
	int crf = 23;                 // constant quality: libx264's crf (0–51) or libvpx-vp9's (0–63)
	std::string preset = "veryfast";  // x264 preset (MP4 only)
	int threads = 0;              // encoder threads (0 = all cores)
	VideoContainer container = VideoContainer::Mp4;
	bool alpha = false;           // WebM only: VP9 with an alpha plane (YuvImage::a of every frame)
};

// H.264 (libx264, yuv420p) + AAC MP4 — or VP9 + Vorbis WebM, options.container — muxed in process with
// libav. Frames are 8-bit RGB or limited-range YUV 4:2:0 of the given size (with their alpha plane when
// options.alpha), written in order; the audio (optional) is encoded alongside, and what is left of it after
// the last frame is written by finish(). Writes to `path` directly: callers write to a temporary name and
// rename.
class Mp4Writer {
public:
	Mp4Writer(const std::string& path, const VideoOptions& options, const AudioClip* audio);
	// The audio pulled from a source as the video advances (the source must outlive the writer).
	Mp4Writer(const std::string& path, const VideoOptions& options, AudioSource* audio);
	~Mp4Writer();
	Mp4Writer(const Mp4Writer&) = delete;
	Mp4Writer& operator=(const Mp4Writer&) = delete;
	void write(const Image8& frame);
	void write(const YuvImage& frame);  // already converted (e.g. by worker threads)
	void finish();

private:
	struct Impl;
	std::unique_ptr<AudioSource> ownSource_;  // a clip's source (declared first: outlives the encoder)
	std::unique_ptr<Impl> impl_;
	void open(const std::string& path, const VideoOptions& options, AudioSource* audio);
};

// A live stream (talkhead serve): H.264 (x264, zerolatency) + AAC as fragmented MP4 for Media Source
// Extensions — an init segment (ftyp + empty moov), then a fragment (moof + mdat) per frame — handed to
// `write` as it is made (`write` returns false when its reader is gone: the next write throws). The audio
// is pulled up to each frame's end as frames are written.
class Mp4LiveWriter {
public:
	using Write = std::function<bool(const std::uint8_t* data, std::size_t size)>;
	Mp4LiveWriter(Write write, const VideoOptions& options, AudioSource* audio);
	~Mp4LiveWriter();
	Mp4LiveWriter(const Mp4LiveWriter&) = delete;
	Mp4LiveWriter& operator=(const Mp4LiveWriter&) = delete;
	// The codecs, RFC 6381 ("avc1.64001f,mp4a.40.2"): the MIME type is video/mp4; codecs="…".
	const std::string& codecs() const { return codecs_; }
	void write(const YuvImage& frame);  // limited range, the options' size
	void finish();

private:
	const struct AvModule* av_ = nullptr;
	void* encoder_ = nullptr;
	Write write_;
	std::string codecs_;
};

// Loads the libav plugin now instead of on first use: a long-running process (serve) does it before it
// takes connections, so that it never loads libraries when it may be out of file descriptors.
void loadVideoPlugin();

// YUV4MPEG2 stream (C420jpeg: chroma centred on its 2×2 block, as rgbToYuv420 makes it; BT.601 limited
// range, declared with XCOLORRANGE=LIMITED), e.g. to standard output for `| ffplay -`.
class Y4mWriter {
public:
	// `name`: the file's name for messages ("-" = standard output).
	Y4mWriter(std::FILE* out, const VideoOptions& options, std::string name = "-");
	void write(const Image8& frame);
	void write(const YuvImage& frame);  // limited range (YuvRange::Limited)

private:
	std::FILE* out_;
	VideoOptions o_;
	std::string name_;
	YuvImage yuv_;
	[[noreturn]] void fail() const;  // throws Error naming the file and errno's reason
};

}  // namespace talkhead
