// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "base/error.h"
#include "model/model_file.h"
#include "test_support.h"

using namespace talkhead;
namespace fs = std::filesystem;

namespace {

std::string errorOf(const std::string& path) {
	try {
		loadModel(path);
	} catch (const Error& e) {
		return e.what();
	}
	return "no error";
}

std::vector<char> readAll(const std::string& p) {
	std::ifstream in(p, std::ios::binary);
	return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeAll(const std::string& p, const std::vector<char>& b) {
	std::ofstream out(p, std::ios::binary);
	out.write(b.data(), std::streamsize(b.size()));
}

template <class A, class B>
bool sameBytes(const A& a, const B& b) {
	return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(*a.data()) * std::size_t(a.size())) == 0;
}

}  // namespace

TEST(ModelFile, roundTripIsBitExact) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel(6);
	std::string dir = test::tempDir("roundtrip"), path = dir + "/m.thm";
	saveModel(m, path);
	FaceModel r = loadModel(path);
	EXPECT_EQ(r.scheme.name, m.scheme.name);
	EXPECT_EQ(r.scheme.pointNames, m.scheme.pointNames);
	EXPECT_EQ(r.width, m.width);
	EXPECT_TRUE(sameBytes(r.meanShape, m.meanShape));
	ASSERT_EQ(r.alignedShapes.size(), m.alignedShapes.size());
	for (std::size_t i = 0; i < m.alignedShapes.size(); ++i) EXPECT_TRUE(sameBytes(r.alignedShapes[i], m.alignedShapes[i]));
	EXPECT_EQ(r.samples.size(), m.samples.size());
	EXPECT_EQ(r.samples[3].cdv, m.samples[3].cdv);
	EXPECT_EQ(r.faceMesh.triangles, m.faceMesh.triangles);
	EXPECT_EQ(r.frameMesh.triangles, m.frameMesh.triangles);
	EXPECT_EQ(r.baseface.data, m.baseface.data);
	ASSERT_EQ(r.regions.size(), m.regions.size());
	for (std::size_t i = 0; i < m.regions.size(); ++i) {
		EXPECT_EQ(r.regions[i].pixels, m.regions[i].pixels);
		EXPECT_TRUE(sameBytes(r.regions[i].alpha, m.regions[i].alpha));
		EXPECT_TRUE(sameBytes(r.regions[i].pca.basis, m.regions[i].pca.basis));
		EXPECT_TRUE(sameBytes(r.regions[i].pca.mean, m.regions[i].pca.mean));
		EXPECT_TRUE(sameBytes(r.regions[i].pca.sigma, m.regions[i].pca.sigma));
		EXPECT_TRUE(sameBytes(r.regions[i].pca.eigenvalues, m.regions[i].pca.eigenvalues));
		EXPECT_TRUE(sameBytes(r.regions[i].pca.trainingCoefficients, m.regions[i].pca.trainingCoefficients));
		EXPECT_EQ(r.regions[i].sampleAppearances, m.regions[i].sampleAppearances);
	}
	// Saving the loaded model gives the same file.
	saveModel(r, dir + "/again.thm");
	EXPECT_EQ(readAll(path), readAll(dir + "/again.thm"));
	// No temporary file is left behind.
	int files = 0;
	for (auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
	EXPECT_EQ(files, 2);
}

TEST(ModelFile, damageIsDetected) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel(6);
	std::string dir = test::tempDir("damage"), path = dir + "/m.thm";
	saveModel(m, path);
	const std::vector<char> good = readAll(path);
	// A single flipped byte anywhere in the payload.
	for (std::size_t pos : {std::size_t(40), good.size() / 3, good.size() / 2, good.size() - 1}) {
		auto bad = good;
		bad[pos] ^= 0x10;
		writeAll(dir + "/flip.thm", bad);
		EXPECT_NE(errorOf(dir + "/flip.thm").find("checksum mismatch"), std::string::npos) << "flip at " << pos;
	}
	auto truncated = good;
	truncated.resize(good.size() - 1000);
	writeAll(dir + "/trunc.thm", truncated);
	EXPECT_NE(errorOf(dir + "/trunc.thm").find("truncated"), std::string::npos);
	auto version = good;
	version[8] = 99;  // (the current version is 2)
	writeAll(dir + "/version.thm", version);
	EXPECT_NE(errorOf(dir + "/version.thm").find("format version 99 is not supported"), std::string::npos);
	writeAll(dir + "/magic.thm", std::vector<char>{'n', 'o', 'p', 'e'});
	EXPECT_NE(errorOf(dir + "/magic.thm").find("not a talkhead model file"), std::string::npos);
	EXPECT_EQ(errorOf(dir + "/missing.thm").rfind(dir + "/missing.thm: cannot open model", 0), 0u);
}

TEST(ModelFile, checksumSeesEverySingleByteChange) {
	std::vector<unsigned char> data(1000);
	for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<unsigned char>(i * 7);
	const auto h = checksum64(data.data(), data.size());
	for (std::size_t i = 0; i < data.size(); i += 37) {
		auto d = data;
		d[i] ^= 1;
		EXPECT_NE(checksum64(d.data(), d.size()), h);
	}
	EXPECT_NE(checksum64(data.data(), 999), h);
}

TEST(ModelFile, renderLoadSkipsTheBasesButVerifiesWhatItReads) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel(6);
	std::string dir = test::tempDir("renderload"), path = dir + "/m.thm";
	saveModel(m, path);
	FaceModel r = loadModel(path, ModelParts::Render);
	ASSERT_EQ(r.regions.size(), m.regions.size());
	EXPECT_EQ(r.regions[0].pca.basis.size(), 0);
	// The appearance cache stays on disk and is read sample by sample, identical to the full load's.
	EXPECT_TRUE(r.regions[0].sampleAppearances.empty());
	ASSERT_TRUE(r.regions[0].hasAppearanceCache());
	for (std::size_t i : {std::size_t(0), m.sampleCount() - 1})
		for (std::size_t g = 0; g < m.regions.size(); ++g) {
			EXPECT_EQ(r.regions[g].cachedAppearance(i), m.regions[g].cachedAppearance(i));
			EXPECT_EQ(r.regions[g].cachedAppearance(i).size(), m.regions[g].appearanceSize());
		}
	EXPECT_EQ(r.baseface.data, m.baseface.data);
	// A damaged byte in a record that is read is caught; one in a skipped basis only by a full load; one
	// in the cached appearance of a sample when that sample is read (render) or by a full load.
	const std::vector<char> good = readAll(path);
	auto find = [&](const std::string& name) {
		const std::string needle = std::string("\0\0\0", 3) + name;  // u32 length's high bytes, then the name
		auto it = std::search(good.begin(), good.end(), needle.begin(), needle.end());
		return std::size_t(it - good.begin()) + needle.size() + 4 + 8 + 16;  // a few bytes into the data
	};
	auto bad = good;
	bad[find("appearances")] ^= 0x20;  // sample 0 of the first region
	writeAll(dir + "/a.thm", bad);
	EXPECT_NE(errorOf(dir + "/a.thm").find("checksum mismatch in record 'appearances'"), std::string::npos);
	FaceModel damaged = loadModel(dir + "/a.thm", ModelParts::Render);
	EXPECT_EQ(damaged.regions[0].cachedAppearance(1), m.regions[0].cachedAppearance(1));
	try {
		damaged.regions[0].cachedAppearance(0);
		ADD_FAILURE() << "a damaged cached appearance was read without an error";
	} catch (const Error& e) {
		EXPECT_EQ(std::string(e.what()).rfind(dir + "/a.thm: corrupt model file: checksum mismatch in the cached appearance of sample 0", 0), 0u)
		    << e.what();
	}
	bad = good;
	bad[find("basis")] ^= 0x20;
	writeAll(dir + "/b.thm", bad);
	EXPECT_NO_THROW(loadModel(dir + "/b.thm", ModelParts::Render));
	EXPECT_NE(errorOf(dir + "/b.thm").find("checksum mismatch in record 'basis'"), std::string::npos);
}

TEST(ModelFile, componentLevelsParse) {
	const ComponentLevels l = parseComponentLevels("face=20,cheeks_lips=90%,lips=all");
	ASSERT_EQ(l.size(), 3u);
	EXPECT_EQ(l.at("face").count, 20);
	EXPECT_DOUBLE_EQ(l.at("cheeks_lips").evr, 0.9);
	EXPECT_DOUBLE_EQ(l.at("lips").evr, 1.0);
	EXPECT_TRUE(parseComponentLevels("all").empty());
	for (const char* bad : {"", "face", "face=", "=3", "face=0", "face=-2", "face=2x", "face=120%", "face=0%", "face=3,face=4", "face=3,,lips=2", "face= 3"})
		EXPECT_THROW(parseComponentLevels(bad), Error) << bad;
}

TEST(ModelFile, renderLoadReducesComponents) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel(6);
	std::string dir = test::tempDir("reduced"), path = dir + "/m.thm";
	saveModel(m, path);
	const std::string region = m.regions.back().name;
	const Eigen::Index l = m.regions.back().pca.components();
	ASSERT_GE(l, 3);
	const std::size_t q3 = std::size_t(m.regions.back().appearanceSize());
	// Every component: the build's cache, byte for byte.
	FaceModel all = loadModel(path, ModelParts::Render, {{region, {0, 1.0}}});
	for (std::size_t i = 0; i < m.sampleCount(); ++i) EXPECT_EQ(all.regions.back().cachedAppearance(i), m.regions.back().cachedAppearance(i));
	// k components: ā + σ ∘ (D_a α) over the first k, rounded; only k basis columns read into memory; the
	// other regions untouched. Fewer components, further from the full appearance.
	double lastError = -1;
	for (Eigen::Index k = l; k >= 1; k -= std::max<Eigen::Index>(1, l / 3)) {
		FaceModel r = loadModel(path, ModelParts::Render, {{region, {long(k), 0}}});
		const Eigen::VectorXf want = synthesizeAppearances(m.regions.back(), m.regions.back().pca.trainingCoefficients.row(2).head(k).transpose());
		const Eigen::VectorXf got = r.regions.back().cachedAppearance(2);
		ASSERT_EQ(std::size_t(got.size()), q3);
		EXPECT_LE((got - want.array().round().max(0.f).min(255.f).matrix()).cwiseAbs().maxCoeff(), 1.f) << k;
		EXPECT_EQ(r.regions.front().cachedAppearance(2), m.regions.front().cachedAppearance(2));
		double error = 0;
		for (std::size_t i = 0; i < m.sampleCount(); ++i) error += (r.regions.back().cachedAppearance(i) - m.regions.back().cachedAppearance(i)).squaredNorm();
		EXPECT_GE(error, lastError) << k;
		lastError = error;
	}
	EXPECT_GT(lastError, 0);
	// An EVR level picks the model's count for it.
	FaceModel e = loadModel(path, ModelParts::Render, {{region, {0, 0.8}}});
	const Eigen::Index k80 = m.regions.back().pca.componentsFor(0.8);
	FaceModel c = loadModel(path, ModelParts::Render, {{region, {long(k80), 0}}});
	EXPECT_EQ(e.regions.back().cachedAppearance(1), c.regions.back().cachedAppearance(1));
	// Errors name the model: an unknown region, more components than kept.
	try {
		loadModel(path, ModelParts::Render, {{"nose", {3, 0}}});
		ADD_FAILURE() << "unknown region accepted";
	} catch (const Error& x) {
		EXPECT_NE(std::string(x.what()).find(path + ": {{components}} names region 'nose'"), std::string::npos) << x.what();
	}
	EXPECT_THROW(loadModel(path, ModelParts::Render, {{region, {long(l) + 1, 0}}}), Error);
	// The basis record is still verified though only its first columns are kept: a flipped byte in its
	// last column is caught.
	std::vector<char> bad = readAll(path);
	const std::string needle = std::string("\0\0\0", 3) + "basis";
	std::size_t at = 0;
	for (std::size_t g = 0; g < m.regions.size(); ++g)
		at = std::size_t(std::search(bad.begin() + std::ptrdiff_t(at) + 1, bad.end(), needle.begin(), needle.end()) - bad.begin());
	const std::size_t dataStart = at + needle.size() + 4 + 8;
	const std::size_t n = std::size_t(m.regions.back().pca.basis.rows());
	bad[dataStart + (std::size_t(l) * n - 1) * 4] ^= 0x10;
	writeAll(dir + "/d.thm", bad);
	EXPECT_NO_THROW(loadModel(dir + "/d.thm", ModelParts::Render));
	try {
		loadModel(dir + "/d.thm", ModelParts::Render, {{region, {1, 0}}});
		ADD_FAILURE() << "damaged basis accepted";
	} catch (const Error& x) {
		EXPECT_NE(std::string(x.what()).find("checksum mismatch in record 'basis'"), std::string::npos) << x.what();
	}
}
