// SPDX-License-Identifier: GPL-3.0-or-later
#include "corpus/build.h"

#include <filesystem>

#include "base/error.h"
#include "media/image_io.h"

namespace talkhead {

Scheme corpusScheme(const Corpus& corpus, const std::string& name) {
	if (corpus.entries.empty()) throw Error(corpus.path, 0, "the corpus has no image");
	const int k = int(corpus.entries.front().points.rows());
	const std::string schemeName = name.empty() ? corpus.schemeName : name;
	if (schemeName.empty()) throw Error(corpus.path, 0, "cannot tell the landmark scheme from " + std::to_string(k) + " points; name the scheme");
	Scheme scheme = loadScheme(schemeName);
	if (scheme.pointCount() != k)
		throw Error(corpus.path, 0, "has " + std::to_string(k) + " points per shape, scheme " + scheme.name + " has " + std::to_string(scheme.pointCount()));
	return scheme;
}

FaceModel buildFaceModel(const Corpus& corpus, const Scheme& scheme, BuildOptions options, ProgressSink& progress) {
	if (corpus.entries.empty()) throw Error(corpus.path, 0, "the corpus has no image");
	int width = 0, height = 0;
	imageSize(corpus.entries.front().imagePath, width, height);
	std::vector<Points> shapes;
	std::vector<SampleInfo> samples;
	for (const auto& e : corpus.entries) {
		if (e.points.rows() != scheme.pointCount())
			throw Error(corpus.path, 0, std::filesystem::path(e.imagePath).filename().string() + " has " + std::to_string(e.points.rows()) + " points, scheme " +
			                                scheme.name + " has " + std::to_string(scheme.pointCount()));
		if (!corpus.baseface.empty() && e.imagePath == corpus.baseface && options.baseface < 0) options.baseface = long(shapes.size());
		if (!corpus.closedEyes.empty() && e.imagePath == corpus.closedEyes) options.closedEyes = long(shapes.size());
		shapes.push_back(e.points);
		samples.push_back(SampleInfo{std::filesystem::path(e.imagePath).filename().string(), e.emotionLabel(), e.cdvLabel(), e.word, e.context});
	}
	return buildFaceModel(scheme, shapes, samples, width, height, [&](std::size_t i) { return readImage(corpus.entries[i].imagePath); }, options, progress);
}

AuAppearance buildAuAppearance(const Corpus& corpus, const Scheme& scheme, const std::map<std::string, AuProfile>& profiles, int gridWidth) {
	std::vector<AppearanceSample> samples;
	for (const auto& e : corpus.entries) samples.push_back({e.emotionLabel(), e.cdvLabel(), e.points});
	AuAppearance a = learnAuAppearance(
	    scheme, samples, [&](std::size_t i) { return readImage(corpus.entries[i].imagePath); }, profiles, gridWidth);
	a.source = std::filesystem::path(corpus.path).filename().string() + ": " + a.source;
	return a;
}

}  // namespace talkhead
