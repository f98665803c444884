// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/matte.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace talkhead {

FaceMatte::FaceMatte(const Scheme& scheme, MatteOptions options) : options_(options) {
	for (const BrowSpec& b : scheme.brows) brows_.insert(brows_.end(), b.points.begin(), b.points.end());
}

double FaceMatte::feather(double faceWidth) const { return options_.feather > 0 ? options_.feather : std::max(1.5, 0.02 * faceWidth); }

void FaceMatte::draw(const Points& points, int width, int height, std::vector<std::uint8_t>& alpha) const {
	alpha.assign(std::size_t(width) * std::size_t(height), 0);
	if (points.rows() < 3 || width < 1 || height < 1) return;
	thread_local std::vector<cv::Point2f> cloud;
	thread_local std::vector<cv::Point2f> hull;
	thread_local std::vector<cv::Point> outline;
	thread_local cv::Mat scratch;
	cloud.clear();
	double top = points(0, 1), bottom = points(0, 1), left = points(0, 0), right = points(0, 0);
	for (Eigen::Index i = 0; i < points.rows(); ++i) {
		cloud.emplace_back(float(points(i, 0)), float(points(i, 1)));
		top = std::min(top, points(i, 1)), bottom = std::max(bottom, points(i, 1));
		left = std::min(left, points(i, 0)), right = std::max(right, points(i, 0));
	}
	// A forehead where the scheme has brows and nothing above them: an arc over the brows, half the
	// brow-to-chin height high.
	double browY = top, browLeft = left, browRight = right;
	if (!brows_.empty()) {
		browY = 0, browLeft = 1e300, browRight = -1e300;
		for (int b : brows_) {
			browY += points(b, 1) / double(brows_.size());
			browLeft = std::min(browLeft, points(b, 0)), browRight = std::max(browRight, points(b, 0));
		}
	}
	const double browToChin = bottom - browY;
	if (!brows_.empty() && browToChin > 0 && top > browY - 0.25 * browToChin) {
		const double cx = 0.5 * (browLeft + browRight), a = 0.55 * (browRight - browLeft), b = 0.5 * browToChin;
		for (int k = 0; k <= 12; ++k) {
			const double t = M_PI * k / 12;
			cloud.emplace_back(float(cx + a * std::cos(t)), float(browY - b * std::sin(t)));
		}
	}
	cv::convexHull(cloud, hull);
	const double sigma = feather(right - left);
	double mx = 0, my = 0;
	for (const auto& p : hull) mx += p.x / double(hull.size()), my += p.y / double(hull.size());
	// Pushed out by 2σ (the outline itself opaque), in 1/16 pixels.
	outline.clear();
	int x0 = width, y0 = height, x1 = -1, y1 = -1;
	for (const auto& p : hull) {
		const double dx = p.x - mx, dy = p.y - my, n = std::max(1e-9, std::hypot(dx, dy));
		const double x = p.x + 2 * sigma * dx / n, y = p.y + 2 * sigma * dy / n;
		outline.emplace_back(int(std::lround(x * 16)), int(std::lround(y * 16)));
		x0 = std::min(x0, int(std::floor(x))), x1 = std::max(x1, int(std::ceil(x)));
		y0 = std::min(y0, int(std::floor(y))), y1 = std::max(y1, int(std::ceil(y)));
	}
	cv::Mat a(height, width, CV_8UC1, alpha.data());
	cv::fillConvexPoly(a, outline.data(), int(outline.size()), cv::Scalar(255), cv::LINE_8, 4);
	const int reach = int(std::ceil(3 * sigma)) + 1;
	const cv::Rect box = cv::Rect(x0 - reach, y0 - reach, x1 - x0 + 2 * reach + 1, y1 - y0 + 2 * reach + 1) & cv::Rect(0, 0, width, height);
	if (box.area() == 0) return;
	if (scratch.rows != height || scratch.cols != width) scratch.create(height, width, CV_8UC1);
	cv::Mat out = scratch(box);
	cv::GaussianBlur(a(box), out, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);  // a face cut by the frame stays opaque to its edge
	out.copyTo(a(box));
}

}  // namespace talkhead
