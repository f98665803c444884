// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/video_reader.h"

#include <cmath>

#include "base/error.h"
#include "media/av_module.h"

namespace talkhead {

VideoReader::VideoReader(const std::string& path) : path_(path) {
	std::string error;
	handle_ = avModule().openVideo(path, info_, error);
	if (!handle_) throw Error(error);
}

VideoReader::~VideoReader() {
	if (handle_) avModule().closeVideo(handle_);
}

namespace {
// One decoded frame through a plugin entry (RGB or YUV): false at the end, Error on failure.
template <class Frame, class Entry>
bool readWith(void* handle, Entry entry, Frame& frame, Ticks& time, std::int64_t& index, std::int64_t& next) {
	std::string error;
	double seconds = 0;
	const int r = entry(handle, frame, seconds, error);
	if (r < 0) throw Error(error);
	if (r == 0) return false;
	time = ticksFromSeconds(seconds);
	index = next++;
	return true;
}
}  // namespace

bool VideoReader::read(Image8& frame, Ticks& time, std::int64_t& index) { return readWith(handle_, avModule().readVideo, frame, time, index, next_); }

bool VideoReader::readYuv(YuvImage& frame, Ticks& time, std::int64_t& index) {
	frame.resize(info_.width, info_.height);
	return readWith(handle_, avModule().readVideoYuv, frame, time, index, next_);
}

}  // namespace talkhead
