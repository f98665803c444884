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
	// Encoded in memory (the format from the name), then written with checked I/O through a temporary name.
	thread_local std::vector<unsigned char> bytes;  // reused: frames are written by the drawing threads
	std::string error;
	if (!module().encodeImage(fs::path(path).filename().string(), image, pngCompression, bytes, error)) throw Error(path, 0, error);
	writeFileAtomically(path, bytes.data(), bytes.size());
}

}  // namespace talkhead
