// SPDX-License-Identifier: GPL-3.0-or-later
#include "stimuli/side_by_side.h"

#include <algorithm>
#include <cstring>

#include "base/error.h"
#include "media/video_reader.h"
#include "render/output.h"

namespace talkhead {

void writeSideBySide(const std::string& left, const std::string& right, const std::string& audioPath, const std::string& out,
                     const SideBySideOptions& options) {
	if (options.gap < 0 || options.gap % 2 || options.gap > 4096) throw std::logic_error("writeSideBySide: the gap must be even");
	VideoReader a(left), b(right);
	const VideoInfo &ia = a.info(), &ib = b.info();
	if (ia.width != ib.width || ia.height != ib.height)
		throw Error(right, 0, "is " + std::to_string(ib.width) + "x" + std::to_string(ib.height) + ", " + left + " is " + std::to_string(ia.width) + "x" +
		                          std::to_string(ia.height) + ": side by side needs the same size");
	if (ia.fpsNum <= 0 || ib.fpsNum <= 0 || std::int64_t(ia.fpsNum) * ib.fpsDen != std::int64_t(ib.fpsNum) * ia.fpsDen)
		throw Error(right, 0, "has another frame rate than " + left + ": side by side needs the same");
	if (ia.width % 2 || ia.height % 2) throw Error(left, 0, "odd frame size: side by side needs an even width and height");
	StreamInfo info;
	info.width = 2 * ia.width + options.gap;
	info.height = ia.height;
	info.rate = FrameRate{ia.fpsNum, ia.fpsDen};
	info.frames = ia.frameCountHint;
	OutputSpec spec;
	spec.format = VideoFormat::Mp4, spec.path = out, spec.crf = options.mp4.crf, spec.preset = options.mp4.preset;
	auto sink = makeVideoSink(spec, audioPath.empty() ? nullptr : openAudioFile(audioPath));
	sink->begin(info);
	YuvImage fa, fb, both;
	both.resize(info.width, info.height);
	// The gap, limited-range mid-grey (RGB 128): Y 126, U = V = 128; the sides are pasted over it.
	std::fill(both.y.begin(), both.y.end(), std::uint8_t(126));
	std::fill(both.u.begin(), both.u.end(), std::uint8_t(128));
	std::fill(both.v.begin(), both.v.end(), std::uint8_t(128));
	auto paste = [](const std::vector<std::uint8_t>& src, int w, int h, std::vector<std::uint8_t>& dst, int dstWidth, int x) {
		for (int r = 0; r < h; ++r) std::memcpy(&dst[std::size_t(r) * std::size_t(dstWidth) + std::size_t(x)], &src[std::size_t(r) * std::size_t(w)], std::size_t(w));
	};
	Ticks ta{0}, tb{0};
	std::int64_t na = 0, nb = 0, frames = 0;
	for (;;) {
		const bool ga = a.readYuv(fa, ta, na), gb = b.readYuv(fb, tb, nb);
		if (ga != gb) throw Error(ga ? right : left, 0, "has fewer frames than " + (ga ? left : right) + ": side by side needs the same length");
		if (!ga) break;
		const int cw = fa.chromaWidth(), ch = fa.chromaHeight(), bw = both.chromaWidth();
		paste(fa.y, fa.width, fa.height, both.y, both.width, 0);
		paste(fb.y, fb.width, fb.height, both.y, both.width, fa.width + options.gap);
		paste(fa.u, cw, ch, both.u, bw, 0);
		paste(fb.u, cw, ch, both.u, bw, (fa.width + options.gap) / 2);
		paste(fa.v, cw, ch, both.v, bw, 0);
		paste(fb.v, cw, ch, both.v, bw, (fa.width + options.gap) / 2);
		RenderedFrame f;
		f.index = frames;
		f.time = info.rate.time(frames);
		f.yuv = &both;
		sink->frame(f);
		++frames;
	}
	if (frames == 0) throw Error(left, 0, "no frames");
	sink->finish();
	sink->commit();
}

}  // namespace talkhead
