// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/progress.h"

#include <unistd.h>

#include <cstdio>

namespace talkhead {

ProgressBar::ProgressBar(bool quiet) : enabled_(!quiet && ::isatty(2)), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::report(double fraction, const std::string& stage) {
	if (!enabled_) return;
	int permille = int(fraction * 1000);
	if (permille == lastPermille_ && stage == lastStage_) return;
	lastPermille_ = permille;
	lastStage_ = stage;
	const int width = 30;
	int filled = int(fraction * width + 0.5);
	double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
	std::fprintf(stderr, "\r[%.*s%*s] %5.1f%% %6.1fs  %-24.24s", filled, "##############################", width - filled, "",
	             fraction * 100.0, secs, stage.c_str());
	std::fflush(stderr);
	drawn_ = true;
}

void ProgressBar::finish() {
	if (drawn_) {
		std::fprintf(stderr, "\r%*s\r", 80, "");
		std::fflush(stderr);
		drawn_ = false;
	}
}

}  // namespace talkhead
