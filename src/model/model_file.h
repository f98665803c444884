// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
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

// Throws Error("PATH: …") for a missing, truncated, corrupted (checksum) or wrong-version file.
FaceModel loadModel(const std::string& path, ModelParts parts = ModelParts::All);

// 64-bit checksum of a byte range (four interleaved multiply–xor lanes; any single changed byte changes it).
std::uint64_t checksum64(const void* data, std::size_t size, std::uint64_t seed = 0x9E3779B97F4A7C15ull);

}  // namespace talkhead
