// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/scheme.h"
#include "geometry/shape.h"
#include "test_support.h"

using namespace talkhead;

namespace {
Points randomShape(int k, unsigned seed) {
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(0, 500);
	Points p(k, 2);
	for (int i = 0; i < k; ++i) p.row(i) << u(rng), u(rng);
	return p;
}
}  // namespace

TEST(Similarity, alignRecoversKnownTransform) {
	Points src = randomShape(56, 1);
	Similarity truth = Similarity::fromScaleAngle(1.37, 0.41, 123.5, -47.25);
	Points dst = truth.apply(src);
	Eigen::VectorXd w = Eigen::VectorXd::Constant(56, 1.0);
	w.head(16).setConstant(0.2);
	Similarity s = alignSimilarity(src, dst, w);
	EXPECT_NEAR(s.scale(), 1.37, 1e-9);
	EXPECT_NEAR(s.angle(), 0.41, 1e-9);
	EXPECT_NEAR(s.tx, 123.5, 1e-9);
	EXPECT_NEAR(s.ty, -47.25, 1e-9);
	EXPECT_LT((s.apply(src) - dst).cwiseAbs().maxCoeff(), 1e-9);
	// The inverse undoes it.
	EXPECT_LT((s.inverse().apply(dst) - src).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Similarity, weightsDecideWhichPointsTheFitFollows) {
	Points src = randomShape(20, 2);
	Similarity truth = Similarity::fromScaleAngle(0.8, -0.3, 10, 20);
	Points dst = truth.apply(src);
	dst.row(0) += Eigen::RowVector2d(80, -60);  // one point moved far away (a "dynamic" point)
	Eigen::VectorXd equal = Eigen::VectorXd::Ones(20);
	Eigen::VectorXd ignoreMoved = equal;
	ignoreMoved(0) = 0;
	Eigen::VectorXd lowMoved = equal;
	lowMoved(0) = 0.2;
	Similarity a = alignSimilarity(src, dst, equal);
	Similarity b = alignSimilarity(src, dst, ignoreMoved);
	Similarity c = alignSimilarity(src, dst, lowMoved);
	// Weight 0: the moved point has no influence, the transform is recovered exactly.
	EXPECT_NEAR(b.scale(), 0.8, 1e-9);
	EXPECT_NEAR(b.angle(), -0.3, 1e-9);
	// Equal weights: the fit is pulled towards the moved point; a lower weight pulls less.
	double errA = std::abs(a.tx - 10) + std::abs(a.ty - 20);
	double errC = std::abs(c.tx - 10) + std::abs(c.ty - 20);
	EXPECT_GT(errA, 1.0);
	EXPECT_LT(errC, errA);
	EXPECT_GT(errC, 1e-6);
}

TEST(Procrustes, syntheticSetRecoversTheCommonShape) {
	Points base = randomShape(30, 3);
	std::vector<Points> shapes;
	for (int i = 0; i < 25; ++i)
		shapes.push_back(Similarity::fromScaleAngle(0.7 + 0.03 * i, 0.05 * i - 0.5, 7.0 * i, -3.0 * i).apply(base));
	ProcrustesResult r = generalizedProcrustes(shapes, Eigen::VectorXd::Ones(30));
	EXPECT_TRUE(r.converged);
	for (const auto& a : r.aligned) EXPECT_LT((a - r.mean).cwiseAbs().maxCoeff(), 1e-6);
	// The mean keeps the reference shape's pose and size.
	EXPECT_LT((r.mean - shapes[r.reference]).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Procrustes, immFrontalShapesConvergeWithNormalisedMean) {
	SKIP_WITHOUT_IMM();
	const Corpus& c = test::immCorpus();
	ASSERT_EQ(c.entries.size(), 120u);
	std::vector<Points> shapes;
	for (const auto& e : c.entries) shapes.push_back(e.points);
	Scheme scheme = loadScheme("imm-73");
	ProcrustesResult r = generalizedProcrustes(shapes, scheme.weights);
	EXPECT_TRUE(r.converged);
	EXPECT_LE(r.lastChange, 1e-4);
	EXPECT_LT(r.iterations, 20);
	// Normalised: aligning the mean to the reference shape is the identity.
	Similarity s = alignSimilarity(r.mean, shapes[r.reference], scheme.weights);
	EXPECT_NEAR(s.scale(), 1.0, 1e-6);
	EXPECT_NEAR(s.angle(), 0.0, 1e-6);
	EXPECT_NEAR(s.tx, 0.0, 1e-3);
	EXPECT_NEAR(s.ty, 0.0, 1e-3);
	// The mean of the aligned shapes is close to the normalised mean but not equal to it: aligning to
	// a target shrinks shapes slightly (decisions.md: c̄ uses the column mean, s̄ the GPA mean).
	Points avg = Points::Zero(73, 2);
	for (const auto& a : r.aligned) avg += a;
	avg /= 120.0;
	const double extent = (r.mean.colwise().maxCoeff() - r.mean.colwise().minCoeff()).maxCoeff();
	EXPECT_LT((avg - r.mean).cwiseAbs().maxCoeff(), 0.005 * extent);
	// Deterministic.
	ProcrustesResult again = generalizedProcrustes(shapes, scheme.weights);
	EXPECT_EQ(again.reference, r.reference);
	EXPECT_EQ((again.mean - r.mean).cwiseAbs().maxCoeff(), 0.0);
}
