// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"
#include "geometry/scheme.h"
#include "media/image_io.h"
#include "model/face_model.h"
#include "test_support.h"

using namespace talkhead;

TEST(FaceModel, structureFollowsTheScheme) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel();
	EXPECT_EQ(m.pointCount(), 73);
	EXPECT_EQ(m.sampleCount(), 20u);
	ASSERT_EQ(m.regions.size(), 3u);
	EXPECT_EQ(m.faceMesh.vertexCount, 73);
	EXPECT_EQ(m.frameMesh.vertexCount, 73 + kFrameBorderPoints);
	EXPECT_EQ(m.basefaceIndex, nearestShape(m.alignedShapes, m.meanShape));
	// Coarse to fine: each region smaller than the one before.
	EXPECT_GT(m.regions[0].pixelCount(), m.regions[1].pixelCount());
	EXPECT_GT(m.regions[1].pixelCount(), m.regions[2].pixelCount());
	for (const auto& r : m.regions) {
		EXPECT_EQ(r.pca.mean.size(), 3 * r.pixelCount() + 2 * 73);
		EXPECT_EQ(r.pca.components(), 19);  // all non-null components: m − 1
		float maxAlpha = 0;
		for (float a : r.alpha) {
			ASSERT_GT(a, 0.f);
			ASSERT_LE(a, 1.f);
			maxAlpha = std::max(maxAlpha, a);
		}
		EXPECT_EQ(maxAlpha, 1.f) << r.name << " has no fully opaque interior";
	}
	// The shape part of the PCA mean is the mean of the aligned shapes, within 1 px of the GPA mean.
	Points s0 = synthesizeShape(m, Eigen::VectorXf::Zero(19));
	Points avg = Points::Zero(73, 2);
	for (const auto& a : m.alignedShapes) avg += a;
	avg /= double(m.alignedShapes.size());
	EXPECT_LT((s0 - avg).cwiseAbs().maxCoeff(), 1e-3);
	EXPECT_LT((s0 - m.meanShape).cwiseAbs().maxCoeff(), 1.0);
}

TEST(FaceModel, allComponentsReconstructTrainingImagesAbove45dB) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel();
	for (std::size_t i : {std::size_t(0), std::size_t(7), std::size_t(19)}) {
		const CorpusEntry& e = test::immCorpus().entries[i];
		Projection p = projectImage(m, readImage(e.imagePath), e.points);
		EXPECT_LT((p.alignedShape - m.alignedShapes[i]).cwiseAbs().maxCoeff(), 1e-6);
		for (std::size_t r = 0; r < m.regions.size(); ++r) {
			const RegionModel& region = m.regions[r];
			// Projection of a training image gives its stored coefficients…
			Eigen::VectorXf stored = sampleCoefficients(region, i);
			EXPECT_LT((p.coefficients[r] - stored).cwiseAbs().maxCoeff(), 1e-2 * std::max(1.0f, stored.cwiseAbs().maxCoeff()));
			// …and reconstructs it in the shape-free frame.
			Image recon = p.shapeFree;
			scatterAppearance(region, synthesizeAppearance(region, stored), recon);
			std::vector<std::uint8_t> mask(recon.pixelCount(), 0);
			for (auto px : region.pixels) mask[std::size_t(px)] = 1;
			EXPECT_GE(psnr(p.shapeFree, recon, mask), 45.0) << "image " << i << " region " << region.name;
		}
	}
}

TEST(FaceModel, appearanceCacheHoldsEachSamplesReconstruction) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel();
	for (const auto& r : m.regions) {
		ASSERT_EQ(r.sampleAppearances.size(), m.sampleCount() * std::size_t(r.appearanceSize()));
		for (std::size_t i : {std::size_t(0), std::size_t(13)}) {
			const Eigen::VectorXf exact = synthesizeAppearance(r, sampleCoefficients(r, i)).cwiseMax(0.f).cwiseMin(255.f);
			EXPECT_LE((r.cachedAppearance(i) - exact).cwiseAbs().maxCoeff(), 0.5f + 1e-3f) << r.name << " sample " << i;
		}
	}
}

TEST(FaceModel, heldOutImageReconstructsWorseThanTrainingButSensibly) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel();
	const CorpusEntry& e = test::immCorpus().entries[40];  // person 05, not in the model
	Projection p = projectImage(m, readImage(e.imagePath), e.points);
	const RegionModel& face = m.regions[0];
	Image recon = p.shapeFree;
	scatterAppearance(face, synthesizeAppearance(face, p.coefficients[0]), recon);
	std::vector<std::uint8_t> mask(recon.pixelCount(), 0);
	for (auto px : face.pixels) mask[std::size_t(px)] = 1;
	double db = psnr(p.shapeFree, recon, mask);
	EXPECT_GT(db, 15.0);
	EXPECT_LT(db, 45.0);
}

TEST(FaceModel, compositeOfATrainingSampleMatchesItsImage) {
	SKIP_WITHOUT_IMM();
	const FaceModel& m = test::immModel();
	const std::size_t i = 5;
	std::vector<Eigen::VectorXf> coeffs;
	for (const auto& r : m.regions) coeffs.push_back(sampleCoefficients(r, i));
	Image composite = compositeAppearance(m, coeffs);
	const CorpusEntry& e = test::immCorpus().entries[i];
	Projection p = projectImage(m, readImage(e.imagePath), e.points);
	// Inside the lips region (fully opaque part) the composite is the sample's own shape-free image.
	const RegionModel& lips = m.regions[2];
	std::vector<std::uint8_t> mask(composite.pixelCount(), 0);
	for (std::size_t k = 0; k < lips.pixels.size(); ++k) mask[std::size_t(lips.pixels[k])] = lips.alpha[k] == 1.f;
	EXPECT_GE(psnr(p.shapeFree, composite, mask), 40.0);
}

TEST(FaceModel, componentOptionsTruncatePerRegion) {
	SKIP_WITHOUT_IMM();
	const Corpus& c = test::immCorpus();
	std::vector<Points> shapes;
	std::vector<SampleInfo> samples;
	for (std::size_t i = 0; i < 12; ++i) {
		shapes.push_back(c.entries[i].points);
		samples.push_back(SampleInfo{c.entries[i].cdvLabel(), "-", c.entries[i].cdvLabel(), "", {}});
	}
	BuildOptions opts;
	opts.pca.maxComponents = 4;
	opts.regionPca["lips"] = PcaOptions{};  // all
	NullProgress quiet;
	FaceModel m = buildFaceModel(loadScheme("imm-73"), shapes, samples, 800, 600,
	                             [&](std::size_t i) { return readImage(c.entries[i].imagePath); }, opts, quiet);
	EXPECT_EQ(m.regions[0].pca.components(), 4);
	EXPECT_EQ(m.regions[1].pca.components(), 4);
	EXPECT_EQ(m.regions[2].pca.components(), 11);
}

TEST(FaceModel, badTrainingInputIsReported) {
	SKIP_WITHOUT_IMM();
	const Corpus& c = test::immCorpus();
	std::vector<Points> shapes{c.entries[0].points, c.entries[1].points, c.entries[2].points};
	std::vector<SampleInfo> samples{{"a.jpg", "-", "a", "", {}}, {"b.jpg", "-", "b", "", {}}, {"c.jpg", "-", "c", "", {}}};
	NullProgress quiet;
	Scheme scheme = loadScheme("imm-73");
	// One image of another size.
	auto images = [&](std::size_t i) { return i == 1 ? Image8(640, 480, 3) : readImage(c.entries[i].imagePath); };
	try {
		buildFaceModel(scheme, shapes, samples, 800, 600, images, BuildOptions{}, quiet);
		FAIL() << "expected an error";
	} catch (const Error& e) {
		EXPECT_NE(std::string(e.what()).find("b.jpg"), std::string::npos) << e.what();
	}
	// A shape with a point far outside the image.
	shapes[2](4, 0) = 1e6;
	try {
		buildFaceModel(scheme, shapes, samples, 800, 600, [&](std::size_t i) { return readImage(c.entries[i].imagePath); }, BuildOptions{}, quiet);
		FAIL() << "expected an error";
	} catch (const Error& e) {
		EXPECT_NE(std::string(e.what()).find("c.jpg: point 5"), std::string::npos) << e.what();
	}
	// Too few images.
	EXPECT_THROW(buildFaceModel(scheme, {shapes[0]}, {samples[0]}, 800, 600, images, BuildOptions{}, quiet), Error);
}

TEST(FaceModel, findSamplePicksTheNearestPhoneContextAmongSeveral) {
	FaceModel m;
	auto sample = [](std::string emotion, std::string cdv, std::array<std::string, 5> ctx) {
		SampleInfo s;
		s.emotion = std::move(emotion), s.cdv = std::move(cdv), s.context = std::move(ctx);
		return s;
	};
	m.samples = {sample("neutral", "p1", {"_", "a", "p", "i", "_"}), sample("neutral", "t1", {"_", "_", "t", "i", "_"}),
	             sample("neutral", "p1", {"_", "u", "m", "u", "_"}), sample("joy", "p1", {"_", "u", "m", "u", "_"}),
	             sample("neutral", "p1", {"_", "_", "b", "a", "s"})};
	const std::array<std::string, 5> afterU{"s", "u", "p", "u", "_"}, startBa{"_", "_", "b", "a", "_"}, other{"k", "e", "m", "e", "k"};
	EXPECT_EQ(m.findSample("neutral", "p1"), 0);             // no context: the corpus's first (most typical)
	EXPECT_EQ(m.findSample("neutral", "p1", &afterU), 2);     // both neighbours [u]
	EXPECT_EQ(m.findSample("neutral", "p1", &startBa), 4);    // utterance start, then [a]
	EXPECT_EQ(m.findSample("neutral", "p1", &other), 2);      // own phone [m] matches the second; ties keep order
	EXPECT_EQ(m.findSample("joy", "p1", &startBa), 3);        // the emotion's only sample
	EXPECT_EQ(m.findSample("anger", "p1", &afterU), -1);
}
