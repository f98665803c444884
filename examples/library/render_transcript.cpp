// SPDX-License-Identifier: GPL-3.0-or-later
// Renders a timed transcript to an MP4 with talkhead's library.
//   render_transcript MODEL.thm TRANSCRIPT OUT.mp4 [LANG] [EMOTION]
#include <cstdio>
#include <exception>

#include "phonetics/language.h"
#include "phonetics/transcript.h"
#include "render/render.h"

int main(int argc, char** argv) {
	if (argc < 4) {
		std::fprintf(stderr, "usage: render_transcript MODEL.thm TRANSCRIPT OUT.mp4 [LANG] [EMOTION]\n");
		return 2;
	}
	try {
		using namespace talkhead;
		// Phones → context-dependent visemes → one keypose per phone.
		const Language& lang = Language::get(argc > 4 ? argv[4] : "pt-BR");
		const std::vector<PhoneSegment> phones = phoneSegments(readTranscript(argv[2]), lang);
		Performance performance;
		performance.rate = FrameRate{30, 1};
		performance.keys = keyposes(phones, performance.rate.frameLength());
		performance.duration = phones.back().end;
		performance.emotion = Emotion::parse(argc > 5 ? argv[5] : "neutral");
		// The model, one sink (MP4 without audio), and the render.
		const FaceModel model = loadRenderModel(argv[1]);
		auto mp4 = makeMp4Sink(argv[3], Mp4Settings{}, nullptr);
		const RenderStats stats = renderPerformance(model, performance, RenderOptions{}, {mp4.get()});
		std::printf("%s: %lld frames, %dx%d, %zu keyposes\n", argv[3], (long long)stats.frames, stats.width, stats.height, stats.keyposes);
		return 0;
	} catch (const std::exception& e) {
		std::fprintf(stderr, "render_transcript: %s\n", e.what());
		return 1;
	}
}
