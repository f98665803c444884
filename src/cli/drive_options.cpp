// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/run.h"
#include "cli/drive_options.h"

#include <cstdio>

#include "base/error.h"
#include "base/progress.h"
#include "base/text.h"
#include "media/video_reader.h"
#include "track/drive_mouth.h"

namespace talkhead::cli {

NonVerbalOptions parseNonVerbalOptions(const Args& args, const std::string& command, const std::string& defaultParts) {
	NonVerbalOptions o;
	o.head = o.brows = o.eyes = o.mouth = false;
	for (const std::string& part : split(args.get("--parts", defaultParts), ',')) {
		if (part == "head") o.head = true;
		else if (part == "brows") o.brows = true;
		else if (part == "eyes") o.eyes = true;
		else if (part == "mouth") o.mouth = true;
		else throw UsageError(command + ": --parts takes head, brows, eyes and mouth, not '" + part + "'");
	}
	o.neutralSeconds = args.number("--neutral-seconds", o.neutralSeconds, 0.04, 60);
	o.neutralFrames = int(args.number("--neutral-frames", 0, 0, 100000));
	o.maxTurnDegrees = args.number("--max-turn", o.maxTurnDegrees, 5, 90);
	return o;
}

std::vector<OptionSpec> nonVerbalOptionSpecs() {
	return {{"--neutral-frames", "N", "neutral face: the per-point median of the first N frames with a face (default: the first second)"},
	        {"--neutral-seconds", "S", "neutral face: over the first S seconds (default 1)"},
	        {"--max-turn", "DEG", "drop (and bridge) frames whose head turns further than DEG degrees (default 30)"}};
}

NonVerbalTrack trackNonVerbal(const std::string& input, const NonVerbalOptions& o, const std::string& dlibModel, bool quiet, LandmarkTrack* landmarks) {
	LandmarkTrack lt;
	if (endsWith(input, ".tsv")) {
		lt = readLandmarksTsv(input);
	} else {
		TrackOptions to;
		if (!dlibModel.empty()) to.modelPath = dlibModel;
		ProgressBar bar(quiet);
		lt = trackVideo(input, to, bar);
		bar.finish();
	}
	NonVerbalTrack nv = analyseNonVerbal(lt, o);
	for (const std::string& w : nv.warnings) std::fprintf(stderr, "talkhead: warning: %s\n", shownLine(input + ": " + w).c_str());
	if (landmarks) *landmarks = std::move(lt);
	return nv;
}

Driving parseDriving(const Args& args, const std::string& command) {
	Driving d;
	d.video = args.get("--drive");
	d.mouth = args.has("--drive-mouth");
	if (d.mouth && !d.video) throw UsageError(command + ": --drive-mouth goes with --drive VIDEO");
	if (d.mouth && (args.get("--transcript") || args.get("--text") || args.get("--text-file")))
		throw UsageError(command + ": --drive-mouth takes the mouth from the video: give no --transcript or --text");
	if (!d.video && (args.get("--parts") || args.get("--drive-model") || args.get("--neutral-frames") || args.get("--neutral-seconds") || args.get("--max-turn")))
		throw UsageError(command + ": --parts, --drive-model, --neutral-frames, --neutral-seconds and --max-turn go with --drive VIDEO");
	d.options = parseNonVerbalOptions(args, command, "head,brows,eyes");
	d.model = args.get("--drive-model", "");
	return d;
}

bool Driving::hasAudio() const { return video && VideoReader(*video).info().hasAudio; }

void Driving::track(bool quiet) {
	if (!video) return;
	nv = trackNonVerbal(*video, options, model, quiet, mouth ? &landmarks : nullptr);
	end = nv.curves().end() + ticksFromSeconds(1 / nv.rate);
}

void Driving::mouthKeys(PerformanceSpec& spec, const FaceModel& model, Emotion emotion) {
	const DrivenMouth dm = driveMouth(landmarks, model, emotion.label());
	spec.keys = dm.keys;
	spec.duration = end;
	exemplarChoices = dm.exemplarChoices;
}

void Driving::report(const Performance& perf, bool quiet) const {
	if (!video) return;
	if (end + ticksFromSeconds(0.5) < perf.duration)
		std::fprintf(stderr, "talkhead: warning: %s: the video (%.2f s) is shorter than the render (%.2f s); the head holds its last pose after it\n",
		             video->c_str(), toSeconds(end), toSeconds(perf.duration));
	if (!quiet)
		std::fprintf(stderr, "talkhead: %s drives the face: %zu frames, %zu blink(s)%s%s\n", video->c_str(), nv.frames.size(), nv.blinks.size(),
		             nv.bridged.empty() ? "" : ", some frames bridged",
		             mouth ? (", the mouth: " + std::to_string(perf.timeline.keys.size()) + " keyposes (" + std::to_string(exemplarChoices) + " exemplars chosen by shape)").c_str()
		                   : "");
}

}  // namespace talkhead::cli
