// SPDX-License-Identifier: GPL-3.0-or-later
// Receives talkhead's frames through a callback instead of a file: counts them, checks their times and
// prints the mean luma of the whole clip.
//   frame_stats MODEL.thm TRANSCRIPT [LANG]
#include <cmath>
#include <cstdio>
#include <exception>

#include "phonetics/language.h"
#include "phonetics/transcript.h"
#include "render/render.h"

int main(int argc, char** argv) {
	if (argc < 3) {
		std::fprintf(stderr, "usage: frame_stats MODEL.thm TRANSCRIPT [LANG]\n");
		return 2;
	}
	try {
		using namespace talkhead;
		const Language& lang = Language::get(argc > 3 ? argv[3] : "pt-BR");
		const std::vector<PhoneSegment> phones = phoneSegments(readTranscript(argv[2]), lang);
		Performance performance;
		performance.rate = FrameRate{25, 1};
		performance.timeline.keys = keyposes(phones, performance.rate.frameLength());
		performance.duration = phones.back().end;
		long long frames = 0, outOfOrder = 0;
		double lumaSum = 0;
		auto sink = makeCallbackSink([&](const StreamInfo& info, const RenderedFrame& f) {
			if (f.index != frames || f.time != info.rate.time(f.index)) ++outOfOrder;
			const YuvImage& yuv = *f.yuv;
			double sum = 0;
			for (int y = 0; y < yuv.height; ++y)
				for (int x = 0; x < yuv.width; ++x) sum += yuv.y[std::size_t(y) * std::size_t(yuv.width) + std::size_t(x)];
			lumaSum += sum / (double(yuv.width) * yuv.height);
			++frames;
		});
		const FaceModel model = loadRenderModel(argv[1]);
		const RenderStats stats = renderPerformance(model, performance, RenderOptions{}, {sink.get()});
		std::printf("frames %lld of %lld, out of order %lld, mean luma %.2f\n", frames, (long long)stats.frames, outOfOrder, lumaSum / double(frames));
		return frames == stats.frames && outOfOrder == 0 ? 0 : 1;
	} catch (const std::exception& e) {
		std::fprintf(stderr, "frame_stats: %s\n", e.what());
		return 1;
	}
}
