// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/image_io.h"

#include <cstdio>
#include <filesystem>

#include "base/atomic_file.h"
#include "base/interrupt.h"
#include "base/error.h"
#include "base/plugin.h"
#include "media/image_io_module.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {
const ImageIoModule& module() {
	static const auto* m = static_cast<const ImageIoModule*>(loadPlugin("libtalkhead-oiio.so", "talkhead_image_io_module", kImageIoModuleAbi));
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
		releaseTemporary(tmp.string());
		throw Error(path, 0, error);
	}
	std::error_code ec;
	fs::rename(tmp, target, ec);
	if (ec) std::remove(tmp.string().c_str());
	releaseTemporary(tmp.string());
	if (ec) throw Error(path, 0, "cannot write image: " + ec.message());
}

}  // namespace talkhead
