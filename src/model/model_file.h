// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "model/face_model.h"

namespace talkhead {

// The .thm model file: "TALKHEAD" magic, u32 format version, u32 flags, u64 payload size, u64 payload
// checksum, then the payload: named, typed records (little-endian; float32 for image and basis data,
// float64 for shapes and eigenvalues). Written to a temporary name and renamed into place.
// 2: per-sample appearance cache; 3: per-record checksums; 4: per-sample checksums of the cache.
constexpr std::uint32_t kModelFormatVersion = 5;  // reads 4 too (no region.towards)

void saveModel(const FaceModel& model, const std::string& path);
// What to load: everything, or what rendering needs: the bases and training coefficients are skipped and
// the per-sample appearance cache stays on disk (RegionModel::appearanceSource reads one sample at a
// time), so a 1.4 GB model loads ~15 MB; every record and every sample read is checksum-verified.
enum class ModelParts { All, Render };

// Components kept per region at render time (costa-spec §6.6, the thesis's Appendix C reductions): the
// named regions' keypose appearances are reconstructed from their first `count` components (or the
// fewest whose cumulative EVR reaches `evr`) instead of read from the full-quality cache. Shapes are the
// corpus's, as in the thesis's test (only the appearance is reduced).
struct ComponentLevel {
	long count = 0;   // > 0: this many components
	double evr = 0;   // else: the fewest reaching this EVR (0, 1]
};
using ComponentLevels = std::map<std::string, ComponentLevel>;
// "face=20,cheeks_lips=90%,lips=all" (all = every kept component; "all" alone: no reduction). Throws Error on bad syntax.
ComponentLevels parseComponentLevels(const std::string& spec);

// Throws Error("PATH: …") for a missing, truncated, corrupted (checksum) or wrong-version file.
// `levels`: reduce those regions (an unknown region or more components than the model keeps is an Error
// naming the model). With ModelParts::Render only the kept basis columns are held (the rest of the
// basis record is read through to verify its checksum).
FaceModel loadModel(const std::string& path, ModelParts parts = ModelParts::All, const ComponentLevels& levels = {});

// 64-bit checksum of a byte range (four interleaved multiply–xor lanes; any single changed byte changes it).
std::uint64_t checksum64(const void* data, std::size_t size, std::uint64_t seed = 0x9E3779B97F4A7C15ull);

}  // namespace talkhead
