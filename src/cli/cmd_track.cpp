// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead corpus landmarks | corpus from-video | compare: faces from real video (issue 10).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "base/atomic_file.h"
#include "base/error.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/output_dir.h"
#include "cli/drive_options.h"
#include "cli/video_options.h"
#include "base/text.h"
#include "base/progress.h"
#include "media/image_io.h"
#include "track/compare.h"
#include "track/landmarks.h"
#include "track/nonverbal.h"
#include "perform/controls.h"

namespace talkhead::cli {

namespace {

// Keeps evenly spaced thumbnails of a stream of frames whose count is only estimated.
class ThumbnailPicker {
public:
	ThumbnailPicker(std::size_t want, double expectedFrames) : want_(want), step_(std::max(1.0, expectedFrames / double(want))) {}
	void offer(const FrameLandmarks& f, const Image8& rgb) {
		if (double(seen_++) + 1e-9 >= next_) {
			thumbs_.push_back({f, rgb});
			next_ += step_;
		}
	}
	std::vector<Thumbnail>& thumbs() { return thumbs_; }

private:
	std::size_t want_;
	double step_, next_ = 0;
	std::size_t seen_ = 0;
	std::vector<Thumbnail> thumbs_;
};

// How a video is tracked: --every, --start, --duration, the one-euro smoothing, --redetect, --model.
TrackOptions trackOptions(const Args& args) {
	TrackOptions o;
	o.every = int(args.number("--every", 1, 1, 10000));
	if (auto s = args.get("--start")) o.start = ticksFromSeconds(parseTimeOption("--start", *s));
	if (auto d = args.get("--duration")) o.duration = ticksFromSeconds(parseTimeOption("--duration", *d));
	o.smoothing.enabled = !args.has("--no-smooth");
	o.smoothing.minCutoffHz = args.number("--min-cutoff", o.smoothing.minCutoffHz, 0.01, 100);
	o.smoothing.beta = args.number("--beta", o.smoothing.beta, 0, 1000);
	o.smoothing.mouthMinCutoffHz = args.number("--mouth-min-cutoff", o.smoothing.mouthMinCutoffHz, 0.01, 100);
	o.smoothing.mouthBeta = args.number("--mouth-beta", o.smoothing.mouthBeta, 0, 10000);
	o.redetectSeconds = args.number("--redetect", o.redetectSeconds, 0, 3600);
	if (auto m = args.get("--model")) o.modelPath = *m;
	return o;
}

// About how many frames the input gives (for spacing the contact sheet's thumbnails).
double expectedFrames(const std::string& input, const TrackOptions& o) {
	if (std::filesystem::is_directory(input)) {
		double n = 0;
		for (const auto& e : std::filesystem::directory_iterator(input)) n += e.is_regular_file();
		return n;
	}
	VideoReader probe(input);
	const auto& info = probe.info();
	double secs = toSeconds(info.duration) - toSeconds(o.start);
	if (o.duration.count() >= 0) secs = std::min(secs, toSeconds(o.duration));
	return info.fpsNum > 0 ? secs * info.fpsNum / info.fpsDen / o.every : double(info.frameCountHint);
}

}  // namespace

int runCorpusLandmarks(const std::vector<std::string>& argv) {
	Args args("corpus landmarks", "talkhead corpus landmarks VIDEO|IMAGE_FOLDER -o DIR [options]",
	          {{"--output", "DIR", "folder for the .pts files, landmarks.tsv and contact.png (required)", "-o"},
	           {"--every", "N", "landmark every Nth frame (default 1)"},
	           {"--start", "T", "start at T seconds (or m:ss)"},
	           {"--duration", "T", "landmark T seconds (default: to the end)"},
	           {"--no-smooth", "", "write the unsmoothed fits (default: one-euro smoothing of every point)"},
	           {"--min-cutoff", "HZ", "one-euro cutoff at rest (default 1.5 Hz)"},
	           {"--beta", "B", "one-euro speed coefficient, per eye distance per second (default 4)"},
	           {"--mouth-min-cutoff", "HZ", "the same for the lips (default 3 Hz)"},
	           {"--mouth-beta", "B", "the same for the lips (default 40)"},
	           {"--redetect", "S", "run the face detector every S seconds while tracking (default 2)"},
	           {"--model", "F.dat", "dlib 68-point predictor (default /usr/share/dlib/shape_predictor_68_face_landmarks.dat)"},
	           {"--no-pts", "", "do not write one .pts file per frame"},
	           {"--sheet", "N", "frames on the contact sheet (default 24)"},
	           {"--quiet", "", "no progress and no summary", "-q"}},
	          "Finds the face and its 68 iBUG points (dlib) in every frame of a video, or in every image of a folder.\n"
	          "Video: detect once, then track from frame to frame (re-detecting every few seconds or when a fit\n"
	          "is inconsistent), with one-euro smoothing that removes jitter without lagging the mouth. Writes\n"
	          "one iBUG .pts per frame (frame_NNNNNN.pts, or the image's name), landmarks.tsv (frame, time,\n"
	          "status, confidence, x y per point) and contact.png (points drawn on sampled frames). Frames where\n"
	          "the face is lost are marked 'lost' in landmarks.tsv, with no .pts.");
	if (!args.parse(argv)) return 0;
	args.onePositional("give one video or image folder");
	const std::string out = args.required("--output", "-o DIR is required");
	const std::string input = args.positionals()[0];
	const TrackOptions o = trackOptions(args);
	const int sheetCount = int(args.number("--sheet", 24, 0, 400));
	const bool quiet = args.has("--quiet");
	const auto t0 = std::chrono::steady_clock::now();

	OutputDir dir(out);
	ProgressBar bar(quiet);
	std::unique_ptr<ThumbnailPicker> picker;
	const bool writeEachPts = !args.has("--no-pts");
	auto onFrame = [&](const FrameLandmarks& f, const Image8& rgb) {
		if (!picker) picker = std::make_unique<ThumbnailPicker>(std::size_t(std::max(0, sheetCount)), std::max(1.0, expectedFrames(input, o)));
		if (sheetCount > 0) picker->offer(f, rgb);
		if (writeEachPts && f.found) {
			char name[64];
			std::snprintf(name, sizeof name, "frame_%06lld.pts", (long long)f.frame);
			writePts(dir.path(f.name.empty() ? std::string(name) : std::filesystem::path(f.name).stem().string() + ".pts"), f.points);
		}
	};
	LandmarkTrack track = landmarkInput(input, o, bar, onFrame);
	bar.finish();
	writeFileAtomically(dir.path("landmarks.tsv"), landmarksTsv(track));
	if (sheetCount > 0 && picker) writeImage(dir.path("contact.png"), contactSheet(picker->thumbs()));
	dir.commit();
	if (!quiet) {
		const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		const std::size_t lost = track.frames.size() - track.foundCount();
		std::fprintf(stderr, "wrote %s: %zu frames, face in %zu (%zu lost), in %.1f s (%.0f frames/s)", out.c_str(), track.frames.size(), track.foundCount(), lost,
		             secs, double(track.frames.size()) / std::max(1e-9, secs));
		if (track.frames.size() > 2 && std::filesystem::is_regular_file(input))
			std::fprintf(stderr, "; rigid-point jitter %.4f raw -> %.4f eye distances", rigidJitter(track, true), rigidJitter(track, false));
		std::fprintf(stderr, "\n");
	}
	return 0;
}

int runCompare(const std::vector<std::string>& argv) {
	Args args("compare", "talkhead compare SYNTH.mp4 REAL.mp4 [--json]",
	          {{"--json", "", "print the measures as one JSON object"},
	           {"--rate", "HZ", "resampling rate (default 100)"},
	           {"--max-lag", "MS", "search the best lag within ±MS (default 120)"},
	           {"--model", "F.dat", "dlib 68-point predictor"},
	           {"--quiet", "", "no progress", "-q"}},
	          "Tracks the face in both videos (as 'corpus landmarks' does) and measures how well the synthesized\n"
	          "mouth follows the real one: Pearson r of the inner-lip opening (divided by the eye distance) at lag 0\n"
	          "and at the best lag, the mouth-landmark distance (LMD) after aligning the mouths, and the coverage\n"
	          "(frames with a face). Both videos are compared from their start over the shorter one's length.");
	if (!args.parse(argv)) return 0;
	if (args.positionals().size() != 2) throw UsageError("compare: give two videos, SYNTH and REAL");
	TrackOptions o;
	if (auto m = args.get("--model")) o.modelPath = *m;
	ProgressBar bar(args.has("--quiet") || args.has("--json"));
	const LandmarkTrack a = trackVideo(args.positionals()[0], o, bar);
	const LandmarkTrack b = trackVideo(args.positionals()[1], o, bar);
	bar.finish();
	const LipSyncReport r = compareLipSync(a, b, args.number("--rate", 100, 10, 1000), args.number("--max-lag", 120, 0, 2000));
	std::fputs(args.has("--json") ? (r.json() + "\n").c_str() : r.text().c_str(), stdout);
	return 0;
}

int runTrack(const std::vector<std::string>& argv) {
	std::vector<OptionSpec> specs = {{"--output", "F.json", "the control track (required)", "-o"},
	                                 {"--parts", "LIST", "what to track: head, brows, eyes, mouth (default head,brows,eyes)"},
	                                 {"--plot", "F.png", "the tracks over time (default: the output's name with .png)"},
	                                 {"--model", "F.dat", "dlib 68-point predictor"},
	                                 {"--quiet", "", "no progress and no summary", "-q"}};
	for (auto& s : nonVerbalOptionSpecs()) specs.push_back(s);
	Args args("track", "talkhead track VIDEO|landmarks.tsv -o controls.json [--parts head,brows,eyes,mouth] [options]", specs,
	          "Tracks a person's face through a video (as 'corpus landmarks' does, or reads its landmarks.tsv) and\n"
	          "writes what the face does besides speaking as a control track that 'render --controls' replays on\n"
	          "any model: the head's roll, position and size against the person's neutral face (the median of the\n"
	          "first second), the brows' and eyes' action units (each side's displacements projected onto the\n"
	          "scheme's action-unit templates), and the blinks. Frames where the face is lost or turned past\n"
	          "--max-turn are dropped and bridged by Hermite interpolation (a warning names spans of 0.5 s or more).");
	if (!args.parse(argv)) return 0;
	args.onePositional("give one video (or a landmarks.tsv)");
	const std::string out = args.required("--output", "-o F.json is required");
	const NonVerbalOptions o = parseNonVerbalOptions(args, "track", "head,brows,eyes");
	std::string plot = args.get("--plot", "");
	if (plot.empty()) plot = (endsWith(out, ".json") ? out.substr(0, out.size() - 5) : out) + ".png";
	checkWritableFolder(out);
	checkWritableFolder(plot);
	const std::string input = args.positionals()[0];
	const bool quiet = args.has("--quiet");
	const NonVerbalTrack nv = trackNonVerbal(input, o, args.get("--model", ""), quiet);
	const ControlTrack controls = controlsOf(nv);
	char note[200];
	std::snprintf(note, sizeof note, "talkhead track: %zu frames at %.3f fps, neutral from %zu frames; head roll in degrees, x y in eye distances", nv.frames.size(),
	              nv.rate, nv.neutralCount);
	// Both under temporary names first: a failure or a stop leaves neither.
	StagedFile png(plot), json(out);
	png.write([&](const std::string& t) { writeImage(t, plotNonVerbal(nv)); });
	json.write([&](const std::string& t) { writeFileAtomically(t, controlTrackJson(controls, input, note)); });
	png.commit();
	json.commit();
	if (!quiet) {
		double maxRoll = 0;
		for (const auto& f : nv.frames) maxRoll = std::max(maxRoll, std::abs(f.roll) * 57.29577951308232);
		double bridged = 0;
		for (const auto& [a, b] : nv.bridged) bridged += toSeconds(b - a);
		std::fprintf(stderr, "%s: %zu frames, %zu blinks, head roll up to %.1f deg, %zu action-unit curves, %.1f s bridged; plot %s\n", out.c_str(),
		             nv.frames.size(), nv.blinks.size(), maxRoll, nv.channels.size(), bridged, plot.c_str());
	}
	return 0;
}

}  // namespace talkhead::cli
