// SPDX-License-Identifier: GPL-3.0-or-later
// Renders a timed transcript to a video with talkhead's library.
//   render_transcript MODEL.thm TRANSCRIPT OUT.mp4|OUT.webm|OUT.y4m [LANG] [EMOTION[:INTENSITY]]
#include <cstdio>
#include <exception>

#include "phonetics/language.h"
#include "phonetics/transcript.h"
#include "render/output.h"
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
		performance.timeline.keys = keyposes(phones, performance.rate.frameLength());
		performance.duration = phones.back().end;
		if (argc > 5) performance.expression = Expression::parse(argv[5]);  // "joy", "anger:0.6"; checked here
		// The model, one sink (its format from the output's name, no audio), and the render.
		const FaceModel model = loadRenderModel(argv[1]);
		OutputSpec out;
		out.path = argv[3];
		out.format = videoFormatFor(out.path, "");
		auto video = makeVideoSink(out, nullptr);
		const RenderStats stats = renderPerformance(model, performance, RenderOptions{}, {video.get()});
		std::printf("%s: %lld frames, %dx%d, %zu keyposes\n", argv[3], (long long)stats.frames, stats.width, stats.height, stats.keyposes);
		return 0;
	} catch (const std::exception& e) {
		std::fprintf(stderr, "render_transcript: %s\n", e.what());
		return 1;
	}
}
