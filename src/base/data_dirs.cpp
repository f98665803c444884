// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/data_dirs.h"

#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace talkhead {

std::vector<std::string> dataDirs() {
	std::vector<std::string> dirs;
	if (const char* env = std::getenv("TALKHEAD_DATA_DIR"); env && *env) dirs.emplace_back(env);
	std::error_code ec;
	fs::path exe = fs::read_symlink("/proc/self/exe", ec);
	if (!ec) dirs.push_back((exe.parent_path().parent_path() / "share" / "talkhead").string());
#ifdef TALKHEAD_DATA_INSTALL_DIR
	dirs.emplace_back(TALKHEAD_DATA_INSTALL_DIR);  // a program linking the installed library, anywhere
#endif
#ifdef TALKHEAD_SOURCE_DIR
	dirs.emplace_back(TALKHEAD_SOURCE_DIR "/models");
	dirs.emplace_back(TALKHEAD_SOURCE_DIR);
#endif
	// Data made at build time (models/au-appearance.bin): beside the executable in a build tree, or the build tree.
	if (!ec) dirs.push_back(exe.parent_path().string());
#ifdef TALKHEAD_BINARY_DIR
	dirs.emplace_back(TALKHEAD_BINARY_DIR);
#endif
	if (const std::string cache = userCacheDir(); !cache.empty()) dirs.push_back(cache);
	return dirs;
}

std::string userCacheDir() {
	if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x == '/') return (fs::path(x) / "talkhead").string();
	if (const char* h = std::getenv("HOME"); h && *h == '/') return (fs::path(h) / ".cache" / "talkhead").string();
	return "";
}

std::optional<std::string> findDataFile(const std::string& relative) {
	for (const auto& d : dataDirs()) {
		fs::path p = fs::path(d) / relative;
		std::error_code ec;
		if (fs::is_regular_file(p, ec)) return p.string();
	}
	return std::nullopt;
}

}  // namespace talkhead

namespace talkhead {

std::vector<std::string> defaultModelCandidates() {
	std::vector<std::string> c;
	if (const char* env = std::getenv("TALKHEAD_MODEL"); env && *env) c.emplace_back(env);
	std::error_code ec;
	fs::path exe = fs::read_symlink("/proc/self/exe", ec);
	if (!ec) {
		c.push_back((exe.parent_path() / "models" / "default.thm").string());
		c.push_back((exe.parent_path().parent_path() / "share" / "talkhead" / "models" / "default.thm").string());
	}
#ifdef TALKHEAD_DATA_INSTALL_DIR
	c.emplace_back(TALKHEAD_DATA_INSTALL_DIR "/models/default.thm");
#endif
#ifdef TALKHEAD_BINARY_DIR
	c.emplace_back(TALKHEAD_BINARY_DIR "/models/default.thm");
#endif
	if (const std::string cache = userCacheDir(); !cache.empty()) c.push_back((fs::path(cache) / "models" / "default.thm").string());
	return c;
}

std::optional<std::string> findDefaultModel() {
	for (const auto& p : defaultModelCandidates()) {
		std::error_code ec;
		if (fs::is_regular_file(p, ec)) return p;
	}
	return std::nullopt;
}

}  // namespace talkhead
