// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/video_writer.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/channel_layout.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
}

#include <algorithm>
#include <cstring>

#include "media/av_util.h"

namespace talkhead {

struct Mp4Writer::Impl {
	std::string path;
	VideoOptions o;
	const AudioClip* audio = nullptr;
	AVFormatContext* fmt = nullptr;
	AVCodecContext* venc = nullptr;
	AVCodecContext* aenc = nullptr;
	AVStream* vst = nullptr;
	AVStream* ast = nullptr;
	AVFrame* vframe = nullptr;
	AVFrame* aframe = nullptr;
	AVPacket* pkt = nullptr;
	YuvImage rgbFrame;  // write(Image8): the converted frame
	std::int64_t frameIndex = 0;
	std::int64_t audioPos = 0;  // next audio sample frame to encode
	bool finished = false;

	void open() {
		checkAv(avformat_alloc_output_context2(&fmt, nullptr, "mp4", path.c_str()), path, "cannot create the MP4 muxer");
		const AVCodec* h264 = avcodec_find_encoder_by_name("libx264");
		if (!h264) throw Error(path, 0, "this libav has no libx264 encoder");
		vst = avformat_new_stream(fmt, nullptr);
		venc = avcodec_alloc_context3(h264);
		venc->width = o.width;
		venc->height = o.height;
		venc->pix_fmt = AV_PIX_FMT_YUV420P;
		venc->time_base = AVRational{o.fpsDen, o.fpsNum};
		venc->framerate = AVRational{o.fpsNum, o.fpsDen};
		venc->gop_size = 10 * o.fpsNum / std::max(1, o.fpsDen);
		venc->thread_count = o.threads;
		if (fmt->oformat->flags & AVFMT_GLOBALHEADER) venc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
		av_opt_set(venc->priv_data, "preset", o.preset.c_str(), 0);
		av_opt_set(venc->priv_data, "crf", std::to_string(o.crf).c_str(), 0);
		checkAv(avcodec_open2(venc, h264, nullptr), path, "cannot open the H.264 encoder");
		checkAv(avcodec_parameters_from_context(vst->codecpar, venc), path, "H.264 parameters");
		vst->time_base = venc->time_base;
		vst->avg_frame_rate = venc->framerate;

		if (audio) {
			const AVCodec* aac = avcodec_find_encoder(AV_CODEC_ID_AAC);
			if (!aac) throw Error(path, 0, "this libav has no AAC encoder");
			ast = avformat_new_stream(fmt, nullptr);
			aenc = avcodec_alloc_context3(aac);
			aenc->sample_fmt = AV_SAMPLE_FMT_FLTP;
			aenc->sample_rate = audio->sampleRate;
			av_channel_layout_default(&aenc->ch_layout, audio->channels);
			aenc->bit_rate = 128000;
			aenc->time_base = AVRational{1, audio->sampleRate};
			if (fmt->oformat->flags & AVFMT_GLOBALHEADER) aenc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
			checkAv(avcodec_open2(aenc, aac, nullptr), path, "cannot open the AAC encoder");
			checkAv(avcodec_parameters_from_context(ast->codecpar, aenc), path, "AAC parameters");
			ast->time_base = aenc->time_base;
			aframe = av_frame_alloc();
			aframe->format = AV_SAMPLE_FMT_FLTP;
			aframe->sample_rate = audio->sampleRate;
			av_channel_layout_copy(&aframe->ch_layout, &aenc->ch_layout);
			aframe->nb_samples = aenc->frame_size;
			checkAv(av_frame_get_buffer(aframe, 0), path, "audio frame");
		}
		checkAv(avio_open(&fmt->pb, path.c_str(), AVIO_FLAG_WRITE), path, "cannot write the video");
		AVDictionary* opts = nullptr;
		av_dict_set(&opts, "movflags", "+faststart", 0);
		fmt->flags |= AVFMT_FLAG_BITEXACT;  // no library version strings: the same input gives the same file
		const int r = avformat_write_header(fmt, &opts);
		av_dict_free(&opts);
		checkAv(r, path, "cannot write the MP4 header");
		vframe = av_frame_alloc();
		vframe->format = AV_PIX_FMT_YUV420P;
		vframe->width = o.width;
		vframe->height = o.height;
		checkAv(av_frame_get_buffer(vframe, 0), path, "video frame");
		pkt = av_packet_alloc();
	}

	void drain(AVCodecContext* enc, AVStream* st) {
		for (;;) {
			int r = avcodec_receive_packet(enc, pkt);
			if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
			checkAv(r, path, "encoding failed");
			av_packet_rescale_ts(pkt, enc->time_base, st->time_base);
			pkt->stream_index = st->index;
			checkAv(av_interleaved_write_frame(fmt, pkt), path, "cannot write the video");
		}
	}

	// Encodes audio up to sample frame `until` (whole AAC frames; the rest waits), or everything (flush).
	void encodeAudio(std::int64_t until, bool all) {
		if (!audio) return;
		const std::int64_t total = std::int64_t(audio->frameCount());
		const int n = aenc->frame_size;
		until = std::min(until, total);
		while (audioPos < total && (all || audioPos + n <= until)) {
			checkAv(av_frame_make_writable(aframe), path, "audio frame");
			const int count = int(std::min<std::int64_t>(n, total - audioPos));
			for (int c = 0; c < audio->channels; ++c) {
				float* dst = reinterpret_cast<float*>(aframe->data[c]);
				for (int k = 0; k < n; ++k)
					dst[k] = k < count ? audio->samples[std::size_t((audioPos + k) * audio->channels + c)] : 0.f;
			}
			aframe->nb_samples = count == n ? n : count;
			aframe->pts = audioPos;
			checkAv(avcodec_send_frame(aenc, aframe), path, "AAC encoding failed");
			drain(aenc, ast);
			audioPos += count;
			aframe->nb_samples = n;
		}
	}

	void write(const Image8& img) {
		if (img.width != o.width || img.height != o.height || img.channels != 3) throw std::logic_error("Mp4Writer: frame size differs");
		rgbToYuv420(img, rgbFrame, YuvRange::Limited);
		writeYuv(rgbFrame);
	}

	void writeYuv(const YuvImage& img) {
		if (img.width != o.width || img.height != o.height) throw std::logic_error("Mp4Writer: frame size differs");
		checkAv(av_frame_make_writable(vframe), path, "video frame");
		const int cw = (o.width + 1) / 2, ch = (o.height + 1) / 2;
		for (int y = 0; y < o.height; ++y) std::memcpy(vframe->data[0] + std::size_t(y) * vframe->linesize[0], img.y.data() + std::size_t(y) * o.width, std::size_t(o.width));
		for (int y = 0; y < ch; ++y) {
			std::memcpy(vframe->data[1] + std::size_t(y) * vframe->linesize[1], img.u.data() + std::size_t(y) * cw, std::size_t(cw));
			std::memcpy(vframe->data[2] + std::size_t(y) * vframe->linesize[2], img.v.data() + std::size_t(y) * cw, std::size_t(cw));
		}
		vframe->pts = frameIndex++;
		checkAv(avcodec_send_frame(venc, vframe), path, "H.264 encoding failed");
		drain(venc, vst);
		if (audio) encodeAudio(av_rescale_q(frameIndex, AVRational{o.fpsDen, o.fpsNum}, AVRational{1, audio->sampleRate}), false);
	}

	void finish() {
		if (finished) return;
		finished = true;
		checkAv(avcodec_send_frame(venc, nullptr), path, "H.264 flush");
		drain(venc, vst);
		if (audio) {
			encodeAudio(0, true);
			checkAv(avcodec_send_frame(aenc, nullptr), path, "AAC flush");
			drain(aenc, ast);
		}
		checkAv(av_write_trailer(fmt), path, "cannot finish the MP4");
		checkAv(avio_closep(&fmt->pb), path, "cannot close the video file");
	}

	~Impl() {
		av_packet_free(&pkt);
		av_frame_free(&vframe);
		av_frame_free(&aframe);
		avcodec_free_context(&venc);
		avcodec_free_context(&aenc);
		if (fmt) {
			if (fmt->pb) avio_closep(&fmt->pb);
			avformat_free_context(fmt);
		}
	}
};

Mp4Writer::Mp4Writer(const std::string& path, const VideoOptions& o, const AudioClip* audio) : impl_(std::make_unique<Impl>()) {
	if (o.width < 16 || o.height < 16 || o.width > 7680 || o.height > 4320 || o.width % 2 || o.height % 2)
		throw Error(path, 0, "unsupported video size " + std::to_string(o.width) + "x" + std::to_string(o.height) + " (even, 16–7680 x 16–4320)");
	impl_->path = path;
	impl_->o = o;
	impl_->audio = audio && audio->frameCount() ? audio : nullptr;
	av_log_set_level(AV_LOG_ERROR);
	impl_->open();
}

Mp4Writer::~Mp4Writer() = default;
void Mp4Writer::write(const Image8& frame) { impl_->write(frame); }
void Mp4Writer::write(const YuvImage& frame) { impl_->writeYuv(frame); }

void Mp4Writer::finish() { impl_->finish(); }

Y4mWriter::Y4mWriter(std::FILE* out, const VideoOptions& o) : out_(out), o_(o) {
	std::fprintf(out_, "YUV4MPEG2 W%d H%d F%d:%d Ip A1:1 C420jpeg\n", o.width, o.height, o.fpsNum, o.fpsDen);
}

void Y4mWriter::write(const Image8& img) {
	rgbToYuv420(img, yuv_, YuvRange::Full);
	write(yuv_);
}

void Y4mWriter::write(const YuvImage& f) {
	if (f.width != o_.width || f.height != o_.height) throw std::logic_error("Y4mWriter: frame size differs");
	std::fputs("FRAME\n", out_);
	if (std::fwrite(f.y.data(), 1, f.y.size(), out_) != f.y.size() || std::fwrite(f.u.data(), 1, f.u.size(), out_) != f.u.size() ||
	    std::fwrite(f.v.data(), 1, f.v.size(), out_) != f.v.size())
		throw Error("-", 0, "cannot write the y4m stream (closed pipe?)");
	std::fflush(out_);
}

}  // namespace talkhead
