// SPDX-License-Identifier: GPL-3.0-or-later
// BRISQUE (Mittal et al. 2012; OpenCV's quality module with the LIVE model of Debian's opencv-data) of each
// image named: "SCORE PATH" per line, lower is better (bench/fidelity.sh).
//   bench_brisque MODEL.yml RANGE.yml IMAGE.png...
#include <cstdio>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/quality/qualitybrisque.hpp>

#include "media/image_io.h"

int main(int argc, char** argv) {
	if (argc < 4) {
		std::fprintf(stderr, "usage: bench_brisque MODEL.yml RANGE.yml IMAGE.png...\n");
		return 2;
	}
	try {
		for (int i = 3; i < argc; ++i) {
			const talkhead::Image8 im = talkhead::readImage(argv[i]);
			cv::Mat rgb(im.height, im.width, im.channels == 3 ? CV_8UC3 : CV_8UC1, const_cast<std::uint8_t*>(im.data.data())), bgr;
			if (im.channels == 3) cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
			else bgr = rgb;
			const cv::Scalar s = cv::quality::QualityBRISQUE::compute(bgr, argv[1], argv[2]);
			std::printf("%.3f %s\n", s[0], argv[i]);
		}
	} catch (const std::exception& e) {
		std::fprintf(stderr, "bench_brisque: %s\n", e.what());
		return 1;
	}
	return 0;
}
