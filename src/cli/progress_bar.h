// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <string>

#include "base/progress.h"

namespace talkhead::cli {

// Draws a one-line progress bar on stderr when stderr is a terminal (and not quiet); silent otherwise.
class ProgressBar final : public ProgressSink {
public:
	explicit ProgressBar(bool quiet = false);
	~ProgressBar() override;
	void report(double fraction, const std::string& stage) override;
	void finish();

private:
	bool enabled_;
	bool drawn_ = false;
	int lastPermille_ = -1;
	std::string lastStage_;
	std::chrono::steady_clock::time_point start_;
};

}  // namespace talkhead::cli
