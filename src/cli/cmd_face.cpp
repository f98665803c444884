// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead face create VIDEO[:EMOTION]… -o me.thm: your own face from videos, in one command (issue 48, D92).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/progress.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/output_dir.h"
#include "cli/run.h"
#include "cli/video_options.h"
#include "model/faces.h"
#include "model/model_file.h"
#include "phonetics/emotion.h"
#include "phonetics/labels.h"
#include "track/face_build.h"

namespace fs = std::filesystem;

namespace talkhead::cli {

namespace {

// VIDEO or VIDEO:EMOTION (the emotion only when the part after the last colon is one: a file name may
// hold a colon).
VideoTake takeOf(const std::string& arg) {
	const auto colon = arg.rfind(':');
	if (colon != std::string::npos && colon > 0 && canonicalEmotion(arg.substr(colon + 1))) return parseTakeSpec(arg);
	VideoTake t;
	t.video = arg;
	t.where = arg;
	std::error_code ec;
	if (!fs::is_regular_file(arg, ec)) throw Error(arg, 0, "no such video file");
	return t;
}

void printReport(const FaceCreateReport& r, const std::string& out, double seconds) {
	for (std::size_t k = 0; k < r.takes.size(); ++k) {
		const TakeCensus& c = r.takes[k];
		std::fprintf(stderr, "%s (%s, frames by %s): %zu frames seen (%.1f s), face in %zu; usable %zu — refused: %zu tracked without confidence, "
		             "%zu head turned or tilted, %zu blinks, %zu caught smiles; brightness %.0f of 255 (varies %.0f %%), detail %.2f, mouth opening spans %.2f eye distances%s\n",
		             fs::path(c.video).filename().c_str(), r.emotions[k].c_str(), r.methods[k] == "phones" ? "phones" : "mouth shape", c.seen, c.seconds, c.found,
		             c.usable, c.lowConfidence, c.turned, c.blinks, c.smiles, c.brightness, 100 * c.brightnessDrift, c.detail, c.openingRange,
		             r.takes.size() > 1 ? (k == r.baseTake ? "; the baseface's take" : "") : "");
		if (r.takes.size() > 1 && k != r.baseTake)
			std::fprintf(stderr, "  its colours matched to the baseface's take: gain %.2f %.2f %.2f (lighting drift between takes)\n", r.colours[k].gain[0],
			             r.colours[k].gain[1], r.colours[k].gain[2]);
	}
	std::string covered, missing;
	for (const auto& [cdv, n] : r.cdvFrames) covered += (covered.empty() ? "" : " ") + cdv + (n > 1 ? "×" + std::to_string(n) : "");
	for (const auto& m : r.missing) missing += (missing.empty() ? "" : " ") + m;
	std::fprintf(stderr, "visemes covered: %zu of %zu (%s)\n", r.cdvFrames.size(), r.cdvFrames.size() + r.missing.size(), covered.c_str());
	if (!missing.empty()) std::fprintf(stderr, "no frame of their own (drawn from the nearest mouth the face has): %s\n", missing.c_str());
	std::fprintf(stderr, "blinks: %s\n", r.ownBlink ? "the person's own shut eyes" : "drawn lids (no frame with the eyes shut, the head still)");
	for (const auto& a : r.advice) std::fprintf(stderr, "to make it better: %s\n", a.c_str());
	std::fprintf(stderr, "wrote %s: %zu images; %.1f s\n", out.c_str(), r.samples, seconds);
}

int runFaceCreate(const std::vector<std::string>& argv) {
	Args args("face create",
	          "talkhead face create VIDEO[:EMOTION]… [--text \"…\" | --transcript T] [--lang L] -o ME.thm\n"
	          "       talkhead face create --takes LIST.tsv [--lang L] -o ME.thm",
	          {{"--output", "ME.thm", "the face model to write (or --name)", "-o"},
	           {"--name", "NAME", "keep the face under this name in the cache instead: 'talkhead faces' lists it, --face NAME uses it"},
	           {"--takes", "LIST.tsv", "the takes as a list: columns video, emotion [start, duration, transcript, text, audio]"},
	           {"--text", "TEXT", "the words spoken (aligned to each video's audio): frames chosen by phone"},
	           {"--text-file", "F", "the same, from a file"},
	           {"--transcript", "T", "timed phones or words of the one video's speech (TextGrid, GRID .align, …)"},
	           {"--lang", "LANG", "the speech's language (default en-US)"},
	           {"--start", "T", "use each video from T seconds (or m:ss)"},
	           {"--duration", "T", "use T seconds of each video"},
	           {"--quiet", "", "no progress and no report", "-q"}},
	          "Makes a face model from videos of one person, in one step: tracks the 68 points (dlib), measures each\n"
	          "video's frames (light, detail, head pose, blinks, smiles), chooses frames by phone when the speech's\n"
	          "words are known (--text, --transcript, a list's columns) and by mouth shape otherwise, matches the takes'\n"
	          "colours, builds the model, and reports: frames kept of frames seen, visemes covered, frames refused and\n"
	          "why, lighting, and what would make the face better. A video that cannot make a face is refused in one\n"
	          "line and nothing is written: no face, several faces, too short, too dark, too blurred, the head turned\n"
	          "most of the time. VIDEO:EMOTION names a take's emotion (default neutral): one video per emotion makes\n"
	          "a face with those emotions recorded (the others are drawn from action units).");
	if (!args.parse(argv)) return 0;
	if (args.has("--output") == args.has("--name")) throw UsageError("face create: give -o ME.thm or --name NAME (one of them)");
	std::string out = args.get("--output", "");
	if (auto name = args.get("--name")) {
		checkOwnFaceName(*name);
		const std::string dir = ownFacesDir();
		if (dir.empty()) throw Error("face create: no cache folder to keep the face in (set XDG_CACHE_HOME or HOME)");
		std::error_code ec;
		fs::create_directories(dir, ec);
		if (ec) throw Error(dir, 0, "cannot make the folder for your faces (" + ec.message() + ")");
		out = (fs::path(dir) / (*name + ".thm")).string();
	}
	const bool quiet = args.has("--quiet");
	if (int(args.has("--transcript")) + int(args.has("--text")) + int(args.has("--text-file")) > 1)
		throw UsageError("face create: give one of --transcript, --text and --text-file");
	std::vector<VideoTake> takes;
	if (auto list = args.get("--takes")) {
		if (!args.positionals().empty()) throw UsageError("face create: with --takes, name no video as an argument");
		takes = readTakeList(*list);
	}
	for (const auto& a : args.positionals()) takes.push_back(takeOf(a));
	if (takes.empty()) throw UsageError("face create: give one or more videos (VIDEO or VIDEO:EMOTION), or --takes LIST.tsv");
	if (args.has("--transcript") && takes.size() > 1) throw UsageError("face create: --transcript is one video's: give a take list (--takes) for several");
	std::string text;
	if (auto t = args.get("--text")) text = *t;
	else if (auto f = args.get("--text-file")) text = readTextFile(*f);
	for (VideoTake& t : takes) {
		if (auto tr = args.get("--transcript")) t.transcript = *tr;
		if (t.transcript.empty() && t.text.empty()) t.text = text;
		if (auto s = args.get("--start")) t.start = ticksFromSeconds(parseTimeOption("--start", *s));
		if (auto d = args.get("--duration")) t.duration = ticksFromSeconds(parseTimeOption("--duration", *d));
	}
	checkWritableFolder(out);
	FaceCreateOptions o;
	o.lang = args.get("--lang", "en-US");
	const auto t0 = std::chrono::steady_clock::now();
	ProgressBar bar(quiet);
	FaceCreateReport report;
	try {
		report = createFace(takes, o, out, bar);
	} catch (...) {
		bar.finish();
		throw;
	}
	bar.finish();
	if (args.has("--name")) {  // what `talkhead faces` lists
		std::string emotions, sources;
		for (const auto& e : report.emotions)
			if (emotions.find(e) == std::string::npos) emotions += (emotions.empty() ? "" : ",") + e;
		for (const auto& t : takes) sources += (sources.empty() ? "" : ", ") + fs::path(t.video).filename().string();
		const FaceModel m = loadModel(out, ModelParts::Render);
		writeFileAtomically(fs::path(out).replace_extension(".info").string(), "size\t" + std::to_string(m.width) + "x" + std::to_string(m.height) +
		                                                                          "\nemotions\t" + emotions + "\nsource\tface create: " + sources + "\n");
	}
	if (!quiet) printReport(report, out, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
	return 0;
}

}  // namespace

int runFace(const std::vector<std::string>& argv) {
	if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
		std::printf("usage: talkhead face create VIDEO[:EMOTION]… [--text \"…\" | --transcript T] [--lang L] -o ME.thm\n\n"
		            "Your own face from videos of you, in one command (see 'talkhead face create --help');\n"
		            "'talkhead faces' lists the faces that ship with talkhead.\n");
		if (argv.empty()) throw UsageError("face: expected a subcommand (create)");
		return 0;
	}
	const std::vector<std::string> rest(argv.begin() + 1, argv.end());
	if (argv[0] == "create") return runFaceCreate(rest);
	throw UsageError("face: unknown subcommand '" + argv[0] + "' (expected create)");
}

}  // namespace talkhead::cli
