// SPDX-License-Identifier: GPL-3.0-or-later
// Times loadModel (read, checksum, parse) in-process, excluding program start-up.
// usage: bench_model_load MODEL.thm [REPEATS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "model/model_file.h"

int main(int argc, char** argv) {
	if (argc < 2) {
		std::fprintf(stderr, "usage: bench_model_load MODEL.thm [REPEATS]\n");
		return 2;
	}
	const int reps = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
	std::vector<double> ms;
	std::size_t samples = 0;
	for (int i = 0; i < reps; ++i) {
		auto t0 = std::chrono::steady_clock::now();
		talkhead::FaceModel m = talkhead::loadModel(argv[1]);
		ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
		samples = m.sampleCount();
	}
	std::vector<double> renderMs;
	for (int i = 0; i < reps; ++i) {
		auto t0 = std::chrono::steady_clock::now();
		talkhead::FaceModel m = talkhead::loadModel(argv[1], talkhead::ModelParts::Render);
		renderMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
	}
	std::sort(renderMs.begin(), renderMs.end());
	std::printf("render load (bases skipped, appearance cache left on disk): median %.1f ms (min %.1f)\n", renderMs[renderMs.size() / 2],
	            renderMs.front());
	std::sort(ms.begin(), ms.end());
	double mib = double(std::filesystem::file_size(argv[1])) / 1048576.0;
	std::printf("model %s: %zu samples, %.1f MiB; load median %.1f ms (min %.1f) = %.2f GiB/s\n", argv[1], samples, mib, ms[ms.size() / 2],
	            ms.front(), mib / 1024.0 / (ms[ms.size() / 2] / 1000.0));
	return 0;
}
