// SPDX-License-Identifier: GPL-3.0-or-later
#include <opencv2/imgproc.hpp>

#include "image/image.h"

#include <algorithm>

namespace talkhead {

double ssim(const Image& a, const Image& b, const std::vector<std::uint8_t>& mask) {
	if (a.width != b.width || a.height != b.height || a.channels != b.channels)
		throw std::logic_error("ssim: image sizes differ");
	if (!mask.empty() && mask.size() != a.pixelCount()) throw std::logic_error("ssim: mask size differs");
	const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
	// Only the mask's bounding box (plus the window's reach) matters.
	cv::Rect box(0, 0, a.width, a.height);
	if (!mask.empty()) {
		int x0 = a.width, y0 = a.height, x1 = -1, y1 = -1;
		for (int y = 0; y < a.height; ++y)
			for (int x = 0; x < a.width; ++x)
				if (mask[std::size_t(y) * a.width + x]) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
		if (x1 < 0) return 1.0;
		box = cv::Rect(x0 - 8, y0 - 8, x1 - x0 + 17, y1 - y0 + 17) & box;
	}
	cv::Mat ma(a.height, a.width, CV_32FC(a.channels), const_cast<float*>(a.data.data()));
	cv::Mat mb(b.height, b.width, CV_32FC(b.channels), const_cast<float*>(b.data.data()));
	std::vector<cv::Mat> ca, cb;
	cv::split(ma(box), ca);
	cv::split(mb(box), cb);
	double total = 0;
	std::size_t count = 0;
	const cv::Size win(11, 11);
	for (int c = 0; c < a.channels; ++c) {
		cv::Mat x, y, xx, yy, xy, mx, my, sxx, syy, sxy;
		ca[c].convertTo(x, CV_64F);
		cb[c].convertTo(y, CV_64F);
		cv::GaussianBlur(x, mx, win, 1.5);
		cv::GaussianBlur(y, my, win, 1.5);
		cv::GaussianBlur(x.mul(x), sxx, win, 1.5);
		cv::GaussianBlur(y.mul(y), syy, win, 1.5);
		cv::GaussianBlur(x.mul(y), sxy, win, 1.5);
		for (int r = 0; r < box.height; ++r) {
			const double *pmx = mx.ptr<double>(r), *pmy = my.ptr<double>(r), *pxx = sxx.ptr<double>(r),
			             *pyy = syy.ptr<double>(r), *pxy = sxy.ptr<double>(r);
			for (int col = 0; col < box.width; ++col) {
				if (!mask.empty() && !mask[std::size_t(r + box.y) * a.width + col + box.x]) continue;
				double ux = pmx[col], uy = pmy[col];
				double vx = pxx[col] - ux * ux, vy = pyy[col] - uy * uy, cxy = pxy[col] - ux * uy;
				total += ((2 * ux * uy + c1) * (2 * cxy + c2)) / ((ux * ux + uy * uy + c1) * (vx + vy + c2));
				++count;
			}
		}
	}
	return count ? total / count : 1.0;
}

}  // namespace talkhead
