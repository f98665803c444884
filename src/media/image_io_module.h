// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The image I/O module: OpenImageIO and the ~260 shared libraries it pulls in cost ~0.35 s of start-up,
// so they live in a plugin (libtalkhead-oiio.so) that image_io.cpp loads on the first image read or
// written. Commands that touch no image file (render to MP4, say) never load it. Built from the same
// tree with the same compiler, so C++ types cross the boundary; errors come back as strings.
#include <string>
#include <vector>

#include "image/image.h"

namespace talkhead {

constexpr int kImageIoModuleAbi = 2;  // 2: encodeImage (to memory) instead of writeImage

struct ImageIoModule {
	int abi;  // kImageIoModuleAbi
	// Each returns false and sets `error` (the message without the path) on failure; never throws.
	bool (*imageSize)(const std::string& path, int& width, int& height, std::string& error);
	bool (*readImage)(const std::string& path, Image8& out, std::string& error);
	// Encodes the image in memory in the format that `formatName`'s extension names (the caller writes the
	// bytes with checked I/O: libpng's failed writes to a full disk went unreported through OIIO's files).
	bool (*encodeImage)(const std::string& formatName, const Image8& image, int pngCompression, std::vector<unsigned char>& out, std::string& error);
};

}  // namespace talkhead

extern "C" const void* talkhead_image_io_module();
