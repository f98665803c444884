// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The dlib plugin (libtalkhead-dlib.so): dlib's HOG frontal face detector and its 68-point shape
// predictor (Debian libdlib-dev, model from libdlib-data). Loaded on the first command that tracks a face,
// so the others start without dlib. Built from the same tree, so C++ types cross the boundary; errors come
// back as strings.
#include <string>
#include <vector>

#include "image/image.h"

namespace talkhead {

constexpr int kDlibModuleAbi = 1;

// A face box in pixels (dlib's rectangle: inclusive corners as doubles) with the detector's score.
struct FaceBox {
	double left = 0, top = 0, right = 0, bottom = 0;
	double score = 0;
	double width() const { return right - left; }
	double height() const { return bottom - top; }
};

struct DlibModule {
	int abi;  // kDlibModuleAbi
	// Loads the predictor (a .dat file); an opaque handle, or nullptr with `error` set.
	void* (*open)(const std::string& predictorPath, std::string& error);
	// Faces in a grey image (one byte per pixel), upsampling it `upsample` times first (0 = as is); sorted by
	// score, best first.
	bool (*detect)(void* handle, const Image8& grey, int upsample, std::vector<FaceBox>& faces, std::string& error);
	// 68 points (x0 y0 x1 y1 …, 0-based pixel centres) fitted inside `box`.
	bool (*fit)(void* handle, const Image8& grey, const FaceBox& box, std::vector<float>& xy, std::string& error);
	void (*close)(void* handle);
};

}  // namespace talkhead

extern "C" const void* talkhead_dlib_module();
