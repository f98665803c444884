// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/overlay.h"

#include <opencv2/imgproc.hpp>

namespace talkhead {

namespace {
template <class Colour>
void draw(cv::Mat m, const Points& points, const std::vector<std::string>& lines, Colour light, Colour dark) {
	const double scale = std::max(0.4, m.rows / 1000.0);
	const int r = std::max(2, m.rows / 300);
	int y = int(28 * scale) + 4;
	for (const std::string& line : lines) {
		cv::putText(m, line, {10, y}, cv::FONT_HERSHEY_SIMPLEX, scale, dark, std::max(3, int(4 * scale)), cv::LINE_8);
		cv::putText(m, line, {10, y}, cv::FONT_HERSHEY_SIMPLEX, scale, light, std::max(1, int(1.5 * scale)), cv::LINE_8);
		y += int(30 * scale) + 4;
	}
	auto at = [&](Eigen::Index i) { return cv::Point(int(std::lround(points(i, 0))), int(std::lround(points(i, 1)))); };
	for (Eigen::Index i = 0; i < points.rows(); ++i) cv::circle(m, at(i), r + 1, dark, -1, cv::LINE_8);  // then the points,
	for (Eigen::Index i = 0; i < points.rows(); ++i) cv::circle(m, at(i), r, light, -1, cv::LINE_8);     // outlines first: no dot hides another
}
}  // namespace

void drawDebugOverlay(YuvImage& frame, const Points& points, const std::vector<std::string>& lines) {
	draw(cv::Mat(frame.height, frame.width, CV_8UC1, frame.y.data()), points, lines, cv::Scalar(235), cv::Scalar(16));
}

void drawDebugOverlay(Image8& rgb, const Points& points, const std::vector<std::string>& lines) {
	draw(cv::Mat(rgb.height, rgb.width, CV_8UC3, rgb.data.data()), points, lines, cv::Scalar(255, 255, 255), cv::Scalar(0, 0, 0));
}

}  // namespace talkhead
