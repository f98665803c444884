// SPDX-License-Identifier: GPL-3.0-or-later
// The .thm model loader (src/model/model_file.cpp): the input is the file, loaded whole (ModelParts::All)
// and for rendering (ModelParts::Render, whose appearance cache stays on disk and is read sample by sample).
//
// With TALKHEAD_FUZZ_FIX_CHECKSUMS=1 (target model_fixed) the harness first re-stamps every checksum
// the loader verifies (each record's own, and the header's payload size and checksum), walking the
// format's self-describing records, so mutations reach the structural checks behind them instead of
// stopping at "checksum mismatch". The loader has no switch to skip its checks, and gets none: this keeps
// the production path the one fuzzed. (The per-sample checksums of the appearance cache are data of the
// "appearanceChecksums" record, read lazily; they are left as the input has them.)
#include <cstring>
#include <string>

#include "fuzz_support.h"
#include "model/model_file.h"

#ifndef TALKHEAD_FUZZ_FIX_CHECKSUMS
#define TALKHEAD_FUZZ_FIX_CHECKSUMS 0
#endif

using namespace talkhead;

namespace {

constexpr std::size_t kHeaderSize = 32;  // magic, u32 version, u32 flags, u64 payload size, u64 checksum

template <class T>
T load(const std::string& b, std::size_t at) {
	T v;
	std::memcpy(&v, b.data() + at, sizeof v);
	return v;
}
template <class T>
void store(std::string& b, std::size_t at, T v) {
	std::memcpy(b.data() + at, &v, sizeof v);
}

// Records: u32 name length, name, u32 type, u64 count, data, u64 checksum of all that precedes it in the
// record. Element sizes by type: F32 4, F64 8, I32 4, U8 1, Str (u32 length + bytes each), U64 8.
void fixChecksums(std::string& b) {
	if (b.size() < kHeaderSize) return;
	std::size_t at = kHeaderSize;
	while (at + 4 <= b.size()) {
		const std::size_t start = at;
		const std::uint64_t nameLen = load<std::uint32_t>(b, at);
		if (nameLen > b.size() - at - 4 || b.size() - at - 4 - nameLen < 12) break;
		at += 4 + nameLen;
		const std::uint32_t type = load<std::uint32_t>(b, at);
		const std::uint64_t count = load<std::uint64_t>(b, at + 4);
		at += 12;
		std::uint64_t elem = 0;
		switch (type) {
			case 1: case 3: elem = 4; break;
			case 2: case 6: elem = 8; break;
			case 4: elem = 1; break;
			case 5: break;
			default: return;  // an unknown type: the loader stops here too
		}
		if (type == 5) {
			for (std::uint64_t i = 0; i < count; ++i) {
				if (b.size() - at < 4) return;
				const std::uint64_t len = load<std::uint32_t>(b, at);
				if (len > b.size() - at - 4) return;
				at += 4 + len;
			}
		} else {
			if (count > (b.size() - at) / elem) return;
			at += count * elem;
		}
		if (b.size() - at < 8) return;
		store<std::uint64_t>(b, at, checksum64(b.data() + start, at - start));
		at += 8;
	}
}

void fixHeader(std::string& b) {
	if (b.size() < kHeaderSize) return;
	store<std::uint64_t>(b, 16, b.size() - kHeaderSize);
	store<std::uint64_t>(b, 24, checksum64(b.data() + kHeaderSize, b.size() - kHeaderSize));
}

void exercise(const std::string& path) {
	fuzz::expectOnlyErrors([&] { loadModel(path, ModelParts::All); });
	fuzz::expectOnlyErrors([&] {
		const FaceModel m = loadModel(path, ModelParts::Render);
		std::vector<std::uint8_t> buf;
		for (const RegionModel& r : m.regions) {
			buf.resize(std::size_t(r.appearanceSize()));
			for (std::size_t s = 0; s < m.sampleCount(); ++s) r.readCachedAppearance(s, buf.data());
		}
	});
	// Render-time component reduction (issue 14): the first region's first component, and every one (EVR 1).
	for (const ComponentLevel level : {ComponentLevel{1, 0}, ComponentLevel{0, 1.0}})
		fuzz::expectOnlyErrors([&] {
			const FaceModel head = loadModel(path, ModelParts::Render);
			if (head.regions.empty()) return;
			const FaceModel m = loadModel(path, ModelParts::Render, {{head.regions[0].name, level}});
			std::vector<std::uint8_t> buf(std::size_t(m.regions[0].appearanceSize()));
			for (std::size_t s = 0; s < m.sampleCount(); ++s) m.regions[0].readCachedAppearance(s, buf.data());
		});
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	std::string bytes(reinterpret_cast<const char*>(data), size);
	if (TALKHEAD_FUZZ_FIX_CHECKSUMS) {
		fixChecksums(bytes);
		fixHeader(bytes);
	}
	exercise(fuzz::writeInput(bytes, "model.thm"));
	return 0;
}
