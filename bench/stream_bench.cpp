// SPDX-License-Identifier: GPL-3.0-or-later
// A streamed speak with its text (perform/stream.h) against aligning the whole (issue 49 part 2, D97/D98):
// each clip's audio fed in pieces as a TTS streams it, its text with the first. Per clip: how much audio had
// come when the first part came out, how many parts, whether the phones are the whole alignment's, and the
// distance between their starts (median, max). bench/stream.sh gives it GRID clips and their words.
//   usage: bench_stream PIECE_SECONDS AUDIO TEXT [AUDIO TEXT …]
// With --heard, each clip's audio alone as serve's `speak` with no timing gives it (one piece, its first
// utterance recognised within 1 s, D97): the phones of its parts joined, written as OUTDIR/NAME.tsv
// (start, end, phone: what `talkhead render --transcript` reads), for bench/coarticulation.sh's way `served`.
//   usage: bench_stream --heard OUTDIR AUDIO [AUDIO …]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "align/align.h"
#include "media/audio.h"
#include "perform/stream.h"
#include "phonetics/language.h"
#include "perform/plan.h"

using namespace talkhead;

namespace {

std::vector<float> monoAt(const std::string& path, int rate, int* sampleRate) {
	const AudioClip clip = decodeAudio(path, rate);
	std::vector<float> mono(clip.frameCount());
	const std::size_t ch = std::size_t(std::max(1, clip.channels));
	for (std::size_t i = 0; i < mono.size(); ++i) {
		float s = 0;
		for (std::size_t c = 0; c < ch; ++c) s += clip.samples[i * ch + c];
		mono[i] = s / float(ch);
	}
	*sampleRate = clip.sampleRate;
	return mono;
}

int heard(int argc, char** argv) {
	const std::string dir = argv[2];
	for (int a = 3; a < argc; ++a) {
		const std::string path = argv[a];
		int rate = 0;
		const std::vector<float> mono = monoAt(path, 22050, &rate);
		SpeechStream whole("h", "", Language::get("en-US"), rate, rate);
		std::vector<Utterance> parts;
		whole.feed(mono, true, [&](Utterance u) { parts.push_back(std::move(u)); });
		std::string name = path.substr(path.find_last_of('/') + 1);
		name = name.substr(0, name.find_last_of('.'));
		std::FILE* f = std::fopen((dir + "/" + name + ".tsv").c_str(), "w");
		if (!f) {
			std::fprintf(stderr, "bench_stream: cannot write %s/%s.tsv\n", dir.c_str(), name.c_str());
			return 1;
		}
		std::fprintf(f, "start\tend\tphone\n");
		Ticks at{0};
		for (const Utterance& u : parts) {
			for (const PhoneSegment& p : u.phones) std::fprintf(f, "%.6f\t%.6f\t%s\n", toSeconds(p.start + at), toSeconds(p.end + at), p.phone.c_str());
			at += u.audio.duration();
		}
		std::fclose(f);
		std::printf("%s: %zu parts, the first %.2f s\n", name.c_str(), parts.size(), parts.empty() ? 0.0 : toSeconds(parts[0].audio.duration()));
	}
	return 0;
}

}  // namespace

int main(int argc, char** argv) {
	if (argc >= 4 && std::string(argv[1]) == "--heard") return heard(argc, argv);
	if (argc < 4 || argc % 2) {
		std::fprintf(stderr, "usage: bench_stream PIECE_SECONDS AUDIO TEXT [AUDIO TEXT …]\n");
		return 2;
	}
	const double pieceSeconds = std::atof(argv[1]);
	const Language& lang = Language::get("en-US");
	std::vector<double> firsts, medians, maxima;
	int same = 0, clips = 0;
	std::printf("%-28s %8s %8s %6s %10s %10s %10s\n", "clip", "length s", "first s", "parts", "phones", "median ms", "max ms");
	for (int a = 2; a + 1 < argc; a += 2) {
		const std::string path = argv[a], text = argv[a + 1];
		int rate = 0;
		const std::vector<float> mono = monoAt(path, 22050, &rate);
		SpeechStream stream("b", text, lang, rate, rate);
		std::vector<Utterance> parts;
		double first = -1;
		const std::size_t step = std::size_t(pieceSeconds * rate);
		for (std::size_t at = 0; at < mono.size(); at += step) {
			const bool last = at + step >= mono.size();
			std::vector<float> piece(mono.begin() + std::ptrdiff_t(at), mono.begin() + std::ptrdiff_t(std::min(mono.size(), at + step)));
			stream.feed(piece, last, [&](Utterance u) { parts.push_back(std::move(u)); });
			if (first < 0 && !parts.empty()) first = double(std::min(mono.size(), at + step)) / rate;
		}
		AlignOptions ao;
		ao.languageTag = "en-US";
		AudioClip clip;
		clip.sampleRate = rate, clip.channels = 1, clip.samples = mono;
		const Alignment whole = alignSpeech(clip, text, ao);
		std::vector<PhoneSegment> a1, b1;
		Ticks at{0};
		for (const Utterance& u : parts) {
			for (PhoneSegment p : u.phones)
				if (p.phone != "_") p.start += at, p.end += at, a1.push_back(p);
			at += u.audio.duration();
		}
		for (const PhoneSegment& p : phoneSegments(whole.phones, lang, UnknownPhone::Error, Notation::Ipa))
			if (p.phone != "_") b1.push_back(p);
		std::vector<double> errors;
		bool equal = a1.size() == b1.size();
		for (std::size_t k = 0; equal && k < a1.size(); ++k) {
			equal = a1[k].phone == b1[k].phone;
			errors.push_back(std::abs(toSeconds(a1[k].start - b1[k].start)) * 1000);
		}
		std::sort(errors.begin(), errors.end());
		const double length = double(mono.size()) / rate;
		std::string name = path.substr(path.find_last_of('/') + 1);
		std::printf("%-28s %8.2f %8.2f %6zu %10s", name.c_str(), length, first, parts.size(), equal ? "same" : (std::to_string(a1.size()) + "/" + std::to_string(b1.size())).c_str());
		if (equal && !errors.empty()) {
			std::printf(" %10.0f %10.0f\n", errors[errors.size() / 2], errors.back());
			medians.push_back(errors[errors.size() / 2]), maxima.push_back(errors.back());
		} else {
			std::printf(" %10s %10s\n", "-", "-");
		}
		++clips, same += equal;
		firsts.push_back(length - first);
	}
	const auto med = [](std::vector<double> v) {
		std::sort(v.begin(), v.end());
		return v.empty() ? NAN : v[v.size() / 2];
	};
	std::printf("%d clips: the first part came %.2f s before the audio's end (median); the same phones in %d; boundary median %.0f ms (median over clips), max %.0f ms (median over clips)\n",
	            clips, med(firsts), same, med(medians), med(maxima));
}
