// SPDX-License-Identifier: GPL-3.0-or-later
#include "test_support.h"

#include "base/error.h"

#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;

namespace talkhead::test {

std::string sharedData() {
	if (const char* env = std::getenv("TALKHEAD_SHARED_DATA"); env && *env) return env;
	return TALKHEAD_SHARED_DATA;
}

std::string immFolder() { return sharedData() + "/imm-frontal/IMM-Frontal_Face_DB_SMALL"; }

bool haveImm() { return fs::is_directory(immFolder() + "/asf"); }

const Corpus& immCorpus() {
	static const Corpus c = loadCorpus(immFolder());
	return c;
}

Image8 testPattern(int width, int height) {
	Image8 img(width, height, 3);
	for (int y = 0; y < height; ++y)
		for (int x = 0; x < width; ++x) {
			double u = double(x) / width, v = double(y) / height;
			img.at(x, y, 0) = std::uint8_t(127.5 + 120 * std::sin(9 * u + 4 * v));
			img.at(x, y, 1) = std::uint8_t(127.5 + 120 * std::sin(7 * v - 3 * u + 1));
			img.at(x, y, 2) = std::uint8_t(127.5 + 120 * std::cos(5 * u * v * 6 + 2 * u));
		}
	return img;
}

std::string errorOf(const std::function<void()>& f) {
	try {
		f();
	} catch (const Error& e) {
		return e.what();
	}
	return "no error";
}

std::string tempDir(const std::string& name) {
	fs::path p = fs::temp_directory_path() / ("talkhead-test-" + std::to_string(::getpid())) / name;
	fs::remove_all(p);
	fs::create_directories(p);
	static struct Cleanup {
		~Cleanup() {
			std::error_code ec;
			fs::remove_all(fs::temp_directory_path() / ("talkhead-test-" + std::to_string(::getpid())), ec);
		}
	} cleanup;
	return p.string();
}

}  // namespace talkhead::test

#include <map>
#include <memory>

#include "corpus/build.h"
#include "geometry/scheme.h"
#include "media/image_io.h"
#include "base/progress.h"
#include "synth_corpus.h"

namespace talkhead::test {

const FaceModel& immModel(std::size_t count) {
	static std::map<std::size_t, std::unique_ptr<FaceModel>> cache;
	auto& slot = cache[count];
	if (!slot) {
		// The first `count` IMM faces, unlabelled (emotion "-"), through the library's corpus → model step.
		Corpus c = immCorpus();
		c.entries.resize(count);
		for (CorpusEntry& e : c.entries) e.emotion.reset(), e.word.clear(), e.context = {};
		NullProgress quiet;
		slot = std::make_unique<FaceModel>(buildFaceModel(c, corpusScheme(c), BuildOptions{}, quiet));
	}
	return *slot;
}

FaceModel synthModel(const SynthCorpusOptions& o) {
	const auto items = synthCorpusItems(o);
	FaceRenderer r(o.width, o.height);
	std::vector<Points> shapes;
	std::vector<SampleInfo> samples;
	std::vector<Image8> images;
	for (const auto& it : items) {
		SynthFace f = r.render(it.articulation, it.actionUnits, it.pose);
		shapes.push_back(f.points);
		images.push_back(f.image);
		samples.push_back(SampleInfo{it.fileName, it.emotion, it.viseme, it.word, it.context});
	}
	NullProgress quiet;
	return buildFaceModel(loadScheme("ch-unicamp-56"), shapes, samples, o.width, o.height, [&](std::size_t i) { return images[i]; }, BuildOptions{}, quiet);
}

}  // namespace talkhead::test
