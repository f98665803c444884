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

#include "base/atomic_file.h"
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
