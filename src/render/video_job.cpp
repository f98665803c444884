// SPDX-License-Identifier: GPL-3.0-or-later
// A video job's outputs (render/video_job.h): staged side files, the sinks, the render, the commit.
#include "render/video_job.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "media/audio.h"

namespace talkhead {

std::unique_ptr<AudioSource> applyStimulusTiming(const VideoJob& job, Performance& perf, std::unique_ptr<AudioSource> audio) {
	if (job.leadIn == Ticks(0) && job.tail == Ticks(0) && job.avOffset == Ticks(0)) return audio;
	addLeadInAndTail(perf, job.leadIn, job.tail);
	if (!audio) return audio;
	return shiftedSource(std::move(audio), job.leadIn + job.avOffset, perf.duration);
}

RenderStats renderVideoJob(const VideoJob& job, const Face& face, const Performance& perf, std::unique_ptr<AudioSource> audio,
                           std::vector<SideOutput> side, RenderProgress* progress, FrameSink* extra) {
	// The sound as muxed, as WAV: the track read once into memory, written once the video is complete and
	// muxed from there.
	AudioClip track;
	if (job.audioOut) {
		if (!audio) throw Error(*job.audioOut, 0, "{{audio-out}}: this video has no sound track (give {{audio}})");
		track.sampleRate = audio->sampleRate();
		track.channels = audio->channels();
		std::vector<float> block(std::size_t(4096) * std::size_t(track.channels));
		for (std::size_t n; (n = audio->read(block.data(), 4096)) > 0;)
			track.samples.insert(track.samples.end(), block.begin(), block.begin() + std::ptrdiff_t(n * std::size_t(track.channels)));
		audio = clipSource(track);
		side.push_back({*job.audioOut, [&track](const std::string& p) { writeWav(p, track); }});
	}
	// The side outputs written now (a full disk fails before the render), put in place after it.
	std::vector<std::unique_ptr<StagedFile>> staged;
	for (const auto& s : side) {
		staged.push_back(std::make_unique<StagedFile>(s.path));
		staged.back()->write(s.write);
	}
	const bool withAudio = audio && !job.noAudio;
	std::vector<std::unique_ptr<FrameSink>> owned;
	if (job.format) owned.push_back(makeVideoSink(job.videoSpec(), withAudio ? std::move(audio) : nullptr));
	if (job.landmarksOut) owned.push_back(makeLandmarksSink(*job.landmarksOut));
	if (job.framesDir) owned.push_back(makePngFramesSink(*job.framesDir, job.transparent));
	std::vector<FrameSink*> sinks;
	for (auto& s : owned) sinks.push_back(s.get());
	if (extra) sinks.push_back(extra);
	const RenderStats st = renderPerformance(face, perf, job.render, sinks, progress);
	for (auto& s : staged) s->commit();
	return st;
}

}  // namespace talkhead
