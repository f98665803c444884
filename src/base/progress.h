// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <string>

namespace talkhead {

// Library code reports progress through this interface and never prints; the CLI renders it.
class ProgressSink {
public:
	virtual ~ProgressSink() = default;
	// fraction in [0, 1]; stage names what is being done ("warping", "PCA face").
	virtual void report(double fraction, const std::string& stage) = 0;
};

class NullProgress final : public ProgressSink {
public:
	void report(double, const std::string&) override {}
};

// Draws a one-line progress bar on stderr when stderr is a terminal (and not quiet); silent otherwise.
class ProgressBar final : public ProgressSink {
public:
	explicit ProgressBar(bool quiet = false);
	~ProgressBar() override;
	void report(double fraction, const std::string& stage) override;
	void finish();  // erases the bar

private:
	bool enabled_;
	bool drawn_ = false;
	int lastPermille_ = -1;
	std::string lastStage_;
	std::chrono::steady_clock::time_point start_;
};

}  // namespace talkhead
