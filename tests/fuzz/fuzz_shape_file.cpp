// SPDX-License-Identifier: GPL-3.0-or-later
// The landmark files of an image folder (src/corpus/corpus.cpp): IMM .asf (TALKHEAD_FUZZ_SHAPE "asf") or
// iBUG .pts ("pts"). Both take a path and look for their image beside it, so the input is written to
// input.asf / input.pts in the process's folder, next to a 2×2 PPM that both can find: face.ppm (the host
// image the .asf seeds name; readAsf reads its size through the image plugin) and input.ppm (what readPts
// looks for).
#include <string>

#include "corpus/corpus.h"
#include "fuzz_support.h"

#ifndef TALKHEAD_FUZZ_SHAPE
#error "define TALKHEAD_FUZZ_SHAPE as \"asf\" or \"pts\""
#endif

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	static const bool images = [] {
		const std::string ppm = std::string("P6\n2 2\n255\n") + std::string(12, '\x80');
		fuzz::writeInput(ppm, "face.ppm");
		fuzz::writeInput(ppm, "input.ppm");
		return true;
	}();
	(void)images;
	const std::string shape = TALKHEAD_FUZZ_SHAPE;
	const std::string path = fuzz::writeInput(data, size, "input." + shape);
	fuzz::expectOnlyErrors([&] {
		const CorpusEntry e = shape == "asf" ? readAsf(path) : readPts(path);
		TALKHEAD_FUZZ_CHECK(e.points.rows() >= 3 && e.points.cols() == 2, e.source);
		TALKHEAD_FUZZ_CHECK(e.points.allFinite(), e.source);
	});
	return 0;
}
