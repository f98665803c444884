// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/output_dir.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "base/error.h"
#include "base/interrupt.h"
#include "cli/args.h"

namespace talkhead::cli {

namespace fs = std::filesystem;

OutputDir::OutputDir(const std::string& target) : target_(target) {
	fs::path t(target);
	if (fs::exists(t) && !fs::is_directory(t)) throw Error(target, 0, "exists and is not a folder");
	fs::path parent = t.parent_path().empty() ? fs::path(".") : t.parent_path();
	std::error_code ec;
	fs::create_directories(parent, ec);
	staging_ = (parent / (".tmp-" + std::to_string(::getpid()) + "-" + t.filename().string())).string();
	registerTemporaryFolder(staging_);  // emptied and removed on a signal (base/interrupt.h)
	fs::remove_all(staging_, ec);
	if (!fs::create_directories(staging_, ec) || ec) {
		releaseTemporary(staging_);
		throw Error(target, 0, "cannot create the output folder (" + ec.message() + ")");
	}
}

OutputDir::~OutputDir() {
	if (!committed_) {
		std::error_code ec;
		fs::remove_all(staging_, ec);
	}
	releaseTemporary(staging_);
}

std::string OutputDir::path(const std::string& name) const { return (fs::path(staging_) / name).string(); }

void OutputDir::commit() {
	std::error_code ec;
	if (!fs::exists(target_)) {
		fs::rename(staging_, target_, ec);
		if (ec) throw Error(target_, 0, "cannot create the output folder (" + ec.message() + ")");
	} else {
		for (const auto& e : fs::directory_iterator(staging_)) {
			const fs::path dst = fs::path(target_) / e.path().filename();
			if (fs::is_directory(dst) && e.is_directory()) fs::remove_all(dst, ec);
			fs::rename(e.path(), dst, ec);
			if (ec) throw Error(dst.string(), 0, "cannot write (" + ec.message() + ")");
		}
		fs::remove_all(staging_, ec);
	}
	committed_ = true;
}

double parseTimeOption(const std::string& option, const std::string& value) {
	double minutes = 0, seconds = 0;
	std::size_t used = 0;
	try {
		const auto colon = value.find(':');
		if (colon != std::string::npos) {
			minutes = std::stod(value.substr(0, colon), &used);
			if (used != colon) throw std::invalid_argument("");
			const std::string rest = value.substr(colon + 1);
			seconds = std::stod(rest, &used);
			if (used != rest.size()) throw std::invalid_argument("");
		} else {
			seconds = std::stod(value, &used);
			if (used != value.size()) throw std::invalid_argument("");
		}
	} catch (const std::logic_error&) {
		throw UsageError(option + ": '" + value + "' is not a time (seconds, or minutes:seconds)");
	}
	const double t = minutes * 60 + seconds;
	if (!std::isfinite(t) || t < 0 || t > 24 * 3600) throw UsageError(option + ": '" + value + "' is out of range");
	return t;
}

}  // namespace talkhead::cli
