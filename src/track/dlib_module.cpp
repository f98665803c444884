// SPDX-License-Identifier: GPL-3.0-or-later
// The dlib plugin (libtalkhead-dlib.so). See dlib_module.h.
#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_transforms.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "base/plugin.h"
#include "track/dlib_module.h"

namespace talkhead {

namespace {

struct Handle {
	dlib::frontal_face_detector detector = dlib::get_frontal_face_detector();
	dlib::shape_predictor predictor;
	dlib::array2d<unsigned char> image;  // reused between calls on the same frame size
};


// Copies the grey image into dlib's array.
const dlib::array2d<unsigned char>& toDlib(Handle& h, const Image8& grey) {
	if (grey.channels != 1) throw std::logic_error("dlib module: grey images only");
	if (h.image.nr() != grey.height || h.image.nc() != grey.width) h.image.set_size(grey.height, grey.width);
	for (int y = 0; y < grey.height; ++y) std::copy(grey.row(y), grey.row(y) + grey.width, &h.image[y][0]);
	return h.image;
}

void* openEntry(const std::string& path, std::string& error) {
	auto h = std::make_unique<Handle>();
	const bool ok = guarded(error, [&] {
		if (!std::filesystem::exists(path))
			throw std::runtime_error(path + ": dlib's 68-point face landmark model is missing (install the Debian package libdlib-data, or set TALKHEAD_DLIB_MODEL)");
		try {
			dlib::deserialize(path) >> h->predictor;
		} catch (const std::exception& e) {
			throw std::runtime_error(path + ": not a dlib shape predictor model (" + std::string(e.what()).substr(0, 120) + ")");
		}
		if (h->predictor.num_parts() != 68)
			throw std::runtime_error(path + ": the shape predictor has " + std::to_string(h->predictor.num_parts()) + " points, not 68");
	});
	return ok ? h.release() : nullptr;
}

bool detectEntry(void* hp, const Image8& grey, int upsample, std::vector<FaceBox>& faces, std::string& error) {
	return guarded(error, [&] {
		Handle& h = *static_cast<Handle*>(hp);
		toDlib(h, grey);
		std::vector<dlib::rect_detection> dets;
		if (upsample <= 0) {
			h.detector(h.image, dets, 0.0);
		} else {
			dlib::array2d<unsigned char> up;
			dlib::assign_image(up, h.image);
			for (int i = 0; i < upsample; ++i) dlib::pyramid_up(up);
			h.detector(up, dets, 0.0);
		}
		const double scale = std::pow(2.0, upsample);
		std::sort(dets.begin(), dets.end(), [](const auto& a, const auto& b) { return a.detection_confidence > b.detection_confidence; });
		faces.clear();
		for (const auto& d : dets) {
			const auto& r = d.rect;
			faces.push_back({r.left() / scale, r.top() / scale, (r.right() + 1) / scale - 1, (r.bottom() + 1) / scale - 1, d.detection_confidence});
		}
	});
}

bool fitEntry(void* hp, const Image8& grey, const FaceBox& box, std::vector<float>& xy, std::string& error) {
	return guarded(error, [&] {
		Handle& h = *static_cast<Handle*>(hp);
		toDlib(h, grey);
		const dlib::drectangle r(box.left, box.top, box.right, box.bottom);
		const dlib::full_object_detection shape = h.predictor(h.image, dlib::rectangle(std::lround(r.left()), std::lround(r.top()), std::lround(r.right()), std::lround(r.bottom())));
		xy.resize(2 * shape.num_parts());
		for (unsigned long i = 0; i < shape.num_parts(); ++i) {
			xy[2 * i] = float(shape.part(i).x());
			xy[2 * i + 1] = float(shape.part(i).y());
		}
	});
}

void closeEntry(void* h) { delete static_cast<Handle*>(h); }

const DlibModule kModule{kDlibModuleAbi, openEntry, detectEntry, fitEntry, closeEntry};

}  // namespace

}  // namespace talkhead

extern "C" const void* talkhead_dlib_module() { return &talkhead::kModule; }
