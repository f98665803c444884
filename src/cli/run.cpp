// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/run.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <new>

#include "base/atomic_file.h"
#include "base/data_dirs.h"
#include "base/error.h"
#include "base/progress.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "corpus/build.h"
#include "model/faces.h"
#include "model/model_file.h"
#include "synth_corpus.h"
#include "track/face_build.h"

namespace talkhead::cli {

// How the default face in a user's cache was made: a face in the cache whose stamp differs is made again.
// Change it whenever the default face's corpus or build changes (D80: Lanczos-3 warps to the mean shape).
const char* const kDefaultFaceRecipe = "synthetic corpus 1280x720; Lanczos-3 warps to the mean shape (D80)\n";

namespace {
thread_local FrameSink* extraSink = nullptr;
}

void setExtraFrameSink(FrameSink* sink) { extraSink = sink; }
FrameSink* extraFrameSink() { return extraSink; }

std::string cliField(const std::string& field) { return field == "output" ? "-o" : "--" + field; }

std::string shownLine(const std::string& message) {
	return safeLine(wordFields(message, [](const std::string& f) { return std::optional<std::string>(cliField(f)); }));
}

int runCommandLine(const std::vector<std::string>& args, std::string& error) {
	error.clear();
	const std::string command = args.empty() ? std::string() : args[0];
	const std::vector<std::string> rest(args.empty() ? args.end() : args.begin() + 1, args.end());
	try {
		if (const Command* c = findCommand(command)) return c->run(rest);
		throw UsageError("unknown command '" + command + "'");
	} catch (const UsageError& e) {
		error = "talkhead: " + shownLine(e.what()) + " (see 'talkhead " + (findCommand(command) ? command + " " : std::string()) + "--help')";
		return 2;
	} catch (const std::bad_alloc&) {
		error = "talkhead: error: out of memory";
		return 1;
	} catch (const std::exception& e) {
		// One line, valid UTF-8 and bounded, whatever the message quotes (a label with a newline, raw bytes,
		// a 200 KB line): base/text.h safeLine.
		error = "talkhead: error: " + shownLine(describeException(e));
		return 1;
	}
}

void ensureDefaultFace(bool quiet) {
	namespace fs = std::filesystem;
	const std::string cache = userCacheDir();
	const fs::path models = cache.empty() ? fs::path() : fs::path(cache) / "models", corpus = models / "default-corpus";
	const fs::path made = models / "default.thm", recipe = models / "default.recipe";
	std::error_code ec;
	const auto found = findDefaultModel();
	// A default face made in the cache by an earlier talkhead, another way (D80: the build's warp), is made
	// again; one installed with talkhead is the installation's.
	bool stale = false;
	if (found && !cache.empty() && fs::equivalent(*found, made, ec)) {
		std::string stamp;
		try {
			stamp = readTextFile(recipe.string());
		} catch (const std::exception&) {  // none: made before the stamp
		}
		stale = stamp != kDefaultFaceRecipe;
	}
	if ((found && !stale) || cache.empty()) return;
	const auto t0 = std::chrono::steady_clock::now();
	if (!quiet)
		std::fprintf(stderr, "talkhead: %s: making it once in %s (the synthetic corpus and its model, about a minute on 2 cores)\n",
		             stale ? "the default face in the cache was made by an earlier talkhead" : "no default face installed", models.string().c_str());
	if (stale) {  // its 1.6 GB go before the new one is written
		fs::remove(made, ec);
		fs::remove(recipe, ec);
	}
	fs::create_directories(models, ec);
	if (ec) throw Error(models.string() + ": cannot make the folder for the default face (" + ec.message() + ")");
	// The same steps and sizes as CMakeLists.txt's default_model target, by the library calls `corpus synth`,
	// `talkhead build` and `corpus au-appearance` make (issue 46).
	NullProgress silent;
	SynthCorpusOptions synth;  // as `corpus synth --size 1280x720`
	synth.width = 1280, synth.height = 720;
	writeSynthCorpus(corpus.string(), synth, silent);
	const Corpus c = loadCorpus((corpus / "corpus.csv").string());
	const Scheme scheme = corpusScheme(c);
	saveModel(buildFaceModel(c, scheme, BuildOptions{}, silent), made.string());
	writeFileAtomically(recipe.string(), kDefaultFaceRecipe);
	if (!findDataFile("models/au-appearance.bin"))  // a package installs the skin's maps (6 MB)
		saveAuAppearance(buildAuAppearance(c, scheme), (models / "au-appearance.bin").string());
	fs::remove_all(corpus, ec);  // 200 MB of images, not needed once the model is made
	if (!quiet)
		std::fprintf(stderr, "talkhead: the default face is ready (%.0f s): %s\n",
		             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), made.string().c_str());
}

const char* const kSyntheticFace = "synthetic";

std::string shippedFaceModel(const std::string& name, bool quiet) {
	if (name == kSyntheticFace) {
		ensureDefaultFace(quiet);
		return "";
	}
	if (auto own = ownFace(name)) return own->model;  // made with `face create --name`
	const ShippedFace face = shippedFace(name);
	if (auto built = builtShippedFace(face)) return *built;
	const auto t0 = std::chrono::steady_clock::now();
	const std::string where = shippedFaceModelPath(face);
	if (!quiet)
		std::fprintf(stderr, "talkhead: the face '%s' is built once from its %s clips into %s (10–20 s on 2 cores)\n", name.c_str(),
		             std::to_string(readTakeList(face.takes).size()).c_str(), where.empty() ? "the cache" : std::filesystem::path(where).parent_path().c_str());
	ProgressBar bar(quiet);
	const std::string model = ensureShippedFace(face, bar);
	bar.finish();
	if (!quiet)
		std::fprintf(stderr, "talkhead: the face '%s' is ready (%.0f s): %s\n", name.c_str(),
		             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), model.c_str());
	return model;
}

std::string faceOrModel(const std::optional<std::string>& face, const std::optional<std::string>& model, const std::string& command, bool quiet) {
	if (face && model) throw UsageError(command + ": give --face NAME or --model M.thm, not both");
	if (face) return shippedFaceModel(*face, quiet);
	if (model) return *model;
	ensureDefaultFace(quiet);
	return "";
}

}  // namespace talkhead::cli
