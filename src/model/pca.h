// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <Eigen/Core>

namespace talkhead {

struct PcaOptions {
	int maxComponents = 0;  // 0 = keep every non-null component
	double evr = 1.0;       // < 1: keep the fewest components whose cumulative EVR reaches this
};

// Correlation-matrix PCA of Costa 2015 §4.1.4–4.1.6 ("corrAAM"): columns standardised to zero mean and
// unit standard deviation (m − 1 denominator), eigenvectors of Cov(H) = HᵀH / m found through the m × m
// Gram matrix (Turk–Pentland), sorted by eigenvalue.
struct CorrelationPca {
	Eigen::VectorXf mean;                  // n: column means c̄
	Eigen::VectorXf sigma;                 // n: column standard deviations σ_j (1 where a column is constant)
	Eigen::MatrixXf basis;                 // n × l: column i is the unit eigenvector h_i
	Eigen::VectorXd eigenvalues;           // every non-null eigenvalue λ_i (descending), including dropped ones
	Eigen::MatrixXf trainingCoefficients;  // m × l: α of each training row (α_i = hᵀh_i)

	Eigen::Index components() const { return basis.cols(); }
	double explainedVarianceRatio(Eigen::Index i) const { return eigenvalues(i) / eigenvalues.sum(); }
	// Fewest components whose cumulative EVR reaches `fraction` (≤ number of non-null components).
	Eigen::Index componentsFor(double fraction) const;
};

// samples: n × m, one sample per COLUMN (the thesis's C transposed, so each sample is contiguous); it is
// standardised in place (it becomes Hᵀ). Constant variables get σ = 1 (they are zero in H and carry no
// variance), so they never produce NaN. Components with λ ≤ 1e-10 · λ_max are null (H is centred, so
// its rank is at most m − 1) and are dropped.
CorrelationPca correlationPca(Eigen::MatrixXf& samples, const PcaOptions& options = {});

// α = ((c − c̄) / σ) · basis, for one sample c (n).
Eigen::VectorXf pcaProject(const CorrelationPca& pca, const Eigen::Ref<const Eigen::VectorXf>& sample);
// c = c̄ + σ ∘ (basis · α) over rows [begin, begin + count) of the vector (appearance or shape part).
Eigen::VectorXf pcaReconstruct(const CorrelationPca& pca, const Eigen::Ref<const Eigen::VectorXf>& coefficients,
                               Eigen::Index begin, Eigen::Index count);

}  // namespace talkhead
