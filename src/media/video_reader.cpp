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

bool VideoReader::read(Image8& frame, Ticks& time, std::int64_t& index) {
	std::string error;
	double seconds = 0;
	const int r = avModule().readVideo(handle_, frame, seconds, error);
	if (r < 0) throw Error(error);
	if (r == 0) return false;
	time = ticksFromSeconds(seconds);
	index = next_++;
	return true;
}

bool VideoReader::readYuv(YuvImage& frame, Ticks& time, std::int64_t& index) {
	std::string error;
	double seconds = 0;
	frame.resize(info_.width, info_.height);
	const int r = avModule().readVideoYuv(handle_, frame, seconds, error);
	if (r < 0) throw Error(error);
	if (r == 0) return false;
	time = ticksFromSeconds(seconds);
	index = next_++;
	return true;
}

}  // namespace talkhead
