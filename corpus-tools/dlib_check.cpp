// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead-dlib-check: do real-face detectors take the synthetic face for a face?
//
// Runs dlib's HOG frontal face detector and its 68-point shape predictor (Debian libdlib-data) on every
// image of a CH-Unicamp-format corpus (ch-unicamp-56 points) and compares the predicted eye and mouth
// points with the corpus's ground truth, in units of the outer eye-corner distance (the 300-W
// normalisation). Prints one line per image and a summary; exits 1 if a face is missed or the mean
// error exceeds --max-error (default 0.1).
//
// usage: talkhead-dlib-check CORPUS.csv [--model shape_predictor_68_face_landmarks.dat] [--max-error X]
//        [--every N] [--threads N]
#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_transforms.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "base/error.h"
#include "base/parallel.h"
#include "corpus/corpus.h"
#include "media/image_io.h"

using namespace talkhead;

namespace {

// ch-unicamp-56 index ↔ iBUG-68 index (or the mean of two iBUG points) for the compared points.
struct Pair {
	const char* name;
	int ours;
	int ibugA, ibugB;  // ibugB = −1: one point
};
// ch-unicamp-56 order: RM2 0, LM2 1, CUM 2, CLM 3, VMR 4, VML 5, …, REYE1 16, REYE3 17, REYE2 18, REYE4 19,
// LEYE1 20, LEYE3 21, LEYE2 22, LEYE4 23, …, CIUM 52, CILM 53.
const Pair kPairs[] = {
    {"REYE1 outer corner", 16, 36, -1}, {"REYE3 inner corner", 17, 39, -1}, {"REYE2 upper lid", 18, 37, 38}, {"REYE4 lower lid", 19, 40, 41},
    {"LEYE1 outer corner", 20, 45, -1}, {"LEYE3 inner corner", 21, 42, -1}, {"LEYE2 upper lid", 22, 43, 44}, {"LEYE4 lower lid", 23, 46, 47},
    {"RM2 mouth corner", 0, 48, -1},    {"LM2 mouth corner", 1, 54, -1},    {"CUM upper lip", 2, 51, -1},     {"CLM lower lip", 3, 57, -1},
    {"VMR bow peak", 4, 50, -1},        {"VML bow peak", 5, 52, -1},        {"CIUM inner upper", 52, 62, -1}, {"CILM inner lower", 53, 66, -1},
};

}  // namespace

int main(int argc, char** argv) {
	std::string corpusPath, modelPath = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";
	double maxError = 0.1;
	int every = 1;
	unsigned threads = 0;
	for (int i = 1; i < argc; ++i) {
		std::string a = argv[i];
		auto value = [&]() -> std::string {
			if (i + 1 >= argc) {
				std::fprintf(stderr, "talkhead-dlib-check: %s needs a value\n", a.c_str());
				std::exit(2);
			}
			return argv[++i];
		};
		if (a == "--model") modelPath = value();
		else if (a == "--max-error") maxError = std::atof(value().c_str());
		else if (a == "--every") every = std::max(1, std::atoi(value().c_str()));
		else if (a == "--threads") threads = unsigned(std::max(0, std::atoi(value().c_str())));
		else if (a == "--help" || a == "-h") {
			std::printf("usage: talkhead-dlib-check CORPUS.csv [--model FILE.dat] [--max-error X] [--every N] [--threads N]\n");
			return 0;
		} else if (corpusPath.empty()) corpusPath = a;
		else {
			std::fprintf(stderr, "talkhead-dlib-check: unexpected argument '%s'\n", a.c_str());
			return 2;
		}
	}
	if (corpusPath.empty()) {
		std::fprintf(stderr, "usage: talkhead-dlib-check CORPUS.csv [--model FILE.dat] [--max-error X] [--every N] [--threads N]\n");
		return 2;
	}
	try {
		Corpus corpus = loadCorpus(corpusPath);
		if (corpus.entries.front().points.rows() != 56) throw Error(corpusPath, 0, "expected ch-unicamp-56 points");
		dlib::shape_predictor sp;
		try {
			dlib::deserialize(modelPath) >> sp;
		} catch (const std::exception& e) {
			throw Error(modelPath, 0, std::string("cannot load the dlib shape predictor (Debian package libdlib-data): ") + e.what());
		}
		std::vector<std::size_t> picked;
		for (std::size_t i = 0; i < corpus.entries.size(); i += std::size_t(every)) picked.push_back(i);
		std::vector<double> err(picked.size(), -1);
		std::vector<std::string> lines(picked.size());
		std::vector<std::vector<double>> perPoint(picked.size());
		parallelFor(picked.size(), threads, [&](std::size_t k) {
			thread_local dlib::frontal_face_detector detector = dlib::get_frontal_face_detector();
			const CorpusEntry& e = corpus.entries[picked[k]];
			Image8 img = readImage(e.imagePath);
			// Detect on a half-size image when it is large (faces are ~280 px wide at 720p; HOG needs ≥ 80),
			// predict at full size.
			dlib::array2d<dlib::rgb_pixel> full(img.height, img.width), half;
			for (int y = 0; y < img.height; ++y)
				for (int x = 0; x < img.width; ++x) full[y][x] = dlib::rgb_pixel(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
			const long factor = img.height >= 600 ? 2 : 1;
			half.set_size(img.height / factor, img.width / factor);
			dlib::resize_image(full, half);
			std::vector<dlib::rectangle> faces = detector(half);
			const std::string name = e.imagePath.substr(e.imagePath.find_last_of('/') + 1);
			if (faces.empty()) {
				lines[k] = name + "\tno face found";
				return;
			}
			dlib::rectangle r = faces.front();
			for (const auto& f : faces)
				if (f.area() > r.area()) r = f;
			r = dlib::rectangle(r.left() * factor, r.top() * factor, r.right() * factor + factor - 1, r.bottom() * factor + factor - 1);
			dlib::full_object_detection shape = sp(full, r);
			auto ib = [&](int i) { return Eigen::RowVector2d(shape.part(i).x(), shape.part(i).y()); };
			const double iod = (e.points.row(16) - e.points.row(20)).norm();
			double sum = 0;
			for (const Pair& p : kPairs) {
				Eigen::RowVector2d q = p.ibugB < 0 ? ib(p.ibugA) : 0.5 * (ib(p.ibugA) + ib(p.ibugB));
				double d = (q - e.points.row(p.ours)).norm() / iod;
				perPoint[k].push_back(d);
				sum += d;
			}
			err[k] = sum / std::size(kPairs);
			char buf[128];
			std::snprintf(buf, sizeof buf, "\t%.4f", err[k]);
			lines[k] = name + buf;
		});
		std::size_t missed = 0;
		double total = 0, worst = 0;
		std::vector<double> pointMean(std::size(kPairs), 0);
		for (std::size_t k = 0; k < picked.size(); ++k) {
			std::printf("%s\n", lines[k].c_str());
			if (err[k] < 0) {
				++missed;
				continue;
			}
			total += err[k];
			worst = std::max(worst, err[k]);
			for (std::size_t j = 0; j < std::size(kPairs); ++j) pointMean[j] += perPoint[k][j];
		}
		const std::size_t found = picked.size() - missed;
		const double mean = found ? total / double(found) : 1e9;
		std::printf("\nper point (mean error / eye-corner distance):\n");
		for (std::size_t j = 0; j < std::size(kPairs); ++j) std::printf("  %-20s %.4f\n", kPairs[j].name, found ? pointMean[j] / double(found) : 0.0);
		std::printf("faces found %zu of %zu; mean error %.4f (worst image %.4f) eye-corner distances; limit %.3f\n", found, picked.size(), mean, worst,
		            maxError);
		return (missed == 0 && mean <= maxError) ? 0 : 1;
	} catch (const std::exception& e) {
		std::fprintf(stderr, "talkhead-dlib-check: error: %s\n", describeException(e).c_str());
		return 1;
	}
}
