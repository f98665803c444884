// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

#include "base/progress.h"
#include "corpus/corpus.h"
#include "model/face_model.h"
#include "synth/action_units.h"
#include "synth/au_appearance.h"

namespace talkhead {

// The corpus → model step of `talkhead build` as a library call (issue 46): the shapes and the samples'
// labels from the corpus rows, its baseface and closed-eyes rows, the images read as the build needs
// them (the first image gives the size). `options.baseface` and `options.closedEyes` are taken from the
// corpus. Throws Error naming the corpus when it is empty or its shapes do not have the scheme's points.
FaceModel buildFaceModel(const Corpus& corpus, const Scheme& scheme, BuildOptions options, ProgressSink& progress);

// The corpus → skin maps step of `corpus au-appearance` (issue 31, D61) as a library call: what each action
// unit does to the skin, learnt from every (emotion, CDV) image of the corpus against its CDV's neutral one,
// with each emotion's action units from `profiles` (default: corpus-tools/data/expression-aus.tsv); the
// maps' grid `gridWidth` pixels wide. Its `source` names the corpus.
AuAppearance buildAuAppearance(const Corpus& corpus, const Scheme& scheme, const std::map<std::string, AuProfile>& profiles = defaultAuProfiles(),
                               int gridWidth = 256);

// The scheme a corpus is labelled in: `name`, or when empty the one its reader inferred. Throws Error
// naming the corpus when none can be told or the point counts differ.
Scheme corpusScheme(const Corpus& corpus, const std::string& name = "");

}  // namespace talkhead
