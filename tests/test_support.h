// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "corpus/corpus.h"
#include "image/image.h"

namespace talkhead::test {

// ../shared/data (CI always has it); tests that need it skip with a message naming the folder.
std::string sharedData();
std::string immFolder();  // …/imm-frontal/IMM-Frontal_Face_DB_SMALL
bool haveImm();
// The IMM corpus (120 images, 73 points), loaded once.
const Corpus& immCorpus();

// A smooth colourful test image (sums of sines), deterministic.
Image8 testPattern(int width, int height);

// The message of the talkhead::Error that f throws, or "no error".
std::string errorOf(const std::function<void()>& f);

// A fresh empty folder under the build's temporary area, removed at exit.
std::string tempDir(const std::string& name);

}  // namespace talkhead::test

#define SKIP_WITHOUT_IMM()                                                                          \
	do {                                                                                            \
		if (!::talkhead::test::haveImm()) GTEST_SKIP() << "IMM data not found in " << ::talkhead::test::immFolder(); \
	} while (0)

#include "model/face_model.h"
namespace talkhead {
struct SynthCorpusOptions;
}
namespace talkhead::test {
// A face model built from the first `count` IMM images with all components (cached per count).
const FaceModel& immModel(std::size_t count = 20);
// A face model built in memory from the synthetic corpus of `o` (its size, emotions and visemes), scheme
// ch-unicamp-56, default build options.
FaceModel synthModel(const SynthCorpusOptions& o);
}  // namespace talkhead::test
