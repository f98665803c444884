// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/plugin.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

#include "base/error.h"

namespace fs = std::filesystem;

namespace talkhead {

std::vector<std::string> pluginCandidates(const std::string& fileName) {
	std::vector<std::string> c;
	if (const char* env = std::getenv("TALKHEAD_MODULE_DIR"); env && *env) c.push_back(fs::path(env) / fileName);
	std::error_code ec;
	const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
	if (!ec) {
		c.push_back(exe.parent_path() / "lib" / "talkhead" / fileName);  // build tree
#ifdef TALKHEAD_MODULE_RELATIVE_DIR
		c.push_back(exe.parent_path().parent_path() / TALKHEAD_MODULE_RELATIVE_DIR / fileName);  // installed tree
#endif
	}
#ifdef TALKHEAD_MODULE_INSTALL_DIR
	c.push_back(fs::path(TALKHEAD_MODULE_INSTALL_DIR) / fileName);
#endif
#ifdef TALKHEAD_MODULE_BUILD_DIR
	c.push_back(fs::path(TALKHEAD_MODULE_BUILD_DIR) / fileName);
#endif
	return c;
}

namespace {

// A library's initialiser may end the process when it cannot open a file: libgcrypt (pulled in by libav's
// libssh) aborts when it cannot read /proc/sys/crypto/fips_enabled. So no plugin is loaded while the
// process is (nearly) out of file descriptors; this many must be free. Empty when they are, else why not.
std::string descriptorShortage(int needed) {
	int fds[32];
	int n = 0;
	int err = 0;
	for (; n < needed && n < 32; ++n) {
		fds[n] = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
		if (fds[n] < 0) {
			err = errno;
			break;
		}
	}
	for (int i = 0; i < n; ++i) ::close(fds[i]);
	return err ? std::strerror(err) : std::string();
}

}  // namespace

const void* loadPlugin(const std::string& fileName, const char* entry, int abi) {
	static std::mutex mutex;
	static std::map<std::string, const void*> loaded;
	std::lock_guard<std::mutex> lock(mutex);
	if (auto it = loaded.find(fileName); it != loaded.end()) return it->second;
	if (const std::string why = descriptorShortage(16); !why.empty())
		throw Error("cannot load the plugin " + fileName + " now: " + why + " (the process is out of file descriptors)");
	std::string why = "not found";
	for (const auto& path : pluginCandidates(fileName)) {
		std::error_code ec;
		if (!fs::is_regular_file(path, ec)) continue;
		void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
		if (!handle) {
			const char* e = ::dlerror();
			why = e ? e : "dlopen failed";
			continue;
		}
		auto fn = reinterpret_cast<const void* (*)()>(::dlsym(handle, entry));
		const void* api = fn ? fn() : nullptr;
		if (api && *static_cast<const int*>(api) == abi) {
			loaded[fileName] = api;  // stays loaded for the life of the process
			return api;
		}
		why = path + " is from another talkhead build";
		::dlclose(handle);
	}
	throw Error("cannot load the plugin " + fileName + " (" + why + "; set TALKHEAD_MODULE_DIR to the folder that holds it)");
}

}  // namespace talkhead
