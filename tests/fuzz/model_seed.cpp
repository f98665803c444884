// SPDX-License-Identifier: GPL-3.0-or-later
// Writes the seed of the model-file targets: a real .thm, as small as the format allows to be useful (a
// 6-point scheme with two regions, three 12×9 training images, ~10 KB), built by buildFaceModel and saved
// by saveModel, so every record the loader reads is there. Generated (not committed: *.thm is ignored, and
// the bytes would go stale with the format version). Usage: talkhead-fuzz-model-seed OUT.thm
#include <cstdio>

#include "base/error.h"
#include "base/progress.h"
#include "geometry/scheme.h"
#include "model/face_model.h"
#include "model/model_file.h"

using namespace talkhead;

int main(int argc, char** argv) {
	if (argc != 2) {
		std::fprintf(stderr, "usage: %s OUT.thm\n", argv[0]);
		return 2;
	}
	try {
		const Scheme scheme = parseScheme(
		    "scheme fuzz-6\nclass anchor 1.0\nclass dynamic 0.2\n"
		    "point TL anchor\npoint TR anchor\npoint BR anchor\npoint BL anchor\npoint M1 dynamic\npoint M2 dynamic\n"
		    "region face grow=0 feather=0.05 : TL TR BR BL\nregion mouth grow=0.3 feather=0.1 : M1 BR BL\n",
		    "fuzz-6.scheme");
		const int w = 12, h = 9;
		std::vector<Points> shapes;
		std::vector<SampleInfo> samples;
		for (int i = 0; i < 3; ++i) {
			Points p(6, 2);
			p << 2, 1.5, 9.5, 1.5, 9.5 + 0.25 * i, 7, 2, 7, 4.5, 5 - 0.25 * i, 7, 5 + 0.15 * i;
			shapes.push_back(p);
			SampleInfo s;
			s.image = "s" + std::to_string(i) + ".png";
			s.emotion = i ? "joy" : "neutral";
			s.cdv = i == 2 ? "u" : "a";
			s.word = "a";
			s.context = {"_", "_", "a", "_", "_"};
			samples.push_back(s);
		}
		auto image = [&](std::size_t i) {
			Image8 im;
			im.width = w;
			im.height = h;
			im.channels = 3;
			im.data.resize(std::size_t(w) * h * 3);
			for (std::size_t k = 0; k < im.data.size(); ++k) im.data[k] = std::uint8_t((k * 7 + i * 31) % 251);
			return im;
		};
		BuildOptions options;
		options.threads = 1;
		NullProgress progress;
		const FaceModel m = buildFaceModel(scheme, shapes, samples, w, h, image, options, progress);
		saveModel(m, argv[1]);
	} catch (const std::exception& e) {
		std::fprintf(stderr, "talkhead-fuzz-model-seed: %s\n", describeException(e).c_str());
		return 1;
	}
	return 0;
}
