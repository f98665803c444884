// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Issue 32 (D62): real speakers' clips for learning coarticulation — their tracked 68 points
// ('talkhead corpus landmarks') and their timed phones.
#include <string>
#include <vector>

#include "phonetics/language.h"
#include "synth/coarticulation.h"

namespace talkhead {

// One clip: the landmarks TSV's inner-lip opening per frame (NaN where the face was lost) and the
// transcript's phones in `language`. Errors name the file.
CoarticulationClip coarticulationClip(const std::string& landmarksTsv, const std::string& transcript, const Language& language);

// A list of clips (TSV with columns `landmarks` and `transcript`, relative paths from the list's folder;
// optional `speaker`). Errors name the file and line.
struct CoarticulationList {
	std::vector<CoarticulationClip> clips;
	std::vector<std::string> speakers;  // per clip ("" when the list has no speaker column)
};
CoarticulationList readCoarticulationList(const std::string& path, const Language& language);

}  // namespace talkhead
