// SPDX-License-Identifier: GPL-3.0-or-later
#include "media/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include "base/atomic_file.h"
#include "base/error.h"

namespace talkhead {

namespace {
constexpr long kMaxPixels = 100'000'000;  // refuse absurd sizes before allocating

std::string oiioError(const std::string& fallback) {
	std::string e = OIIO::geterror();
	return e.empty() ? fallback : e;
}
}  // namespace

void imageSize(const std::string& path, int& width, int& height) {
	auto in = OIIO::ImageInput::open(path);
	if (!in) throw Error(path, 0, "cannot open image: " + oiioError("unknown format or missing file"));
	width = in->spec().width;
	height = in->spec().height;
}

Image8 readImage(const std::string& path) {
	if (!std::filesystem::exists(path)) throw Error(path, 0, "image file not found");
	auto in = OIIO::ImageInput::open(path);
	if (!in) throw Error(path, 0, "cannot open image: " + oiioError("unknown format"));
	const OIIO::ImageSpec& spec = in->spec();
	if (spec.width <= 0 || spec.height <= 0 || long(spec.width) * spec.height > kMaxPixels)
		throw Error(path, 0, "absurd image size " + std::to_string(spec.width) + "x" + std::to_string(spec.height));
	const int nc = spec.nchannels;
	if (nc < 1) throw Error(path, 0, "image has no channels");
	std::vector<std::uint8_t> buf(std::size_t(spec.width) * spec.height * nc);
	if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, buf.data()))
		throw Error(path, 0, "cannot decode image: " + oiioError(in->geterror()));
	in->close();
	Image8 out(spec.width, spec.height, 3);
	const std::size_t n = out.pixelCount();
	for (std::size_t p = 0; p < n; ++p) {
		const std::uint8_t* s = &buf[p * nc];
		std::uint8_t* d = &out.data[p * 3];
		if (nc >= 3) {
			d[0] = s[0];
			d[1] = s[1];
			d[2] = s[2];
		} else {
			d[0] = d[1] = d[2] = s[0];
		}
	}
	return out;
}

void writeImage(const std::string& path, const Image8& image, int pngCompression) {
	namespace fs = std::filesystem;
	fs::path target(path);
	fs::path tmp = temporaryNameFor(path);
	auto out = OIIO::ImageOutput::create(target.filename().string());
	if (!out) throw Error(path, 0, "cannot write images of this type: " + oiioError("unknown extension"));
	OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
	if (pngCompression >= 0) spec.attribute("png:compressionLevel", std::min(9, pngCompression));
	// The temporary keeps the real extension at the end so the writer picks the same format.
	if (!out->open(tmp.string(), spec)) throw Error(path, 0, "cannot write image: " + oiioError(out->geterror()));
	bool ok = out->write_image(OIIO::TypeDesc::UINT8, image.data.data());
	ok = out->close() && ok;
	if (!ok) {
		std::remove(tmp.string().c_str());
		throw Error(path, 0, "cannot write image: " + oiioError(out->geterror()));
	}
	std::error_code ec;
	fs::rename(tmp, target, ec);
	if (ec) {
		std::remove(tmp.string().c_str());
		throw Error(path, 0, "cannot write image: " + ec.message());
	}
}

}  // namespace talkhead
