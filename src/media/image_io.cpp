// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/image_io.h"

#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "base/atomic_file.h"
#include "base/error.h"
#include "media/image_io_module.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {
constexpr const char* kModuleName = "libtalkhead-oiio.so";

std::vector<std::string> moduleCandidates() {
	std::vector<std::string> c;
	if (const char* env = std::getenv("TALKHEAD_MODULE_DIR"); env && *env) c.push_back(fs::path(env) / kModuleName);
	std::error_code ec;
	const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
	if (!ec) {
		c.push_back(exe.parent_path() / "lib" / "talkhead" / kModuleName);  // build tree
#ifdef TALKHEAD_MODULE_RELATIVE_DIR
		c.push_back(exe.parent_path().parent_path() / TALKHEAD_MODULE_RELATIVE_DIR / kModuleName);  // installed tree
#endif
	}
#ifdef TALKHEAD_MODULE_INSTALL_DIR
	c.push_back(fs::path(TALKHEAD_MODULE_INSTALL_DIR) / kModuleName);
#endif
#ifdef TALKHEAD_MODULE_BUILD_DIR
	c.push_back(fs::path(TALKHEAD_MODULE_BUILD_DIR) / kModuleName);
#endif
	return c;
}

const ImageIoModule* loadModule() {
	std::string why = "not found";
	for (const auto& path : moduleCandidates()) {
		std::error_code ec;
		if (!fs::is_regular_file(path, ec)) continue;
		void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
		if (!handle) {
			const char* e = ::dlerror();
			why = e ? e : "dlopen failed";
			continue;
		}
		auto entry = reinterpret_cast<const ImageIoModule* (*)()>(::dlsym(handle, "talkhead_image_io_module"));
		const ImageIoModule* m = entry ? entry() : nullptr;
		if (m && m->abi == kImageIoModuleAbi) return m;  // stays loaded for the life of the process
		why = path + " is from another talkhead build";
		::dlclose(handle);
	}
	throw Error(std::string("cannot load the image I/O module ") + kModuleName + " (" + why +
	            "; set TALKHEAD_MODULE_DIR to the folder that holds it)");
}

const ImageIoModule& module() {
	static const ImageIoModule* m = loadModule();  // thread-safe; retried after a failure
	return *m;
}
}  // namespace

void imageSize(const std::string& path, int& width, int& height) {
	std::string error;
	if (!module().imageSize(path, width, height, error)) throw Error(path, 0, error);
}

Image8 readImage(const std::string& path) {
	Image8 out;
	std::string error;
	if (!module().readImage(path, out, error)) throw Error(path, 0, error);
	return out;
}

void writeImage(const std::string& path, const Image8& image, int pngCompression) {
	const ImageIoModule& m = module();
	fs::path target(path);
	fs::path tmp = temporaryNameFor(path);
	// The format comes from the real name; the temporary is renamed into place when complete.
	std::string error;
	if (!m.writeImage(tmp.string(), target.filename().string(), image, pngCompression, error)) {
		std::remove(tmp.string().c_str());
		throw Error(path, 0, error);
	}
	std::error_code ec;
	fs::rename(tmp, target, ec);
	if (ec) {
		std::remove(tmp.string().c_str());
		throw Error(path, 0, "cannot write image: " + ec.message());
	}
}

}  // namespace talkhead
