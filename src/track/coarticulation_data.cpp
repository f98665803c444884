// SPDX-License-Identifier: GPL-3.0-or-later
#include "track/coarticulation_data.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "base/error.h"
#include "base/tsv.h"
#include "geometry/scheme.h"
#include "perform/plan.h"
#include "track/landmarks.h"

namespace talkhead {

CoarticulationClip coarticulationClip(const std::string& landmarksTsv, const std::string& transcript, const Language& language) {
	static const Scheme ibug = loadScheme("ibug-68");
	const LandmarkTrack track = readLandmarksTsv(landmarksTsv);
	CoarticulationClip c;
	c.name = landmarksTsv;
	for (const FrameLandmarks& f : track.frames) {
		c.times.push_back(toSeconds(f.time));
		const bool ok = f.found && f.points.rows() == ibug.pointCount();
		const MouthSize m = ok ? mouthSize(ibug, f.points) : MouthSize{};
		c.openings.push_back(ok ? m.opening : std::numeric_limits<double>::quiet_NaN());
		c.widths.push_back(ok ? m.width : std::numeric_limits<double>::quiet_NaN());
	}
	const TimedSpeech speech = speechFromTranscript(transcript, ReadOptions{}, language, UnknownPhone::Error, Notation::Auto, std::nullopt, false);
	c.phones = speech.phones;
	if (c.phones.empty()) throw Error(transcript + ": no phones");
	return c;
}

CoarticulationList readCoarticulationList(const std::string& path, const Language& language) {
	namespace fs = std::filesystem;
	const TsvTable t = readTsv(path);
	const std::size_t cl = t.column("landmarks"), ct = t.column("transcript");
	const auto speaker = std::find(t.header.begin(), t.header.end(), "speaker");
	const fs::path dir = fs::path(path).parent_path();
	CoarticulationList out;
	for (const auto& row : t.rows) {
		auto file = [&](std::size_t column) {
			const fs::path f(row.fields[column]);
			const fs::path full = f.is_absolute() ? f : dir / f;
			std::error_code ec;  // not the throwing overload (a name too long for the system)
			if (!fs::exists(full, ec)) throw Error(path, row.line, "no such file: " + full.string() + (ec ? " (" + ec.message() + ")" : ""));
			return full.string();
		};
		out.clips.push_back(coarticulationClip(file(cl), file(ct), language));
		out.speakers.push_back(speaker == t.header.end() ? std::string() : row.fields[std::size_t(speaker - t.header.begin())]);
	}
	if (out.clips.empty()) throw Error(path + ": no clips listed");
	return out;
}

}  // namespace talkhead
