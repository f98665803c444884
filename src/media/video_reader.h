// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "base/ticks.h"
#include "image/image.h"
#include "image/yuv.h"

namespace talkhead {

// What a video file holds (the first video stream).
struct VideoInfo {
	int width = 0, height = 0;
	int fpsNum = 0, fpsDen = 1;      // average frame rate (0/1 when the container does not say)
	Ticks duration{0};               // of the video stream (or the container), 0 when unknown
	std::int64_t frameCountHint = 0; // from the container; an estimate, 0 when unknown
	bool hasAudio = false;
};

// Decodes the frames of any video libav reads (MP4/H.264, MPEG-1/2, …) in order, as 8-bit RGB, through
// the libav plugin. Frame times come from the stream's timestamps (frame n of a constant-rate stream is at
// n / fps). Throws Error naming the file.
class VideoReader {
public:
	explicit VideoReader(const std::string& path);
	~VideoReader();
	VideoReader(const VideoReader&) = delete;
	VideoReader& operator=(const VideoReader&) = delete;

	const VideoInfo& info() const { return info_; }
	const std::string& path() const { return path_; }
	// The next frame (RGB, the video's size) and its time and 0-based index; false at the end.
	bool read(Image8& frame, Ticks& time, std::int64_t& index);
	// The same as YUV 4:2:0 planes: a 4:2:0 stream's (a y4m or H.264 file talkhead wrote) exactly as stored.
	bool readYuv(YuvImage& frame, Ticks& time, std::int64_t& index);

private:
	std::string path_;
	VideoInfo info_;
	void* handle_ = nullptr;
	std::int64_t next_ = 0;
};

}  // namespace talkhead
