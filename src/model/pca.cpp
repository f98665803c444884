// SPDX-License-Identifier: GPL-3.0-or-later
// Eigen-heavy translation unit: standardisation, Gram matrix, eigen-decomposition.
#include "model/pca.h"

#include "base/memory.h"
#include "geometry/eigen_products.h"

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

CorrelationPca correlationPca(Eigen::MatrixXf& Ht, const PcaOptions& options) {
	const Eigen::Index n = Ht.rows(), m = Ht.cols();
	if (m < 2) throw std::invalid_argument("PCA needs at least 2 samples");
	pinEigenBlocking();  // the Gram matrix and the eigen-solver's products round the same everywhere (D74)
	CorrelationPca r;
	// Eq. 4.11–4.15: per-variable standardisation, accumulated in double, one sample column at a time.
	Eigen::VectorXd sum = Eigen::VectorXd::Zero(n), sumSq = Eigen::VectorXd::Zero(n);
	for (Eigen::Index i = 0; i < m; ++i) sum += Ht.col(i).cast<double>();
	const Eigen::VectorXd mean = sum / double(m);
	for (Eigen::Index i = 0; i < m; ++i) sumSq += (Ht.col(i).cast<double>() - mean).array().square().matrix();
	Eigen::VectorXd sd = (sumSq / double(m - 1)).cwiseSqrt();
	for (Eigen::Index j = 0; j < n; ++j)
		if (!(sd(j) > 1e-6 * std::max(1.0, std::abs(mean(j))))) sd(j) = 1.0;  // constant variable
	const Eigen::VectorXd inv = sd.cwiseInverse();
	for (Eigen::Index i = 0; i < m; ++i) Ht.col(i) = ((Ht.col(i).cast<double>() - mean).cwiseProduct(inv)).cast<float>();
	r.mean = mean.cast<float>();
	r.sigma = sd.cast<float>();
	// Gram matrix H·Hᵀ (m × m) in double, over row blocks of Hᵀ so it never needs a double copy.
	Eigen::MatrixXd G = Eigen::MatrixXd::Zero(m, m);
	const Eigen::Index block = 1024;
	for (Eigen::Index j = 0; j < n; j += block) {
		const Eigen::Index b = std::min(block, n - j);
		Eigen::MatrixXd Hb = Ht.middleRows(j, b).transpose().cast<double>();  // m × b
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
	r.basis.resize(n, keep);
	adviseHugePages(r.basis.data(), std::size_t(r.basis.size()) * sizeof(float));
	productInRowChunks(Ht, Vs, r.basis);
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
