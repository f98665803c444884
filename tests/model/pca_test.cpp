// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

#include "model/pca.h"

using namespace talkhead;

namespace {
// m samples of n variables with a few strong latent factors, different units per column, and one
// constant column.
Eigen::MatrixXf sampleData(int m, int n, unsigned seed) {
	std::mt19937 rng(seed);
	std::normal_distribution<float> g;
	Eigen::MatrixXf latent(m, 4), load(4, n), data(m, n);
	for (int i = 0; i < latent.size(); ++i) latent.data()[i] = g(rng);
	for (int i = 0; i < load.size(); ++i) load.data()[i] = g(rng);
	data = latent * load;
	for (int i = 0; i < data.size(); ++i) data.data()[i] += 0.3f * g(rng);
	for (int j = 0; j < n; ++j) data.col(j) = data.col(j) * (1.0f + float(j % 7) * 40.f) + Eigen::VectorXf::Constant(m, float(j));
	data.col(5).setConstant(128.f);
	return data;
}

Eigen::MatrixXd standardise(const Eigen::MatrixXf& data) {
	Eigen::MatrixXd d = data.cast<double>();
	for (int j = 0; j < d.cols(); ++j) {
		double mean = d.col(j).mean();
		double sd = std::sqrt((d.col(j).array() - mean).square().sum() / (d.rows() - 1));
		d.col(j) = (d.col(j).array() - mean) / (sd > 1e-9 ? sd : 1.0);
	}
	return d;
}
}  // namespace

TEST(CorrelationPca, eigenvaluesMatchDirectSvd) {
	Eigen::MatrixXf data = sampleData(40, 300, 1);
	Eigen::MatrixXd H = standardise(data);
	Eigen::JacobiSVD<Eigen::MatrixXd> svd(H);
	Eigen::VectorXd expected = svd.singularValues().array().square() / double(H.rows());
	Eigen::MatrixXf work = data.transpose();
	CorrelationPca p = correlationPca(work);
	ASSERT_EQ(p.eigenvalues.size(), 39);  // centred: rank m − 1
	for (Eigen::Index i = 0; i < p.eigenvalues.size(); ++i)
		EXPECT_NEAR(p.eigenvalues(i) / expected(i), 1.0, 1e-6) << "eigenvalue " << i;
	EXPECT_NEAR(expected(39) / expected(0), 0.0, 1e-10);
}

TEST(CorrelationPca, evrSumsToOneAndBasisIsOrthonormal) {
	Eigen::MatrixXf data = sampleData(30, 200, 2).transpose();
	CorrelationPca p = correlationPca(data);
	double sum = 0;
	for (Eigen::Index i = 0; i < p.eigenvalues.size(); ++i) sum += p.explainedVarianceRatio(i);
	EXPECT_NEAR(sum, 1.0, 1e-12);
	Eigen::MatrixXf gram = p.basis.transpose() * p.basis;
	EXPECT_LT((gram - Eigen::MatrixXf::Identity(gram.rows(), gram.cols())).cwiseAbs().maxCoeff(), 1e-4);
	for (Eigen::Index i = 1; i < p.eigenvalues.size(); ++i) EXPECT_GE(p.eigenvalues(i - 1), p.eigenvalues(i));
}

TEST(CorrelationPca, constantColumnsGiveNoNaN) {
	Eigen::MatrixXf data = sampleData(20, 50, 3);
	data.col(7).setZero();
	Eigen::MatrixXf work = data.transpose();
	CorrelationPca p = correlationPca(work);
	EXPECT_TRUE(p.basis.allFinite());
	EXPECT_TRUE(p.mean.allFinite());
	EXPECT_EQ(p.sigma(5), 1.0f);
	EXPECT_EQ(p.sigma(7), 1.0f);
	EXPECT_EQ(p.mean(5), 128.0f);
}

TEST(CorrelationPca, allComponentsReconstructTrainingRowsAndProjectionAgrees) {
	const Eigen::MatrixXf data = sampleData(25, 120, 4);
	Eigen::MatrixXf work = data.transpose();
	CorrelationPca p = correlationPca(work);
	for (Eigen::Index i = 0; i < data.rows(); ++i) {
		Eigen::VectorXf row = data.row(i).transpose();
		Eigen::VectorXf alpha = pcaProject(p, row);
		EXPECT_LT((alpha - p.trainingCoefficients.row(i).transpose()).cwiseAbs().maxCoeff(), 2e-3);
		Eigen::VectorXf back = pcaReconstruct(p, alpha, 0, data.cols());
		EXPECT_LT(((back - row).cwiseQuotient(p.sigma)).cwiseAbs().maxCoeff(), 1e-3);
	}
}

TEST(CorrelationPca, truncationByCountAndByEvr) {
	Eigen::MatrixXf a = sampleData(30, 100, 5).transpose(), b = a, c = a;
	CorrelationPca full = correlationPca(a);
	CorrelationPca byCount = correlationPca(b, PcaOptions{5, 1.0});
	CorrelationPca byEvr = correlationPca(c, PcaOptions{0, 0.9});
	EXPECT_EQ(byCount.components(), 5);
	EXPECT_EQ(byEvr.components(), full.componentsFor(0.9));
	EXPECT_LT(byEvr.components(), full.components());
	// Dropped eigenvalues are still reported, so EVR stays relative to the whole.
	EXPECT_EQ(byCount.eigenvalues.size(), full.eigenvalues.size());
	double kept = byEvr.eigenvalues.head(byEvr.components()).sum() / byEvr.eigenvalues.sum();
	EXPECT_GE(kept, 0.9);
}
