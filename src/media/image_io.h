// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

#include "image/image.h"

namespace talkhead {

// Reads any format OpenImageIO reads, as 8-bit RGB (grey is replicated, alpha dropped, higher bit
// depths scaled). Throws Error("PATH: …") naming the file.
Image8 readImage(const std::string& path);

// Writes an image (format from the extension, e.g. .png; 3 channels RGB, 4 RGBA with straight alpha) to a temporary name in the same folder and
// renames it into place, so a failure leaves no partial file.
// pngCompression: 0 (fastest) … 9 (smallest); −1 = the library's default.
void writeImage(const std::string& path, const Image8& image, int pngCompression = -1);

// Width and height of an image file without decoding its pixels.
void imageSize(const std::string& path, int& width, int& height);

}  // namespace talkhead
