// SPDX-License-Identifier: GPL-3.0-or-later
// The mouth classifier of render --drive-mouth (issue 17, D55) on held-out labelled real frames: each GRID
// clip's sentence is aligned to its audio (talkhead align), each phone's representative frame (issue 10's
// inflection point, corpus from-video) is labelled with the phone's CDV, and the classifier labels the
// same frames from the mouth alone. Two classifiers: trained on the synthetic corpus's CDV shapes
// (phonetics/cdv-mouth-targets.tsv: what --drive-mouth uses on the default face), and trained on the
// other GRID clips' labelled frames (leave one clip out: a real-face corpus). Prints top-1 accuracy over
// the CDVs, accuracy over four coarse mouth classes (closed, rounded, open, mid), and chance.
//   bench_mouth_classifier GRID_DIR
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "align/align.h"
#include "base/error.h"
#include "base/progress.h"
#include "media/audio.h"
#include "phonetics/language.h"
#include "track/drive_mouth.h"
#include "track/from_video.h"
#include "track/landmarks.h"

using namespace talkhead;

namespace {
std::string gridWords(const std::string& n) {
	std::string out;
	auto add = [&](const std::string& w) { out += (out.empty() ? "" : " ") + w; };
	const std::map<char, std::string> c0{{'b', "bin"}, {'l', "lay"}, {'p', "place"}, {'s', "set"}},
	    c1{{'b', "blue"}, {'g', "green"}, {'r', "red"}, {'w', "white"}}, c2{{'a', "at"}, {'b', "by"}, {'i', "in"}, {'w', "with"}},
	    c4{{'z', "zero"}, {'1', "one"}, {'2', "two"}, {'3', "three"}, {'4', "four"}, {'5', "five"}, {'6', "six"}, {'7', "seven"}, {'8', "eight"}, {'9', "nine"}},
	    c5{{'a', "again"}, {'n', "now"}, {'p', "please"}, {'s', "soon"}};
	add(c0.at(n[0]));
	add(c1.at(n[1]));
	add(c2.at(n[2]));
	add(n[3] == 'z' ? "zed" : std::string(1, n[3]));
	add(c4.at(n[4]));
	add(c5.at(n[5]));
	return out;
}
// Four coarse classes from the synthetic face's CDV measures.
std::string coarse(const MouthMeasures& d) {
	if (d.opening < 0.01) return "closed";
	if (d.width < -0.07) return "rounded";
	if (d.opening >= 0.08) return "open";
	return "mid";
}
struct Clip {
	std::string name;
	MouthMeasures rest;
	std::vector<MouthMeasures> all;
	std::vector<std::pair<std::string, MouthMeasures>> labelled;  // (CDV, measures)
};
}  // namespace

int main(int argc, char** argv) {
	if (argc != 2) {
		std::fprintf(stderr, "usage: bench_mouth_classifier GRID_DIR\n");
		return 2;
	}
	try {
		const std::vector<CdvMouthTarget> synthetic = loadCdvMouthTargets();
		std::map<std::string, MouthMeasures> syntheticOf;
		for (const auto& t : synthetic) syntheticOf[t.cdv] = t.delta;
		const Language& lang = Language::get("en-US");
		std::vector<Clip> clips;
		for (const auto& e : std::filesystem::directory_iterator(argv[1])) {
			if (e.path().extension() != ".mpg") continue;
			std::string name = e.path().stem().string();
			name = name.substr(name.rfind('_') + 1);
			NullProgress quiet;
			const LandmarkTrack track = trackVideo(e.path().string(), TrackOptions{}, quiet);
			AlignOptions ao;
			ao.languageTag = "en-US";
			const Alignment al = alignSpeech(decodeAudio(e.path().string()), gridWords(name), ao);
			const std::vector<PhoneSegment> phones = phoneSegments(al.phones, lang, UnknownPhone::Error, Notation::Ipa);
			const VideoCorpusPlan plan = selectByPhones(track, phones, al.words.intervals, FromVideoOptions{});
			Clip c;
			c.name = name;
			FromVideoOptions o;
			o.minConfidence = 0.5;
			const std::int64_t restFrame = mostNeutralFrame(track, o);
			for (const auto& f : track.frames) {
				if (!f.found) continue;
				c.all.push_back(mouthMeasures(unsmoothedPoints(f)));
				if (f.frame == restFrame) c.rest = c.all.back();
			}
			for (const ChosenFrame& ch : plan.entries)
				if (ch.cdv != "sil" && syntheticOf.count(ch.cdv)) c.labelled.emplace_back(ch.cdv, mouthMeasures(ch.points));
			clips.push_back(std::move(c));
		}
		std::sort(clips.begin(), clips.end(), [](const Clip& a, const Clip& b) { return a.name < b.name; });
		std::printf("clip\tframes\tsynthetic_top1\tsynthetic_coarse\treal_loo_top1\treal_loo_coarse\n");
		double totals[4] = {}, count = 0, chanceTop = 0, chanceCoarse = 0;
		for (std::size_t k = 0; k < clips.size(); ++k) {
			const Clip& c = clips[k];
			MouthClassifier syn = MouthClassifier::fromTargets(synthetic);
			syn.calibrate(c.rest, c.all);
			// Leave one out: per CDV the mean displacement from rest of the other clips' labelled frames, each
			// divided by its clip's spread and multiplied back by the synthetic targets' range (the same units).
			std::map<std::string, std::pair<MouthMeasures, int>> sums;
			for (std::size_t j = 0; j < clips.size(); ++j) {
				if (j == k) continue;
				MouthClassifier cal = MouthClassifier::fromTargets(synthetic);
				cal.calibrate(clips[j].rest, clips[j].all);
				for (const auto& [cdv, m] : clips[j].labelled) {
					auto& [s, n] = sums[cdv];
					for (int q = 0; q < 4; ++q) s[q] += (m[q] - clips[j].rest[q]) / cal.scale[q];
					++n;
				}
			}
			std::vector<CdvMouthTarget> realTargets;
			for (auto& [cdv, sn] : sums) {
				CdvMouthTarget t;
				t.cdv = cdv;
				for (int q = 0; q < 4; ++q) t.delta[q] = sn.first[q] / sn.second;
				realTargets.push_back(t);
			}
			MouthClassifier real = MouthClassifier::fromTargets(realTargets);
			real.calibrate(c.rest, c.all);
			double hits[4] = {};
			for (const auto& [cdv, m] : c.labelled) {
				const std::string a = syn.classes[syn.classify(m)], b = real.classes[real.classify(m)];
				if (std::getenv("BENCH_VERBOSE"))
					std::fprintf(stderr, "%s %s -> %s (%s -> %s) opening %+.3f width %+.3f\n", c.name.c_str(), cdv.c_str(), a.c_str(), coarse(syntheticOf[cdv]).c_str(),
					             coarse(syntheticOf[a]).c_str(), (m.opening - c.rest.opening) / syn.scale[0], (m.width - c.rest.width) / syn.scale[1]);
				hits[0] += a == cdv;
				hits[1] += coarse(syntheticOf[a]) == coarse(syntheticOf[cdv]);
				hits[2] += b == cdv;
				hits[3] += coarse(syntheticOf[b]) == coarse(syntheticOf[cdv]);
			}
			const double n = double(c.labelled.size());
			std::printf("%s\t%zu\t%.2f\t%.2f\t%.2f\t%.2f\n", c.name.c_str(), c.labelled.size(), hits[0] / n, hits[1] / n, hits[2] / n, hits[3] / n);
			for (int q = 0; q < 4; ++q) totals[q] += hits[q];
			count += n;
			// Chance: the most frequent label of this clip's frames, at the CDV and the coarse level.
			std::map<std::string, int> f, g;
			for (const auto& [cdv, m] : c.labelled) ++f[cdv], ++g[coarse(syntheticOf[cdv])];
			int bf = 0, bg = 0;
			for (auto& [l, v] : f) bf = std::max(bf, v);
			for (auto& [l, v] : g) bg = std::max(bg, v);
			chanceTop += bf, chanceCoarse += bg;
		}
		std::printf("all\t%.0f\t%.2f\t%.2f\t%.2f\t%.2f\n", count, totals[0] / count, totals[1] / count, totals[2] / count, totals[3] / count);
		std::printf("majority label per clip: top1 %.2f, coarse %.2f\n", chanceTop / count, chanceCoarse / count);
	} catch (const std::exception& e) {
		std::fprintf(stderr, "bench_mouth_classifier: %s\n", e.what());
		return 1;
	}
	return 0;
}
