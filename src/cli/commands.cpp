// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/commands.h"

namespace talkhead::cli {

const std::vector<Command>& commands() {
	static const std::vector<Command> c = {
	    {"build", "build a face model (.thm) from an annotated image corpus", runBuild},
	    {"face", "'face create VIDEO… -o me.thm': your own face from videos of you, in one command, with a report", runFace},
	    {"faces", "the faces that ship with talkhead (real people and the synthetic default) and whether they are built", runFaces},
	    {"inspect", "summarise a face model, draw it (-o DIR), measure reconstruction (--recon)", runInspect},
	    {"corpus", "corpus tools: 'synth' (synthetic corpus), 'landmarks' (track a video), 'from-video' (corpus from a video)", runCorpus},
	    {"render", "render a talking-head video from a transcript, audio (with its text, or alone) and an emotion", runRender},
	    {"say", "text in, talking-head video with speech out (espeak-ng, in process)", runSay},
	    {"align", "forced alignment: speech audio (or video) + its text -> TextGrid of words and phones", runAlign},
	    {"compare", "lip-sync measures of a synthesized video against a real speaker's video", runCompare},
	    {"track", "a person's head motion, brows, eyes and blinks from a video, as a control track", runTrack},
	    {"formats", "the timing formats talkhead reads (what writes them, their units, what is taken from the file)", runFormats},
	    {"visemes", "map a timed transcript (TextGrid, .pho, HTK, GRID, speech marks, …), or speech audio alone, to visemes and keyposes", runVisemes},
	    {"batch", "perceptual-test stimuli from a manifest: blind IDs, key, balanced orders, resumable, shards", runBatch},
	    {"serve", "live streams for chatbots and voice assistants: WebSocket in, fragmented MP4 + JSON events out", runServe},
	    {"live", "render a live session's script (serve --record) offline, frame for frame", runLive},
	    {"job", "run a job written as JSON (a command and its fields): what batch hands each stimulus, what any program can write", runJob}};
	return c;
}

const Command* findCommand(const std::string& name) {
	for (const auto& c : commands())
		if (name == c.name) return &c;
	return nullptr;
}

}  // namespace talkhead::cli
