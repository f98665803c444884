// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

#include "base/progress.h"
#include "corpus/corpus.h"
#include "model/face_model.h"

namespace talkhead {

// The corpus → model step of `talkhead build` as a library call (issue 46): the shapes and the samples'
// labels from the corpus rows, its baseface and closed-eyes rows, the images read as the build needs
// them (the first image gives the size). `options.baseface` and `options.closedEyes` are taken from the
// corpus. Throws Error naming the corpus when it is empty or its shapes do not have the scheme's points.
FaceModel buildFaceModel(const Corpus& corpus, const Scheme& scheme, BuildOptions options, ProgressSink& progress);

// The scheme a corpus is labelled in: `name`, or when empty the one its reader inferred. Throws Error
// naming the corpus when none can be told or the point counts differ.
Scheme corpusScheme(const Corpus& corpus, const std::string& name = "");

}  // namespace talkhead
