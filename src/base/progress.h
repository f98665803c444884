// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
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

}  // namespace talkhead
