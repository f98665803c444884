// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "media/audio.h"
#include "media/video_writer.h"
#include "phonetics/language.h"
#include "synth/synthesizer.h"

namespace talkhead::cli {

// Everything `render` and `say` hand to the video pipeline once the keypose timeline is known.
struct RenderJob {
	std::vector<Keypose> keys;
	std::int64_t frames = 0;
	Ticks duration{0};
	VideoOptions video;
	SynthOptions synth;
	std::string output, format = "mp4", modelPath;
	std::optional<std::string> framesDir, landmarksOut;
	const AudioClip* audio = nullptr;
	bool noAudio = false, quiet = false, jsonProgress = false, timing = false;
	unsigned threads = 0;
	std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
	std::string timingPrefix;  // stages before rendering, for --timing (e.g. "speech 0.020 s; ")
};

// Loads the model, prepares the keyposes, draws every frame (parallel batches) and writes the video,
// landmarks and frames through temporary names; prints the summary unless quiet.
void renderVideo(const RenderJob& job);

// round(duration × fps), at least 1.
std::int64_t frameCount(Ticks duration, int fpsNum, int fpsDen);

}  // namespace talkhead::cli
