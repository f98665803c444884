// SPDX-License-Identifier: GPL-3.0-or-later
// The libav plugin (libtalkhead-av.so): audio decoding and the H.264 + AAC MP4 writer. See av_module.h.
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/channel_layout.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswresample/swresample.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <filesystem>
#include <memory>

#include "media/av_module.h"
#include "base/plugin.h"
#include "media/av_util.h"

namespace talkhead {

namespace {

// "N s" for a limit in a message.
std::string secondsText(double s) {
	char b[32];
	std::snprintf(b, sizeof b, "%g s", s);
	return b;
}

// The first audio stream of a file, decoded and resampled (float, at most 2 channels) as it is read. At
// most maxSeconds of it (issue 45: a 20 kB FLAC can hold hours of silence): a container that declares a
// longer length is refused before anything is decoded, and the samples are counted as they come.
class AudioDecoder {
public:
	AudioDecoder(const std::string& path, int outRate, double maxSeconds) : path_(path), rate_(outRate), maxSeconds_(maxSeconds) {
		// A constructor that throws runs no destructor: what was opened before the throw is released here
		// (a malformed file leaked its demuxer's memory on every refusal; found by the recognize fuzz target).
		try {
			open(path, outRate);
		} catch (...) {
			release();
			throw;
		}
	}
	~AudioDecoder() { release(); }
	void release() {
		av_packet_free(&pkt_);
		av_frame_free(&frame_);
		swr_free(&swr_);
		avcodec_free_context(&ctx_);
		avformat_close_input(&fmt_);
	}
	void open(const std::string& path, int outRate) {
		if (!std::filesystem::exists(path)) throw Error(path, 0, "audio file not found");
		av_log_set_level(AV_LOG_FATAL);  // problems are reported through return codes, as one error line
		checkAv(avformat_open_input(&fmt_, path.c_str(), nullptr, nullptr), path, "cannot open audio");
		checkAv(avformat_find_stream_info(fmt_, nullptr), path, "cannot read audio stream info");
		const AVCodec* dec = nullptr;
		stream_ = av_find_best_stream(fmt_, AVMEDIA_TYPE_AUDIO, -1, -1, &dec, 0);
		if (stream_ < 0 || !dec) throw Error(path, 0, "no audio stream");
		refuseDeclaredLength();
		ctx_ = avcodec_alloc_context3(dec);
		checkAv(avcodec_parameters_to_context(ctx_, fmt_->streams[stream_]->codecpar), path, "bad audio parameters");
		checkAv(avcodec_open2(ctx_, dec, nullptr), path, "cannot open the audio decoder");
		// An absurd rate (a damaged header: 1.8 GHz) would make the resampler's filters take gigabytes.
		if (ctx_->sample_rate < 0 || ctx_->sample_rate > 768000)
			throw Error(path, 0, "the audio's sample rate (" + std::to_string(ctx_->sample_rate) + " Hz) is not plausible: a damaged header?");
		if (ctx_->ch_layout.nb_channels <= 0) av_channel_layout_default(&ctx_->ch_layout, 1);
		channels_ = std::min(2, ctx_->ch_layout.nb_channels);
		if (rate_ <= 0) rate_ = outRate = ctx_->sample_rate > 0 ? ctx_->sample_rate : 48000;  // 0: keep the file's rate
		AVChannelLayout outLayout;
		av_channel_layout_default(&outLayout, channels_);
		checkAv(swr_alloc_set_opts2(&swr_, &outLayout, AV_SAMPLE_FMT_FLT, outRate, &ctx_->ch_layout, ctx_->sample_fmt, ctx_->sample_rate, 0, nullptr),
		        path, "cannot set up resampling");
		checkAv(swr_init(swr_), path, "cannot set up resampling");
		pkt_ = av_packet_alloc();
		frame_ = av_frame_alloc();
	}
	int channels() const { return channels_; }
	int rate() const { return rate_; }
	double declared() const { return declared_; }  // seconds its header declares, −1 when none (or a bit-rate guess)

	// Up to `frames` sample frames into out; fewer only at the end.
	std::size_t read(float* out, std::size_t frames) {
		const std::size_t ch = std::size_t(channels_);
		std::size_t done = 0;
		while (done < frames) {
			if (pos_ < pending_.size() / ch) {
				const std::size_t n = std::min(frames - done, pending_.size() / ch - pos_);
				std::memcpy(out + done * ch, pending_.data() + pos_ * ch, n * ch * sizeof(float));
				pos_ += n, done += n;
				continue;
			}
			pending_.clear(), pos_ = 0;
			if (!refill()) break;
		}
		total_ += std::int64_t(done);
		if (maxSeconds_ > 0 && double(total_) > maxSeconds_ * double(rate_))
			throw Error(path_, 0, "lasts longer than the " + secondsText(maxSeconds_) + " allowed");
		return done;
	}

private:
	// The length the container or the stream declares, when it is read from the file (not estimated from
	// the bit rate): longer than allowed is refused now, before a sample is decoded.
	void refuseDeclaredLength() {
		if (fmt_->duration_estimation_method == AVFMT_DURATION_FROM_BITRATE) return;  // a guess: count instead
		double& declared = declared_;
		const AVStream* st = fmt_->streams[stream_];
		if (st->duration != AV_NOPTS_VALUE && st->duration > 0 && st->time_base.den > 0)
			declared = double(st->duration) * av_q2d(st->time_base);
		else if (fmt_->duration != AV_NOPTS_VALUE && fmt_->duration > 0)
			declared = double(fmt_->duration) / AV_TIME_BASE;
		if (maxSeconds_ > 0 && declared > maxSeconds_ + 0.5) {
			char b[64];
			std::snprintf(b, sizeof b, "%.1f s", declared);
			throw Error(path_, 0, std::string("lasts ") + b + " (as its header says), longer than the " + secondsText(maxSeconds_) + " allowed");
		}
	}

	// Decodes the next packet(s) into pending_; false at the end.
	bool refill() {
		if (flushed_) return false;
		while (pending_.empty()) {
			if (!eof_) {
				if (av_read_frame(fmt_, pkt_) >= 0) {
					if (pkt_->stream_index == stream_) {
						const int r = avcodec_send_packet(ctx_, pkt_);
						if (r < 0 && r != AVERROR(EAGAIN) && r != AVERROR_INVALIDDATA) checkAv(r, path_, "cannot decode audio");
					}
					av_packet_unref(pkt_);
				} else {
					eof_ = true;
					avcodec_send_packet(ctx_, nullptr);
				}
				drainDecoder();
				continue;
			}
			drainDecoder();
			if (!pending_.empty()) break;
			// Flush the resampler.
			pending_.resize(4096 * std::size_t(channels_));
			uint8_t* o[1] = {reinterpret_cast<uint8_t*>(pending_.data())};
			const int got = swr_convert(swr_, o, 4096, nullptr, 0);
			pending_.resize(std::size_t(std::max(got, 0)) * std::size_t(channels_));
			if (got <= 0) {
				flushed_ = true;
				return false;
			}
		}
		return true;
	}
	void drainDecoder() {
		for (;;) {
			const int r = avcodec_receive_frame(ctx_, frame_);
			if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
			checkAv(r, path_, "cannot decode audio");
			const int maxOut = swr_get_out_samples(swr_, frame_->nb_samples);
			const std::size_t old = pending_.size();
			pending_.resize(old + std::size_t(maxOut) * std::size_t(channels_));
			uint8_t* o[1] = {reinterpret_cast<uint8_t*>(pending_.data() + old)};
			const int got = checkAv(swr_convert(swr_, o, maxOut, const_cast<const uint8_t**>(frame_->extended_data), frame_->nb_samples), path_,
			                        "cannot resample audio");
			pending_.resize(old + std::size_t(got) * std::size_t(channels_));
			av_frame_unref(frame_);
		}
	}

	std::string path_;
	int rate_ = 0, channels_ = 0, stream_ = -1;
	double maxSeconds_ = 0, declared_ = -1;
	AVFormatContext* fmt_ = nullptr;
	AVCodecContext* ctx_ = nullptr;
	SwrContext* swr_ = nullptr;
	AVPacket* pkt_ = nullptr;
	AVFrame* frame_ = nullptr;
	std::vector<float> pending_;
	std::size_t pos_ = 0;
	std::int64_t total_ = 0;
	bool eof_ = false, flushed_ = false;
};

// Decodes the whole file into a scratch block, keeping nothing: throws at the decoder's limit.
void countSamples(AudioDecoder& dec) {
	std::vector<float> scratch(16384 * std::size_t(dec.channels()));
	while (dec.read(scratch.data(), 16384) == 16384) {
	}
}

AudioClip decodeAudioImpl(const std::string& path, int outRate, double maxSeconds) {
	auto dec = std::make_unique<AudioDecoder>(path, outRate, maxSeconds);
	// A file that does not declare its length is counted first, keeping nothing, so that one holding more
	// than allowed is refused for a few MiB, not the limit's worth of samples (issue 45, D75); that costs
	// such files a second decoding. One whose header says less than it holds is counted when it passes what
	// its header says (+1 s).
	bool counted = maxSeconds <= 0;
	auto countThenReopen = [&] {  // throws at the limit; else a fresh decoder from the start
		countSamples(*std::make_unique<AudioDecoder>(path, outRate, maxSeconds));
		dec = std::make_unique<AudioDecoder>(path, outRate, maxSeconds);
		counted = true;
	};
	if (!counted && dec->declared() < 0) countThenReopen();
	AudioClip clip;
	clip.sampleRate = dec->rate();
	clip.channels = dec->channels();
	const std::size_t block = 16384;
	for (;;) {
		const std::size_t old = clip.samples.size();
		clip.samples.resize(old + block * std::size_t(clip.channels));
		const std::size_t n = dec->read(clip.samples.data() + old, block);
		clip.samples.resize(old + n * std::size_t(clip.channels));
		if (n < block) break;
		if (!counted && double(clip.frameCount()) > (dec->declared() + 1) * double(dec->rate())) {  // the header lied
			clip.samples = {};
			dec.reset();
			countThenReopen();
		}
	}
	if (clip.frameCount() == 0) throw Error(path, 0, "the audio has no samples (zero length)");
	return clip;
}

struct Mp4Encoder {
	std::string path;
	VideoOptions o;
	AudioSource* audio = nullptr;       // pulled as the video advances
	std::vector<float> audioBlock;      // one AAC frame, interleaved
	bool audioEnded = false;
	AVFormatContext* fmt = nullptr;
	AVCodecContext* venc = nullptr;
	AVCodecContext* aenc = nullptr;
	AVStream* vst = nullptr;
	AVStream* ast = nullptr;
	AVFrame* wrapped = av_frame_alloc();  // a frame lent to the encoder (writeYuv)
	int released = 0;                     // how many of its planes the encoder has let go
	AVFrame* aframe = nullptr;
	AVPacket* pkt = nullptr;
	std::int64_t frameIndex = 0;
	std::int64_t audioPos = 0;  // next audio sample frame to encode
	bool finished = false;
	// Live (openMp4Live): fragmented MP4 handed to `sink` as it is made, a fragment per frame.
	std::function<bool(const std::uint8_t*, std::size_t)> sink;
	bool sinkFailed = false;
	std::string codecs;  // RFC 6381, for a Media Source Extensions SourceBuffer

	static int writeToSink(void* opaque, std::uint8_t* data, int size) {
		auto* self = static_cast<Mp4Encoder*>(opaque);
		if (self->sinkFailed || !self->sink(data, std::size_t(size))) {
			self->sinkFailed = true;
			return AVERROR(EPIPE);
		}
		return size;
	}

	void open() {
		const bool live = bool(sink), webm = o.container == VideoContainer::WebM;
		if (live && webm) throw Error(path, 0, "a live stream is MP4");
		if (o.alpha && !webm) throw Error(path, 0, "MP4 (H.264) has no alpha channel: write WebM");
		checkAv(avformat_alloc_output_context2(&fmt, nullptr, webm ? "webm" : "mp4", live ? nullptr : path.c_str()), path,
		        webm ? "cannot create the WebM muxer" : "cannot create the MP4 muxer");
		openVideo(webm, live);
		if (audio) openAudio(webm, live);
		AVDictionary* opts = nullptr;
		if (live) {
			const int size = 1 << 16;
			auto* buffer = static_cast<unsigned char*>(av_malloc(size));
			if (!buffer) throw Error(path, 0, "out of memory");
			fmt->pb = avio_alloc_context(buffer, size, 1, this, nullptr, &Mp4Encoder::writeToSink, nullptr);
			if (!fmt->pb) {
				av_free(buffer);
				throw Error(path, 0, "out of memory");
			}
			fmt->flags |= AVFMT_FLAG_CUSTOM_IO;
			av_dict_set(&opts, "movflags", "+empty_moov+default_base_moof+frag_custom", 0);
			// RFC 6381 codec names: avc1.PPCCLL (profile, constraints, level) from the sequence parameter set,
			// found in an avcC record or in Annex B NAL units (what libx264 gives as extradata); AAC-LC.
			const std::uint8_t* x = venc->extradata;
			const int xs = venc->extradata_size;
			char name[32] = "";
			if (x && xs >= 4 && x[0] == 1) std::snprintf(name, sizeof name, "avc1.%02x%02x%02x", x[1], x[2], x[3]);
			for (int i = 0; x && !name[0] && i + 6 < xs; ++i)
				if (x[i] == 0 && x[i + 1] == 0 && x[i + 2] == 1 && (x[i + 3] & 0x1f) == 7)
					std::snprintf(name, sizeof name, "avc1.%02x%02x%02x", x[i + 4], x[i + 5], x[i + 6]);
			if (!name[0]) throw Error(path, 0, "the H.264 encoder gave no sequence parameter set");
			codecs = std::string(name) + (audio ? ",mp4a.40.2" : "");
		} else {
			checkAv(avio_open(&fmt->pb, path.c_str(), AVIO_FLAG_WRITE), path, "cannot write the video");
			if (!webm) av_dict_set(&opts, "movflags", "+faststart", 0);
		}
		fmt->flags |= AVFMT_FLAG_BITEXACT;  // no library version strings: the same input gives the same file
		const int r = avformat_write_header(fmt, &opts);
		av_dict_free(&opts);
		checkAv(r, path, webm ? "cannot write the WebM header" : "cannot write the MP4 header");
		if (!wrapped) throw Error(path, 0, "out of memory");
		pkt = av_packet_alloc();
	}

	// The video encoder and stream: x264 (crf, preset; zerolatency for a live stream) or libvpx-vp9.
	void openVideo(bool webm, bool live) {
		const char* videoCodec = webm ? "libvpx-vp9" : "libx264";
		const AVCodec* vcodec = avcodec_find_encoder_by_name(videoCodec);
		if (!vcodec) throw Error(path, 0, std::string("this libav has no ") + videoCodec + " encoder");
		vst = avformat_new_stream(fmt, nullptr);
		venc = avcodec_alloc_context3(vcodec);
		venc->width = o.width;
		venc->height = o.height;
		venc->pix_fmt = o.alpha ? AV_PIX_FMT_YUVA420P : AV_PIX_FMT_YUV420P;
		venc->time_base = AVRational{o.rate.den, o.rate.num};
		venc->framerate = AVRational{o.rate.num, o.rate.den};
		venc->gop_size = 10 * o.rate.num / std::max(1, o.rate.den);
		venc->thread_count = o.threads;
		if (fmt->oformat->flags & AVFMT_GLOBALHEADER) venc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
		if (webm) {
			// Constant quality (crf, no bitrate cap), libvpx's good-quality deadline at its faster speeds;
			// threads over tile columns only (deterministic: libvpx's row-based multithreading, row-mt, is
			// documented as non-deterministic and gave different files under load); BT.601 limited range.
			venc->bit_rate = 0;
			venc->colorspace = AVCOL_SPC_SMPTE170M;
			venc->color_range = AVCOL_RANGE_MPEG;
			av_opt_set(venc->priv_data, "crf", std::to_string(o.crf).c_str(), 0);
			av_opt_set(venc->priv_data, "deadline", "good", 0);
			av_opt_set(venc->priv_data, "cpu-used", "5", 0);
			av_opt_set(venc->priv_data, "row-mt", "0", 0);
			if (o.alpha) av_dict_set(&vst->metadata, "alpha_mode", "1", 0);
		} else {
			av_opt_set(venc->priv_data, "preset", o.preset.c_str(), 0);
			av_opt_set(venc->priv_data, "crf", std::to_string(o.crf).c_str(), 0);
		}
		if (live) {
			// Every frame out as soon as it is in: no B-frames, no lookahead, sliced threads; a keyframe
			// every 2 s.
			av_opt_set(venc->priv_data, "tune", "zerolatency", 0);
			venc->gop_size = 2 * o.rate.num / std::max(1, o.rate.den);
			// Without lookahead, crf 0 leaves P-frames a little lossy: lossless is qp 0.
			if (o.crf == 0) av_opt_set(venc->priv_data, "qp", "0", 0);
		}
		checkAv(avcodec_open2(venc, vcodec, nullptr), path, webm ? "cannot open the VP9 encoder" : "cannot open the H.264 encoder");
		checkAv(avcodec_parameters_from_context(vst->codecpar, venc), path, "video parameters");
		vst->time_base = venc->time_base;
		vst->avg_frame_rate = venc->framerate;

	}

	// The audio encoder and stream: AAC, or Vorbis in WebM; a live stream skips the encoder's priming.
	void openAudio(bool webm, bool live) {
		const AVCodec* acodec = webm ? avcodec_find_encoder_by_name("libvorbis") : avcodec_find_encoder(AV_CODEC_ID_AAC);
		if (!acodec) throw Error(path, 0, webm ? "this libav has no libvorbis encoder" : "this libav has no AAC encoder");
		ast = avformat_new_stream(fmt, nullptr);
		aenc = avcodec_alloc_context3(acodec);
		aenc->sample_fmt = AV_SAMPLE_FMT_FLTP;
		aenc->sample_rate = audio->sampleRate();
		av_channel_layout_default(&aenc->ch_layout, audio->channels());
		if (webm) {  // Vorbis at quality 5 (VBR; an average bitrate cannot be set up for every rate and layout)
			aenc->flags |= AV_CODEC_FLAG_QSCALE;
			aenc->global_quality = 5 * FF_QP2LAMBDA;
		} else {
			aenc->bit_rate = 128000;
		}
		aenc->time_base = AVRational{1, audio->sampleRate()};
		if (fmt->oformat->flags & AVFMT_GLOBALHEADER) aenc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
		checkAv(avcodec_open2(aenc, acodec, nullptr), path, webm ? "cannot open the Vorbis encoder" : "cannot open the AAC encoder");
		checkAv(avcodec_parameters_from_context(ast->codecpar, aenc), path, "audio parameters");
		ast->time_base = aenc->time_base;
		aframe = av_frame_alloc();
		aframe->format = AV_SAMPLE_FMT_FLTP;
		aframe->sample_rate = audio->sampleRate();
		av_channel_layout_copy(&aframe->ch_layout, &aenc->ch_layout);
		aframe->nb_samples = aenc->frame_size;
		checkAv(av_frame_get_buffer(aframe, 0), path, "audio frame");
		if (live && aenc->initial_padding > 0) {
			std::vector<float> skip(std::size_t(aenc->initial_padding) * std::size_t(audio->channels()));
			audio->read(skip.data(), std::size_t(aenc->initial_padding));
		}
	}

	void drain(AVCodecContext* enc, AVStream* st) {
		for (;;) {
			int r = avcodec_receive_packet(enc, pkt);
			if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
			checkAv(r, path, "encoding failed");
			if (sink && enc == aenc) {
				// Live: no edit list to hide the AAC encoder's priming, so its packets start at 0 and the
				// sound's first `initial_padding` samples were skipped (open): sample k plays at k / rate.
				if (pkt->pts != AV_NOPTS_VALUE) pkt->pts += enc->initial_padding;
				if (pkt->dts != AV_NOPTS_VALUE) pkt->dts += enc->initial_padding;
			}
			av_packet_rescale_ts(pkt, enc->time_base, st->time_base);
			pkt->stream_index = st->index;
			checkAv(av_interleaved_write_frame(fmt, pkt), path, "cannot write the video");
		}
	}

	// Encodes audio up to sample frame `until` (whole AAC frames; the rest waits), or everything (flush),
	// reading it from the source one AAC frame at a time.
	void encodeAudio(std::int64_t until, bool all) {
		if (!audio) return;
		const int n = aenc->frame_size, ch = audio->channels();
		audioBlock.resize(std::size_t(n) * std::size_t(ch));
		while (!audioEnded && (all || audioPos + n <= until)) {
			const int count = int(audio->read(audioBlock.data(), std::size_t(n)));
			if (count < n) audioEnded = true;
			if (count == 0) break;
			checkAv(av_frame_make_writable(aframe), path, "audio frame");
			for (int c = 0; c < ch; ++c) {
				float* dst = reinterpret_cast<float*>(aframe->data[c]);
				for (int k = 0; k < n; ++k) dst[k] = k < count ? audioBlock[std::size_t(k) * std::size_t(ch) + std::size_t(c)] : 0.f;
			}
			aframe->nb_samples = count;
			aframe->pts = audioPos;
			checkAv(avcodec_send_frame(aenc, aframe), path, "audio encoding failed");
			drain(aenc, ast);
			audioPos += count;
			aframe->nb_samples = n;
		}
	}

	void writeYuv(const YuvImage& img) {
		if (img.width != o.width || img.height != o.height) throw std::logic_error("Mp4Writer: frame size differs");
		// The caller's planes go to the encoder without a copy: wrapped in buffers whose release only counts.
		// libx264 copies the picture into its own frames inside avcodec_send_frame (the simple encode path
		// encodes a frame as soon as no packet is pending, and drain() leaves none), so libav lets go of
		// them before this returns; if a libav ever kept them, the caller's buffer could change under it,
		// so that is an error, not a silent risk.
		const int cw = (o.width + 1) / 2;
		released = 0;
		auto wrap = [&](const std::vector<std::uint8_t>& plane) {
			AVBufferRef* b = av_buffer_create(const_cast<std::uint8_t*>(plane.data()), plane.size(),
			                                  [](void* opaque, std::uint8_t*) { ++*static_cast<int*>(opaque); }, &released, AV_BUFFER_FLAG_READONLY);
			if (!b) throw Error(path, 0, "out of memory");
			return b;
		};
		av_frame_unref(wrapped);
		if (o.alpha && img.a.size() != std::size_t(o.width) * std::size_t(o.height)) throw std::logic_error("Mp4Writer: a frame without its alpha plane");
		wrapped->format = o.alpha ? AV_PIX_FMT_YUVA420P : AV_PIX_FMT_YUV420P;
		wrapped->width = o.width;
		wrapped->height = o.height;
		const std::vector<std::uint8_t>* planes[4] = {&img.y, &img.u, &img.v, &img.a};
		const int nPlanes = o.alpha ? 4 : 3;
		for (int p = 0; p < nPlanes; ++p) {
			wrapped->buf[p] = wrap(*planes[p]);
			wrapped->data[p] = wrapped->buf[p]->data;
			wrapped->linesize[p] = p == 0 || p == 3 ? o.width : cw;
		}
		wrapped->pts = frameIndex++;
		const int sent = avcodec_send_frame(venc, wrapped);
		av_frame_unref(wrapped);
		checkAv(sent, path, "video encoding failed");
		drain(venc, vst);
		if (released != nPlanes) throw std::logic_error("Mp4Writer: the encoder kept a reference to a frame it was lent");
		// The sound up to this frame's end (live: the source is `initial_padding` samples ahead of the
		// packets, so no further: a live source must not be read past the frames drawn).
		if (audio)
			encodeAudio(av_rescale_q(frameIndex, AVRational{o.rate.den, o.rate.num}, AVRational{1, audio->sampleRate()}) - (sink ? aenc->initial_padding : 0),
			            false);
		if (sink) {  // live: this frame's fragment out now
			checkAv(av_write_frame(fmt, nullptr), path, "cannot write the stream");
			avio_flush(fmt->pb);
			if (sinkFailed) throw Error(path, 0, "the stream's reader is gone");
		}
	}

	void finish() {
		if (finished) return;
		finished = true;
		checkAv(avcodec_send_frame(venc, nullptr), path, "video flush");
		drain(venc, vst);
		if (audio) {
			encodeAudio(0, true);
			checkAv(avcodec_send_frame(aenc, nullptr), path, "audio flush");
			drain(aenc, ast);
		}
		checkAv(av_write_trailer(fmt), path, "cannot finish the video");
		if (sink) avio_flush(fmt->pb);
		else checkAv(avio_closep(&fmt->pb), path, "cannot close the video file");
	}

	~Mp4Encoder() {
		av_packet_free(&pkt);
		av_frame_free(&wrapped);
		av_frame_free(&aframe);
		avcodec_free_context(&venc);
		avcodec_free_context(&aenc);
		if (fmt) {
			if (fmt->pb && (fmt->flags & AVFMT_FLAG_CUSTOM_IO)) {
				av_freep(&fmt->pb->buffer);
				avio_context_free(&fmt->pb);
			} else if (fmt->pb) {
				avio_closep(&fmt->pb);
			}
			avformat_free_context(fmt);
		}
	}
};

struct VideoDecoder {
	std::string path;
	AVFormatContext* fmt = nullptr;
	AVCodecContext* ctx = nullptr;
	SwsContext* sws = nullptr;
	AVPacket* pkt = nullptr;
	AVFrame* frame = nullptr;
	int stream = -1;
	int width = 0, height = 0;
	bool flushed = false, ended = false;
	double lastTime = -1, frameStep = 0;
	std::int64_t decoded = 0;

	void open(VideoInfo& info) {
		if (!std::filesystem::exists(path)) throw Error(path, 0, "video file not found");
		av_log_set_level(AV_LOG_FATAL);
		checkAv(avformat_open_input(&fmt, path.c_str(), nullptr, nullptr), path, "cannot open video");
		checkAv(avformat_find_stream_info(fmt, nullptr), path, "cannot read the stream info");
		const AVCodec* dec = nullptr;
		stream = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, &dec, 0);
		if (stream < 0 || !dec) throw Error(path, 0, "no video stream");
		ctx = avcodec_alloc_context3(dec);
		AVStream* st = fmt->streams[stream];
		checkAv(avcodec_parameters_to_context(ctx, st->codecpar), path, "bad video parameters");
		ctx->thread_count = 1;  // frames in order, deterministic; the caller parallelises per frame
		checkAv(avcodec_open2(ctx, dec, nullptr), path, "cannot open the video decoder");
		width = ctx->width;
		height = ctx->height;
		if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
			throw Error(path, 0, "absurd video size " + std::to_string(width) + "x" + std::to_string(height));
		info.width = width;
		info.height = height;
		AVRational r = st->avg_frame_rate.num > 0 ? st->avg_frame_rate : st->r_frame_rate;
		info.fpsNum = r.num > 0 ? r.num : 0;
		info.fpsDen = r.num > 0 ? r.den : 1;
		frameStep = r.num > 0 ? double(r.den) / r.num : 0;
		double dur = st->duration > 0 ? double(st->duration) * av_q2d(st->time_base) : (fmt->duration > 0 ? double(fmt->duration) / AV_TIME_BASE : 0);
		info.duration = Ticks(std::llround(dur * double(kTicksPerSecond)));
		info.frameCountHint = st->nb_frames > 0 ? st->nb_frames : (r.num > 0 ? std::int64_t(std::llround(dur * av_q2d(r))) : 0);
		info.hasAudio = av_find_best_stream(fmt, AVMEDIA_TYPE_AUDIO, -1, -1, nullptr, 0) >= 0;
		pkt = av_packet_alloc();
		frame = av_frame_alloc();
	}

	// 1 = a frame in `rgb` (or `yuv`), 0 = end.
	int read(Image8* rgb, YuvImage* yuv, double& seconds) {
		for (;;) {
			int r = avcodec_receive_frame(ctx, frame);
			if (r == 0) {
				if (rgb) convert(*rgb);
				else convertYuv(*yuv);
				const AVStream* st = fmt->streams[stream];
				std::int64_t pts = frame->best_effort_timestamp;
				double t = pts != AV_NOPTS_VALUE ? double(pts - (st->start_time != AV_NOPTS_VALUE ? st->start_time : 0)) * av_q2d(st->time_base) : -1;
				// Missing or non-increasing timestamps: continue at the nominal frame rate.
				if (t < 0 || (lastTime >= 0 && t <= lastTime)) t = lastTime < 0 ? 0 : lastTime + (frameStep > 0 ? frameStep : 0.04);
				// Snap to the frame grid of a constant-rate stream (timestamps are often rounded to ms).
				if (frameStep > 0) {
					const double n = std::round(t / frameStep);
					if (std::abs(n * frameStep - t) < 0.25 * frameStep) t = n * frameStep;
				}
				lastTime = t;
				seconds = t;
				av_frame_unref(frame);
				++decoded;
				return 1;
			}
			if (r == AVERROR_EOF) return 0;
			if (r != AVERROR(EAGAIN)) checkAv(r, path, "cannot decode video");
			if (flushed) return 0;
			// Feed the decoder.
			for (;;) {
				r = av_read_frame(fmt, pkt);
				if (r < 0) {
					avcodec_send_packet(ctx, nullptr);
					flushed = true;
					break;
				}
				if (pkt->stream_index == stream) {
					int s = avcodec_send_packet(ctx, pkt);
					av_packet_unref(pkt);
					if (s < 0 && s != AVERROR(EAGAIN) && s != AVERROR_INVALIDDATA) checkAv(s, path, "cannot decode video");
					break;
				}
				av_packet_unref(pkt);
			}
		}
	}

	void convert(Image8& rgb) {
		if (frame->width != width || frame->height != height) {
			// A size change mid-stream: scale to the first frame's size.
		}
		sws = sws_getCachedContext(sws, frame->width, frame->height, AVPixelFormat(frame->format), width, height, AV_PIX_FMT_RGB24,
		                           SWS_BILINEAR | SWS_ACCURATE_RND | SWS_BITEXACT, nullptr, nullptr, nullptr);
		if (!sws) throw Error(path, 0, "cannot convert the video's pixel format");
		if (rgb.width != width || rgb.height != height || rgb.channels != 3) rgb = Image8(width, height, 3);
		uint8_t* dst[1] = {rgb.data.data()};
		int stride[1] = {3 * width};
		sws_scale(sws, frame->data, frame->linesize, 0, frame->height, dst, stride);
	}

	// `yuv` comes sized (width × height) by the caller (YuvImage::resize lives outside the plugin).
	void convertYuv(YuvImage& yuv) {
		if (yuv.width != width || yuv.height != height) throw std::logic_error("readVideoYuv: the frame is not sized");
		const AVPixelFormat f = AVPixelFormat(frame->format);
		if ((f == AV_PIX_FMT_YUV420P || f == AV_PIX_FMT_YUVJ420P) && frame->width == width && frame->height == height) {
			auto copy = [](const std::uint8_t* src, int srcStride, std::uint8_t* dst, int w, int h) {
				for (int r = 0; r < h; ++r) std::memcpy(dst + std::size_t(r) * std::size_t(w), src + std::ptrdiff_t(r) * srcStride, std::size_t(w));
			};
			copy(frame->data[0], frame->linesize[0], yuv.y.data(), width, height);
			copy(frame->data[1], frame->linesize[1], yuv.u.data(), yuv.chromaWidth(), yuv.chromaHeight());
			copy(frame->data[2], frame->linesize[2], yuv.v.data(), yuv.chromaWidth(), yuv.chromaHeight());
			return;
		}
		sws = sws_getCachedContext(sws, frame->width, frame->height, f, width, height, AV_PIX_FMT_YUV420P, SWS_BILINEAR | SWS_ACCURATE_RND | SWS_BITEXACT,
		                           nullptr, nullptr, nullptr);
		if (!sws) throw Error(path, 0, "cannot convert the video's pixel format");
		uint8_t* dst[3] = {yuv.y.data(), yuv.u.data(), yuv.v.data()};
		int stride[3] = {width, yuv.chromaWidth(), yuv.chromaWidth()};
		sws_scale(sws, frame->data, frame->linesize, 0, frame->height, dst, stride);
	}

	~VideoDecoder() {
		sws_freeContext(sws);
		av_packet_free(&pkt);
		av_frame_free(&frame);
		avcodec_free_context(&ctx);
		if (fmt) avformat_close_input(&fmt);
	}
};

// The plugin's entry points: exceptions stay inside (guarded, base/plugin.h), messages go out as strings.
bool decodeAudioEntry(const std::string& path, int sampleRate, double maxSeconds, AudioClip& out, std::string& error) {
	return guarded(error, [&] { out = decodeAudioImpl(path, sampleRate, maxSeconds); });
}

void* openAudioEntry(const std::string& path, int sampleRate, double maxSeconds, int& rate, int& channels, std::string& error) {
	AudioDecoder* d = nullptr;
	guarded(error, [&] {
		d = new AudioDecoder(path, sampleRate, maxSeconds);
		rate = d->rate(), channels = d->channels();
	});
	return d;
}

long readAudioEntry(void* h, float* out, std::size_t frames, std::string& error) {
	long n = -1;
	guarded(error, [&] { n = long(static_cast<AudioDecoder*>(h)->read(out, frames)); });
	return n;
}

void closeAudioEntry(void* h) { delete static_cast<AudioDecoder*>(h); }

void* openMp4Entry(const std::string& path, const VideoOptions& o, AudioSource* audio, std::string& error) {
	auto enc = std::make_unique<Mp4Encoder>();
	const bool ok = guarded(error, [&] {
		enc->path = path;
		enc->o = o;
		enc->audio = audio;
		av_log_set_level(AV_LOG_ERROR);
		enc->open();
	});
	return ok ? enc.release() : nullptr;
}

bool writeMp4Entry(void* h, const YuvImage& frame, std::string& error) {
	return guarded(error, [&] { static_cast<Mp4Encoder*>(h)->writeYuv(frame); });
}

bool finishMp4Entry(void* h, std::string& error) {
	return guarded(error, [&] { static_cast<Mp4Encoder*>(h)->finish(); });
}

void* openMp4LiveEntry(const std::function<bool(const std::uint8_t*, std::size_t)>& write, const VideoOptions& o, AudioSource* audio,
                       std::string& codecs, std::string& error) {
	auto enc = std::make_unique<Mp4Encoder>();
	const bool ok = guarded(error, [&] {
		enc->path = "live stream";
		enc->o = o;
		enc->audio = audio;
		enc->sink = write;
		av_log_set_level(AV_LOG_ERROR);
		enc->open();
		codecs = enc->codecs;
	});
	return ok ? enc.release() : nullptr;
}

void closeMp4Entry(void* h) { delete static_cast<Mp4Encoder*>(h); }

void* openVideoEntry(const std::string& path, VideoInfo& info, std::string& error) {
	auto dec = std::make_unique<VideoDecoder>();
	const bool ok = guarded(error, [&] {
		dec->path = path;
		dec->open(info);
	});
	return ok ? dec.release() : nullptr;
}

int readVideoEntry(void* h, Image8& rgb, double& seconds, std::string& error) {
	int r = -1;
	guarded(error, [&] { r = static_cast<VideoDecoder*>(h)->read(&rgb, nullptr, seconds); });
	return r;
}

int readVideoYuvEntry(void* h, YuvImage& yuv, double& seconds, std::string& error) {
	int r = -1;
	guarded(error, [&] { r = static_cast<VideoDecoder*>(h)->read(nullptr, &yuv, seconds); });
	return r;
}

void closeVideoEntry(void* h) { delete static_cast<VideoDecoder*>(h); }

const AvModule kModule{kAvModuleAbi, decodeAudioEntry, openAudioEntry, readAudioEntry, closeAudioEntry, openMp4Entry, writeMp4Entry, finishMp4Entry, closeMp4Entry,
                       openVideoEntry, readVideoEntry, closeVideoEntry, readVideoYuvEntry, openMp4LiveEntry};

}  // namespace

}  // namespace talkhead

extern "C" const void* talkhead_av_module() { return &talkhead::kModule; }
