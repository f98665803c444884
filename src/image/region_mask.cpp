// SPDX-License-Identifier: GPL-3.0-or-later
#include "image/region_mask.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace talkhead {

Points closedCatmullRom(const Points& b, int samplesPerSegment) {
	const Eigen::Index n = b.rows();
	Points out(n * samplesPerSegment, 2);
	for (Eigen::Index i = 0; i < n; ++i) {
		Eigen::RowVector2d p0 = b.row((i + n - 1) % n), p1 = b.row(i), p2 = b.row((i + 1) % n), p3 = b.row((i + 2) % n);
		for (int s = 0; s < samplesPerSegment; ++s) {
			double t = double(s) / samplesPerSegment, t2 = t * t, t3 = t2 * t;
			out.row(i * samplesPerSegment + s) =
			    0.5 * ((2 * p1) + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2 + (-p0 + 3 * p1 - 3 * p2 + p3) * t3);
		}
	}
	return out;
}

static Points grownCurve(const Points& boundary, double grow) {
	Points curve = closedCatmullRom(boundary);
	Eigen::RowVector2d c = boundary.colwise().mean();
	return (curve.rowwise() - c) * (1.0 + grow) + c.replicate(curve.rows(), 1);
}

double regionArea(const Points& boundary, double grow) {
	Points c = grownCurve(boundary, grow);
	double a = 0;
	for (Eigen::Index i = 0; i < c.rows(); ++i) {
		Eigen::Index j = (i + 1) % c.rows();
		a += c(i, 0) * c(j, 1) - c(j, 0) * c(i, 1);
	}
	return std::abs(a) / 2;
}

std::vector<float> softRegionMask(const Points& boundary, double grow, double featherPx, int width, int height) {
	Points curve = grownCurve(boundary, grow);
	// Fill with 8× sub-pixel precision (cv::fillPoly shift) for a stable edge.
	constexpr int shift = 3;
	std::vector<cv::Point> poly;
	poly.reserve(curve.rows());
	for (Eigen::Index i = 0; i < curve.rows(); ++i)
		poly.emplace_back(int(std::lround(curve(i, 0) * (1 << shift))), int(std::lround(curve(i, 1) * (1 << shift))));
	cv::Mat inside = cv::Mat::zeros(height, width, CV_8U);
	cv::fillPoly(inside, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(255), cv::LINE_8, shift);
	std::vector<float> alpha(std::size_t(width) * height, 0.f);
	if (featherPx <= 0) {
		for (std::size_t i = 0; i < alpha.size(); ++i) alpha[i] = inside.data[i] ? 1.f : 0.f;
		return alpha;
	}
	cv::Mat dist;
	cv::distanceTransform(inside, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
	for (int y = 0; y < height; ++y) {
		const float* d = dist.ptr<float>(y);
		for (int x = 0; x < width; ++x) {
			// distanceTransform gives the distance to the nearest outside pixel; −0.5 puts 0 on the curve.
			double t = std::clamp((d[x] - 0.5) / featherPx, 0.0, 1.0);
			alpha[std::size_t(y) * width + x] = float(t * t * (3 - 2 * t));
		}
	}
	return alpha;
}

}  // namespace talkhead
