// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/audio.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/channel_layout.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswresample/swresample.h>
}

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "media/av_util.h"

namespace talkhead {

AudioClip decodeAudio(const std::string& path, int outRate) {
	if (!std::filesystem::exists(path)) throw Error(path, 0, "audio file not found");
	av_log_set_level(AV_LOG_FATAL);  // problems are reported through return codes, as one error line
	AVFormatContext* fmt = nullptr;
	checkAv(avformat_open_input(&fmt, path.c_str(), nullptr, nullptr), path, "cannot open audio");
	struct FmtGuard {
		AVFormatContext*& f;
		~FmtGuard() { avformat_close_input(&f); }
	} fg{fmt};
	checkAv(avformat_find_stream_info(fmt, nullptr), path, "cannot read audio stream info");
	const AVCodec* dec = nullptr;
	int stream = av_find_best_stream(fmt, AVMEDIA_TYPE_AUDIO, -1, -1, &dec, 0);
	if (stream < 0 || !dec) throw Error(path, 0, "no audio stream");
	AVCodecContext* ctx = avcodec_alloc_context3(dec);
	struct CtxGuard {
		AVCodecContext*& c;
		~CtxGuard() { avcodec_free_context(&c); }
	} cg{ctx};
	checkAv(avcodec_parameters_to_context(ctx, fmt->streams[stream]->codecpar), path, "bad audio parameters");
	checkAv(avcodec_open2(ctx, dec, nullptr), path, "cannot open the audio decoder");
	if (ctx->ch_layout.nb_channels <= 0) av_channel_layout_default(&ctx->ch_layout, 1);
	const int outChannels = std::min(2, ctx->ch_layout.nb_channels);
	AVChannelLayout outLayout;
	av_channel_layout_default(&outLayout, outChannels);
	SwrContext* swr = nullptr;
	checkAv(swr_alloc_set_opts2(&swr, &outLayout, AV_SAMPLE_FMT_FLT, outRate, &ctx->ch_layout, ctx->sample_fmt, ctx->sample_rate, 0, nullptr), path,
	        "cannot set up resampling");
	struct SwrGuard {
		SwrContext*& s;
		~SwrGuard() { swr_free(&s); }
	} sg{swr};
	checkAv(swr_init(swr), path, "cannot set up resampling");
	AudioClip clip;
	clip.sampleRate = outRate;
	clip.channels = outChannels;
	AVPacket* pkt = av_packet_alloc();
	AVFrame* frame = av_frame_alloc();
	struct Guard {
		AVPacket*& p;
		AVFrame*& f;
		~Guard() {
			av_packet_free(&p);
			av_frame_free(&f);
		}
	} g{pkt, frame};
	auto drain = [&]() {
		for (;;) {
			int r = avcodec_receive_frame(ctx, frame);
			if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
			checkAv(r, path, "cannot decode audio");
			const int maxOut = swr_get_out_samples(swr, frame->nb_samples);
			const std::size_t old = clip.samples.size();
			clip.samples.resize(old + std::size_t(maxOut) * outChannels);
			uint8_t* out[1] = {reinterpret_cast<uint8_t*>(clip.samples.data() + old)};
			const int got = checkAv(swr_convert(swr, out, maxOut, const_cast<const uint8_t**>(frame->extended_data), frame->nb_samples), path,
			                        "cannot resample audio");
			clip.samples.resize(old + std::size_t(got) * outChannels);
			av_frame_unref(frame);
			if (clip.samples.size() > std::size_t(outRate) * outChannels * 4 * 3600) throw Error(path, 0, "audio longer than 4 hours");
		}
	};
	while (av_read_frame(fmt, pkt) >= 0) {
		if (pkt->stream_index == stream) {
			int r = avcodec_send_packet(ctx, pkt);
			if (r < 0 && r != AVERROR(EAGAIN) && r != AVERROR_INVALIDDATA) checkAv(r, path, "cannot decode audio");
			drain();
		}
		av_packet_unref(pkt);
	}
	avcodec_send_packet(ctx, nullptr);
	drain();
	// Flush the resampler.
	for (;;) {
		const std::size_t old = clip.samples.size();
		clip.samples.resize(old + 4096 * std::size_t(outChannels));
		uint8_t* out[1] = {reinterpret_cast<uint8_t*>(clip.samples.data() + old)};
		int got = swr_convert(swr, out, 4096, nullptr, 0);
		clip.samples.resize(old + std::size_t(std::max(got, 0)) * outChannels);
		if (got <= 0) break;
	}
	if (clip.frameCount() == 0) throw Error(path, 0, "the audio has no samples (zero length)");
	return clip;
}

void writeWav(const std::string& path, const AudioClip& clip) {
	namespace fs = std::filesystem;
	const fs::path target(path), tmp = target.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" + target.filename().string());
	const std::uint32_t dataBytes = std::uint32_t(clip.samples.size() * 2);
	auto u32 = [](std::ofstream& o, std::uint32_t v) { o.write(reinterpret_cast<const char*>(&v), 4); };
	auto u16 = [](std::ofstream& o, std::uint16_t v) { o.write(reinterpret_cast<const char*>(&v), 2); };
	{
		std::ofstream o(tmp, std::ios::binary);
		o.write("RIFF", 4);
		u32(o, 36 + dataBytes);
		o.write("WAVEfmt ", 8);
		u32(o, 16);
		u16(o, 1);
		u16(o, std::uint16_t(clip.channels));
		u32(o, std::uint32_t(clip.sampleRate));
		u32(o, std::uint32_t(clip.sampleRate * clip.channels * 2));
		u16(o, std::uint16_t(clip.channels * 2));
		u16(o, 16);
		o.write("data", 4);
		u32(o, dataBytes);
		for (float f : clip.samples) {
			const float c = f < -1.f ? -1.f : (f > 1.f ? 1.f : f);
			const std::int16_t v = std::int16_t(std::lround(c * 32767.f));
			o.write(reinterpret_cast<const char*>(&v), 2);
		}
		if (!o) {
			o.close();
			std::remove(tmp.c_str());
			throw Error(path, 0, "cannot write");
		}
	}
	std::error_code ec;
	fs::rename(tmp, target, ec);
	if (ec) {
		std::remove(tmp.c_str());
		throw Error(path, 0, "cannot write: " + ec.message());
	}
}

}  // namespace talkhead
