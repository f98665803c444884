// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/ticks.h"
#include "media/audio.h"
#include "perform/performance.h"
#include "render/output.h"
#include "render/render.h"

namespace talkhead {

// The output half of a video job (issue 46): where a performance's video goes and how it is encoded, the
// files written with it, and a stimulus's timing. render and say fill one from their flags (src/cli), a
// program linking the library fills it itself, and renderVideoJob makes the files.
struct VideoJob {
	std::string output;                                   // the video's path ("-": standard output, y4m only)
	std::optional<VideoFormat> format = VideoFormat::Mp4;  // nullopt: no video (PNG frames or landmarks only)
	int crf = -1;                                         // the format's quality; -1: its default
	std::string preset = "veryfast";                      // x264's
	bool transparent = false;                             // the face's matte as alpha (webm, PNG frames)
	std::optional<std::string> framesDir, landmarksOut;   // PNG frames, the landmarks TSV
	std::optional<std::string> audioOut;                  // the sound track as muxed, as WAV
	bool noAudio = false;                                 // no sound track (its length still sets the duration)
	RenderOptions render;                                 // size, fit, drawing, threads, matte
	Ticks leadIn{0}, tail{0}, avOffset{0};                // a stimulus's still lead-in and tail, audio offset (issue 14)
	// The video output (format set): what makeVideoSink writes.
	OutputSpec videoSpec() const {
		OutputSpec s;
		s.format = format.value_or(VideoFormat::Mp4), s.path = output, s.crf = crf, s.preset = preset, s.alpha = transparent;
		return s;
	}
};

// A file written with the video (speech, sidecar): written to a temporary name before the render and put
// in place only once the video is complete, so a failed or interrupted job leaves none of them.
struct SideOutput {
	std::string path;
	std::function<void(const std::string& temporaryPath)> write;
};

// The lead-in, tail and audio offset on a performance whose duration is set: keyposes and events later by
// the lead-in, the video longer by lead-in + tail, the audio (when there is one) shifted by lead-in +
// offset inside silence.
std::unique_ptr<AudioSource> applyStimulusTiming(const VideoJob& job, Performance& perf, std::unique_ptr<AudioSource> audio);

// Renders `perf` with `model` to the job's outputs: the video (its sound from `audio` unless noAudio), the
// PNG frames, the landmarks TSV, the WAV of the sound as muxed, the `side` files and `extra` (a caller's
// sink, may be null) — all or nothing. Throws Error naming the output when `audioOut` is asked without a
// sound.
RenderStats renderVideoJob(const VideoJob& job, const Face& face, const Performance& perf, std::unique_ptr<AudioSource> audio,
                           std::vector<SideOutput> side, RenderProgress* progress, FrameSink* extra = nullptr);

}  // namespace talkhead
