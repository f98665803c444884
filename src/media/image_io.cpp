// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/image_io.h"

#include <cstdio>
#include <cctype>
#include <filesystem>

#include "base/atomic_file.h"
#include "base/interrupt.h"
#include "base/error.h"
#include "base/text.h"
#include "base/plugin.h"
#include "media/image_io_module.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {
const ImageIoModule& module() {
	static const auto* m = static_cast<const ImageIoModule*>(loadPlugin("libtalkhead-oiio.so", "talkhead_image_io_module", kImageIoModuleAbi));
	return *m;
}
// Still images only. OpenImageIO reads video files too (its FFmpeg plugin), and its FFmpeg reader leaks a
// codec context when it fails (found by the asf fuzz target: a corpus image named like a QuickTime file);
// a corpus or a frame is never a video. A name with a NUL byte would be cut short on the way to the file
// system, so it names another file than it says.
void checkImagePath(const std::string& path) {
	if (path.find('\0') != std::string::npos) throw Error(safeQuote(path), 0, "the file name holds a NUL byte");
	std::string ext = fs::path(path).extension().string();
	for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
	static const char* const kVideo[] = {".avi", ".mov", ".qt", ".mp4", ".m4v", ".m4a", ".3gp", ".3g2", ".mj2", ".mpg", ".mpeg",
	                                     ".mkv", ".webm", ".wmv", ".flv", ".ogv", ".ts", ".y4m"};
	for (const char* v : kVideo)
		if (ext == v) throw Error(path, 0, "a video file, not an image (corpus images and frames are still images: PNG, JPEG, PPM, TIFF, …)");
}
}  // namespace

void imageSize(const std::string& path, int& width, int& height) {
	checkImagePath(path);
	std::string error;
	if (!module().imageSize(path, width, height, error)) throw Error(path, 0, error);
}

Image8 readImage(const std::string& path) {
	checkImagePath(path);
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
