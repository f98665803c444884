// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/video_writer.h"

#include <cerrno>
#include <cstring>


#include <algorithm>
#include <cstring>

#include "base/error.h"
#include "media/av_module.h"

namespace talkhead {

struct Mp4Writer::Impl {
	const AvModule* av = nullptr;
	void* encoder = nullptr;
	YuvImage rgbFrame;  // write(Image8): the converted frame
	int width = 0, height = 0;
	~Impl() {
		if (encoder) av->closeMp4(encoder);
	}
};

namespace {
void checkSize(const std::string& path, const VideoOptions& o) {
	if (o.width < 16 || o.height < 16 || o.width > 7680 || o.height > 4320 || o.width % 2 || o.height % 2)
		throw Error(path, 0, "unsupported video size " + std::to_string(o.width) + "x" + std::to_string(o.height) + " (even, 16–7680 x 16–4320)");
}
}  // namespace

Mp4Writer::Mp4Writer(const std::string& path, const VideoOptions& o, const AudioClip* audio) : impl_(std::make_unique<Impl>()) {
	if (audio && audio->frameCount() > 0) ownSource_ = clipSource(*audio);
	open(path, o, ownSource_.get());
}

Mp4Writer::Mp4Writer(const std::string& path, const VideoOptions& o, AudioSource* audio) : impl_(std::make_unique<Impl>()) { open(path, o, audio); }

void Mp4Writer::open(const std::string& path, const VideoOptions& o, AudioSource* audio) {
	checkSize(path, o);
	impl_->av = &avModule();
	impl_->width = o.width;
	impl_->height = o.height;
	std::string error;
	impl_->encoder = impl_->av->openMp4(path, o, audio, error);
	if (!impl_->encoder) throw Error(error);
}

Mp4Writer::~Mp4Writer() = default;
void Mp4Writer::write(const Image8& frame) {
	if (frame.width != impl_->width || frame.height != impl_->height || frame.channels != 3) throw std::logic_error("Mp4Writer: frame size differs");
	rgbToYuv420(frame, impl_->rgbFrame, YuvRange::Limited);
	write(impl_->rgbFrame);
}

void Mp4Writer::write(const YuvImage& frame) {
	std::string error;
	if (!impl_->av->writeMp4(impl_->encoder, frame, error)) throw Error(error);
}

void Mp4Writer::finish() {
	std::string error;
	if (!impl_->av->finishMp4(impl_->encoder, error)) throw Error(error);
}

void loadVideoPlugin() { avModule(); }

Mp4LiveWriter::Mp4LiveWriter(Write write, const VideoOptions& o, AudioSource* audio) : write_(std::move(write)) {
	checkSize("live stream", o);
	av_ = &avModule();
	std::string error;
	encoder_ = av_->openMp4Live(write_, o, audio, codecs_, error);
	if (!encoder_) throw Error(error);
}

Mp4LiveWriter::~Mp4LiveWriter() {
	if (encoder_) av_->closeMp4(encoder_);
}

void Mp4LiveWriter::write(const YuvImage& frame) {
	std::string error;
	if (!av_->writeMp4(encoder_, frame, error)) throw Error(error);
}

void Mp4LiveWriter::finish() {
	std::string error;
	if (!av_->finishMp4(encoder_, error)) throw Error(error);
}

Y4mWriter::Y4mWriter(std::FILE* out, const VideoOptions& o, std::string name) : out_(out), o_(o), name_(std::move(name)) {
	if (std::fprintf(out_, "YUV4MPEG2 W%d H%d F%d:%d Ip A1:1 C420jpeg XCOLORRANGE=LIMITED\n", o.width, o.height, o.rate.num, o.rate.den) < 0) fail();
}

void Y4mWriter::fail() const {
	const int e = errno;
	if (name_ == "-")
		throw Error(e == EPIPE ? "standard output: the reader closed the pipe; y4m stream stopped" : std::string("standard output: cannot write the y4m stream: ") + std::strerror(e));
	throw Error(name_, 0, std::string("cannot write: ") + std::strerror(e));
}

void Y4mWriter::write(const Image8& img) {
	rgbToYuv420(img, yuv_, YuvRange::Limited);
	write(yuv_);
}

void Y4mWriter::write(const YuvImage& f) {
	if (f.width != o_.width || f.height != o_.height) throw std::logic_error("Y4mWriter: frame size differs");
	errno = 0;
	if (std::fputs("FRAME\n", out_) < 0 || std::fwrite(f.y.data(), 1, f.y.size(), out_) != f.y.size() ||
	    std::fwrite(f.u.data(), 1, f.u.size(), out_) != f.u.size() || std::fwrite(f.v.data(), 1, f.v.size(), out_) != f.v.size() || std::fflush(out_) != 0)
		fail();
}

}  // namespace talkhead
