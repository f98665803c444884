// SPDX-License-Identifier: GPL-3.0-or-later
// Eigen-heavy translation unit: standardisation, Gram matrix, eigen-decomposition.
#include "model/pca.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

namespace talkhead {

Eigen::Index CorrelationPca::componentsFor(double fraction) const {
	const double total = eigenvalues.sum();
	double acc = 0;
	for (Eigen::Index i = 0; i < eigenvalues.size(); ++i) {
		acc += eigenvalues(i);
		if (acc >= fraction * total * (1 - 1e-12)) return i + 1;
	}
	return eigenvalues.size();
}

CorrelationPca correlationPca(Eigen::MatrixXf& H, const PcaOptions& options) {
	const Eigen::Index m = H.rows(), n = H.cols();
	if (m < 2) throw std::invalid_argument("PCA needs at least 2 samples");
	CorrelationPca r;
	r.mean.resize(n);
	r.sigma.resize(n);
	// Eq. 4.11–4.15: per-column standardisation, accumulated in double.
	for (Eigen::Index j = 0; j < n; ++j) {
		float* col = H.col(j).data();
		double s = 0;
		for (Eigen::Index i = 0; i < m; ++i) s += col[i];
		const double mean = s / m;
		double ss = 0;
		for (Eigen::Index i = 0; i < m; ++i) ss += (col[i] - mean) * (col[i] - mean);
		double sd = std::sqrt(ss / (m - 1));
		if (!(sd > 1e-6 * std::max(1.0, std::abs(mean)))) sd = 1.0;  // constant column
		for (Eigen::Index i = 0; i < m; ++i) col[i] = float((col[i] - mean) / sd);
		r.mean(j) = float(mean);
		r.sigma(j) = float(sd);
	}
	// Gram matrix H·Hᵀ (m × m) in double, in column blocks so H never needs a double copy.
	Eigen::MatrixXd G = Eigen::MatrixXd::Zero(m, m);
	const Eigen::Index block = 2048;
	for (Eigen::Index j = 0; j < n; j += block) {
		const Eigen::Index b = std::min(block, n - j);
		Eigen::MatrixXd Hb = H.middleCols(j, b).cast<double>();
		G.selfadjointView<Eigen::Lower>().rankUpdate(Hb);
	}
	G.triangularView<Eigen::StrictlyUpper>() = G.transpose();
	Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(G);
	if (es.info() != Eigen::Success) throw std::runtime_error("PCA: eigen-decomposition failed");
	// Ascending → descending; μ = m·λ.
	const Eigen::VectorXd mu = es.eigenvalues().reverse();
	const Eigen::MatrixXd V = es.eigenvectors().rowwise().reverse();
	Eigen::Index rank = 0;
	const double muMax = std::max(0.0, mu(0));
	while (rank < m && mu(rank) > 1e-10 * muMax && mu(rank) > 0) ++rank;
	r.eigenvalues = mu.head(rank) / double(m);

	Eigen::Index keep = rank;
	if (options.maxComponents > 0) keep = std::min<Eigen::Index>(keep, options.maxComponents);
	if (options.evr < 1.0) keep = std::min(keep, r.componentsFor(options.evr));
	keep = std::max<Eigen::Index>(keep, std::min<Eigen::Index>(rank, 1));

	// Turk–Pentland: h_i = Hᵀ v_i / sqrt(μ_i); training coefficients α_i = H h_i = sqrt(μ_i) v_i.
	Eigen::MatrixXf Vs(m, keep);
	r.trainingCoefficients.resize(m, keep);
	for (Eigen::Index i = 0; i < keep; ++i) {
		const double s = std::sqrt(mu(i));
		Vs.col(i) = (V.col(i) / s).cast<float>();
		r.trainingCoefficients.col(i) = (V.col(i) * s).cast<float>();
	}
	r.basis.noalias() = H.transpose() * Vs;
	return r;
}

Eigen::VectorXf pcaProject(const CorrelationPca& pca, const Eigen::Ref<const Eigen::VectorXf>& sample) {
	Eigen::VectorXf h = (sample - pca.mean).cwiseQuotient(pca.sigma);
	return pca.basis.transpose() * h;
}

Eigen::VectorXf pcaReconstruct(const CorrelationPca& pca, const Eigen::Ref<const Eigen::VectorXf>& coefficients,
                               Eigen::Index begin, Eigen::Index count) {
	const Eigen::Index l = std::min<Eigen::Index>(coefficients.size(), pca.basis.cols());
	Eigen::VectorXf v = pca.basis.block(begin, 0, count, l) * coefficients.head(l);
	return pca.mean.segment(begin, count) + pca.sigma.segment(begin, count).cwiseProduct(v);
}

}  // namespace talkhead
