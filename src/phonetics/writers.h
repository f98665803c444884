// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

#include "phonetics/language.h"

namespace talkhead {

// Output formats of `talkhead visemes`.
const std::vector<std::string>& visemeOutputFormats();  // tsv json textgrid rhubarb-tsv rhubarb-json

// The viseme timeline as text: one row per phone (start, end, phone, CDV, keypose time) in tsv/json; a
// TextGrid with "phones" and "cdv" interval tiers and a "keyposes" point tier; or Rhubarb mouth cues
// (CDVs mapped onto Rhubarb's A–H, X shapes by phonetics/rhubarb-shapes.tsv).
// `notation` (JSON only): how the transcript spelled its phones, when known.
// `confidence`, when given, has one value per phone (recognised phones): a column of the TSV, a member
// of each JSON phone.
std::string formatVisemes(const std::vector<PhoneSegment>& phones, const std::vector<Keypose>& keys, const std::string& format,
                          const std::string& languageTag, const std::string& source, const std::string& notation = "",
                          const std::vector<double>* confidence = nullptr);

// Rhubarb mouth shape of a CDV.
std::string rhubarbShape(const std::string& cdv);

}  // namespace talkhead
