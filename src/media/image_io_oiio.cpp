// SPDX-License-Identifier: GPL-3.0-or-later
// The OpenImageIO plugin (libtalkhead-oiio.so): see image_io_module.h.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <filesystem>

#include "media/image_io_module.h"

namespace talkhead {

namespace {
constexpr long kMaxPixels = 100'000'000;  // refuse absurd sizes before allocating

std::string oiioError(const std::string& fallback) {
	std::string e = OIIO::geterror();
	return e.empty() ? fallback : e;
}

bool imageSizeImpl(const std::string& path, int& width, int& height, std::string& error) try {
	auto in = OIIO::ImageInput::open(path);
	if (!in) {
		error = "cannot open image: " + oiioError("unknown format or missing file");
		return false;
	}
	width = in->spec().width;
	height = in->spec().height;
	return true;
} catch (const std::exception& e) {
	error = std::string("cannot open image: ") + e.what();
	return false;
}

bool readImageImpl(const std::string& path, Image8& out, std::string& error) try {
	if (!std::filesystem::exists(path)) {
		error = "image file not found";
		return false;
	}
	auto in = OIIO::ImageInput::open(path);
	if (!in) {
		error = "cannot open image: " + oiioError("unknown format");
		return false;
	}
	const OIIO::ImageSpec& spec = in->spec();
	if (spec.width <= 0 || spec.height <= 0 || long(spec.width) * spec.height > kMaxPixels) {
		error = "absurd image size " + std::to_string(spec.width) + "x" + std::to_string(spec.height);
		return false;
	}
	const int nc = spec.nchannels;
	if (nc < 1) {
		error = "image has no channels";
		return false;
	}
	std::vector<std::uint8_t> buf(std::size_t(spec.width) * spec.height * nc);
	if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, buf.data())) {
		error = "cannot decode image: " + oiioError(in->geterror());
		return false;
	}
	in->close();
	out = Image8(spec.width, spec.height, 3);
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
	return true;
} catch (const std::exception& e) {
	error = std::string("cannot read image: ") + e.what();
	return false;
}

bool encodeImageImpl(const std::string& formatName, const Image8& image, int pngCompression, std::vector<unsigned char>& bytes, std::string& error) try {
	bytes.clear();
	OIIO::Filesystem::IOVecOutput proxy(bytes);
	auto out = OIIO::ImageOutput::create(formatName, &proxy);
	if (!out) {
		error = "cannot write images of this type: " + oiioError("unknown extension");
		return false;
	}
	if (!out->supports("ioproxy")) {
		error = "cannot write images of this type (its writer cannot write to memory); use .png";
		return false;
	}
	OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
	if (pngCompression >= 0) spec.attribute("png:compressionLevel", std::min(9, pngCompression));
	// A fourth channel is straight (unassociated) alpha, as PNG stores it: written as it is (OpenImageIO
	// would otherwise take the colour as premultiplied and divide it by the alpha).
	if (image.channels == 4) spec.attribute("oiio:UnassociatedAlpha", 1);
	if (!out->open(formatName, spec)) {
		error = "cannot write image: " + oiioError(out->geterror());
		return false;
	}
	bool ok = out->write_image(OIIO::TypeDesc::UINT8, image.data.data());
	ok = out->close() && ok;
	if (!ok) error = "cannot write image: " + oiioError(out->geterror());
	return ok;
} catch (const std::exception& e) {
	error = std::string("cannot write image: ") + e.what();
	return false;
}

const ImageIoModule kModule{kImageIoModuleAbi, imageSizeImpl, readImageImpl, encodeImageImpl};
}  // namespace

}  // namespace talkhead

extern "C" const void* talkhead_image_io_module() { return &talkhead::kModule; }
