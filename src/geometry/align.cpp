// SPDX-License-Identifier: GPL-3.0-or-later
// Similarity alignment and generalised Procrustes (Costa 2015 §4.1.1; Cootes et al. 1995).
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/shape.h"

namespace talkhead {

double Similarity::scale() const { return std::hypot(a, b); }
double Similarity::angle() const { return std::atan2(b, a); }

Points Similarity::apply(const Points& p) const {
	Points q(p.rows(), 2);
	for (Eigen::Index i = 0; i < p.rows(); ++i) {
		q(i, 0) = a * p(i, 0) - b * p(i, 1) + tx;
		q(i, 1) = b * p(i, 0) + a * p(i, 1) + ty;
	}
	return q;
}

Similarity Similarity::inverse() const {
	double d = a * a + b * b;
	Similarity r;
	r.a = a / d;
	r.b = -b / d;
	r.tx = -(r.a * tx - r.b * ty);
	r.ty = -(r.b * tx + r.a * ty);
	return r;
}

Similarity Similarity::fromScaleAngle(double scale, double angleRad, double tx, double ty) {
	return Similarity{scale * std::cos(angleRad), scale * std::sin(angleRad), tx, ty};
}

Similarity alignSimilarity(const Points& from, const Points& to, const Eigen::VectorXd& weights) {
	if (from.rows() != to.rows() || from.rows() != weights.size())
		throw std::logic_error("alignSimilarity: point counts differ");
	double wsum = weights.sum();
	if (!(wsum > 0)) throw std::logic_error("alignSimilarity: weights sum to zero");
	// Weighted centroids; the closed form of Cootes' 4×4 system after centring.
	Eigen::RowVector2d cf = (weights.transpose() * from) / wsum;
	Eigen::RowVector2d ct = (weights.transpose() * to) / wsum;
	double z = 0, c1 = 0, c2 = 0;
	for (Eigen::Index k = 0; k < from.rows(); ++k) {
		double w = weights(k);
		double x2 = from(k, 0) - cf(0), y2 = from(k, 1) - cf(1);
		double x1 = to(k, 0) - ct(0), y1 = to(k, 1) - ct(1);
		z += w * (x2 * x2 + y2 * y2);
		c1 += w * (x1 * x2 + y1 * y2);
		c2 += w * (y1 * x2 - x1 * y2);
	}
	Similarity s;
	if (z <= 0) {  // all weighted points coincide: translation only
		s.a = 1;
		s.b = 0;
	} else {
		s.a = c1 / z;
		s.b = c2 / z;
	}
	s.tx = ct(0) - (s.a * cf(0) - s.b * cf(1));
	s.ty = ct(1) - (s.b * cf(0) + s.a * cf(1));
	return s;
}

double weightedDistance2(const Points& p, const Points& q, const Eigen::VectorXd& weights) {
	return (weights.array() * (p - q).rowwise().squaredNorm().array()).sum();
}

std::size_t nearestShape(const std::vector<Points>& shapes, const Points& target) {
	std::size_t best = 0;
	double bestD = std::numeric_limits<double>::infinity();
	for (std::size_t i = 0; i < shapes.size(); ++i) {
		double d = (shapes[i] - target).squaredNorm();
		if (d < bestD) {
			bestD = d;
			best = i;
		}
	}
	return best;
}

ProcrustesResult generalizedProcrustes(const std::vector<Points>& shapes, const Eigen::VectorXd& weights,
                                       const ProcrustesOptions& options) {
	if (shapes.empty()) throw std::logic_error("generalizedProcrustes: no shapes");
	const std::size_t m = shapes.size();
	ProcrustesResult r;

	// Deterministic reference: the medoid under weighted similarity-aligned distance. For large sets
	// only every step-th shape is a candidate partner, which keeps this O(m·64).
	const std::size_t step = std::max<std::size_t>(1, m / 64);
	double bestCost = std::numeric_limits<double>::infinity();
	for (std::size_t i = 0; i < m; ++i) {
		double cost = 0;
		const Points centred = shapes[i].rowwise() - shapes[i].colwise().mean();
		const double size2 = std::max(1e-12, centred.squaredNorm());
		for (std::size_t j = 0; j < m; j += step) {
			if (i == j) continue;
			Similarity t = alignSimilarity(shapes[j], shapes[i], weights);
			cost += weightedDistance2(t.apply(shapes[j]), shapes[i], weights) / size2;
		}
		if (cost < bestCost) {
			bestCost = cost;
			r.reference = i;
		}
	}
	const Points& reference = shapes[r.reference];

	r.aligned.resize(m);
	r.transforms.resize(m);
	Points target = reference;
	Points previousMean;
	for (int iter = 0; iter <= options.maxIterations; ++iter) {
		for (std::size_t i = 0; i < m; ++i) {
			r.transforms[i] = alignSimilarity(shapes[i], target, weights);
			r.aligned[i] = r.transforms[i].apply(shapes[i]);
		}
		if (iter == options.maxIterations) break;
		Points mean = Points::Zero(reference.rows(), 2);
		for (const auto& s : r.aligned) mean += s;
		mean /= static_cast<double>(m);
		r.iterations = iter + 1;
		if (iter > 0) {
			r.lastChange = (mean - previousMean).cwiseAbs().sum();
			if (r.lastChange <= options.tolerance) {
				r.converged = true;
				previousMean = mean;
				target = alignSimilarity(mean, reference, weights).apply(mean);
				for (std::size_t i = 0; i < m; ++i) {
					r.transforms[i] = alignSimilarity(shapes[i], target, weights);
					r.aligned[i] = r.transforms[i].apply(shapes[i]);
				}
				break;
			}
		}
		previousMean = mean;
		// Normalise the mean's pose and size to the reference (stops shrinking and drift).
		target = alignSimilarity(mean, reference, weights).apply(mean);
	}
	r.mean = target;
	return r;
}

}  // namespace talkhead
