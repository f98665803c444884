// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/face_model.h"

#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>

#include "base/error.h"
#include "base/memory.h"
#include "base/parallel.h"
#include "geometry/eigen_products.h"
#include "image/region_mask.h"
#include "warp/piecewise_affine.h"

namespace talkhead {

long FaceModel::findSample(const std::string& emotion, const std::string& cdv, const std::array<std::string, 5>* context) const {
	static constexpr int kWeight[5] = {1, 4, 2, 4, 1};
	long best = -1;
	int bestScore = -1;
	for (std::size_t i = 0; i < samples.size(); ++i) {
		if (samples[i].emotion != emotion || samples[i].cdv != cdv) continue;
		if (!context) return long(i);
		int score = 0;
		for (int k = 0; k < 5; ++k) score += samples[i].context[std::size_t(k)] == (*context)[std::size_t(k)] ? kWeight[k] : 0;
		if (score > bestScore) best = long(i), bestScore = score;
	}
	return best;
}

int FaceModel::regionIndex(const std::string& name) const {
	for (std::size_t i = 0; i < regions.size(); ++i)
		if (regions[i].name == name) return int(i);
	return -1;
}

namespace {

void checkShape(const Points& s, int k, int width, int height, const std::string& what) {
	if (s.rows() != k) throw Error(what + ": has " + std::to_string(s.rows()) + " points, the scheme has " + std::to_string(k));
	for (Eigen::Index i = 0; i < s.rows(); ++i) {
		double x = s(i, 0), y = s(i, 1);
		if (!std::isfinite(x) || !std::isfinite(y) || x < -width || x > 2.0 * width || y < -height || y > 2.0 * height)
			throw Error(what + ": point " + std::to_string(i + 1) + " (" + std::to_string(x) + ", " + std::to_string(y) +
			            ") is far outside the " + std::to_string(width) + "x" + std::to_string(height) + " image");
	}
}

// The c = [a; s] column of one sample: planar appearance of the region, then the aligned shape.
void fillColumn(const RegionModel& r, const Image& frame, const Points& aligned, Eigen::MatrixXf& data, Eigen::Index col) {
	const Eigen::Index q = r.pixelCount();
	float* c = data.col(col).data();
	for (Eigen::Index p = 0; p < q; ++p) {
		const float* px = &frame.data[std::size_t(r.pixels[p]) * 3];
		c[p] = px[0];
		c[q + p] = px[1];
		c[2 * q + p] = px[2];
	}
	for (Eigen::Index i = 0; i < aligned.rows(); ++i) {
		c[3 * q + 2 * i] = float(aligned(i, 0));
		c[3 * q + 2 * i + 1] = float(aligned(i, 1));
	}
}

}  // namespace

namespace {

// The regions' masks in the mean-shape frame: their pixels and soft alpha.
std::vector<RegionModel> regionMasks(const Scheme& scheme, const Points& meanShape, int width, int height) {
	std::vector<RegionModel> regions;
	for (const RegionSpec& spec : scheme.regions) {
		RegionModel r;
		r.name = spec.name;
		Points boundary = regionBoundary(spec, meanShape);
		double featherPx = spec.feather * std::sqrt(regionArea(boundary, spec.grow));
		std::vector<float> alpha = softRegionMask(boundary, spec.grow, featherPx, width, height);
		for (std::size_t p = 0; p < alpha.size(); ++p) {
			if (alpha[p] > 0.f) {
				r.pixels.push_back(std::int32_t(p));
				r.alpha.push_back(alpha[p]);
			}
		}
		if (r.pixels.empty()) throw Error("region '" + spec.name + "' of scheme " + scheme.name + " covers no pixel of the mean shape");
		regions.push_back(std::move(r));
	}
	return regions;
}

// The render-time cache: each sample's reconstruction, 8-bit, by GEMM in chunks of samples, the chunks in
// parallel (fixed chunks: the bytes do not depend on the core count, D74).
void cacheAppearances(RegionModel& region, std::size_t m) {
	const std::size_t q3 = std::size_t(region.appearanceSize());
	region.sampleAppearances.resize(m * q3);
	parallelFor((m + 127) / 128, 0, [&](std::size_t chunk) {
		const std::size_t first = chunk * 128, count = std::min<std::size_t>(128, m - first);
		const Eigen::MatrixXf a = synthesizeAppearances(
		    region, region.pca.trainingCoefficients.middleRows(Eigen::Index(first), Eigen::Index(count)).transpose());
		for (std::size_t k = 0; k < count; ++k) {
			std::uint8_t* dst = &region.sampleAppearances[(first + k) * q3];
			quantizeAppearance(a.col(Eigen::Index(k)).data(), q3, dst);
		}
	});
}

// Appearance: every image warped to s̄, each region's data matrix filled (a column per image: its
// appearance, then its aligned shape).
std::vector<Eigen::MatrixXf> appearanceData(const FaceModel& model, const std::vector<Points>& shapes, const std::vector<SampleInfo>& samples,
                                            const ImageSource& images, const Points& meanWithBorder, unsigned threads, ProgressSink& progress) {
	const std::size_t m = shapes.size();
	const int k = model.scheme.pointCount(), width = model.width, height = model.height;
	std::vector<Eigen::MatrixXf> data(model.regions.size());
	for (std::size_t r = 0; r < model.regions.size(); ++r) {
		data[r].resize(model.regions[r].appearanceSize() + 2 * k, Eigen::Index(m));
		adviseHugePages(data[r].data(), std::size_t(data[r].size()) * sizeof(float));
	}
	// Only the pixels of the regions are needed: warp just their bounding box.
	int bx0 = width, by0 = height, bx1 = 0, by1 = 0;
	for (const auto& r : model.regions)
		for (auto p : r.pixels) {
			const int x = p % width, y = p / width;
			bx0 = std::min(bx0, x), by0 = std::min(by0, y), bx1 = std::max(bx1, x + 1), by1 = std::max(by1, y + 1);
		}
	PiecewiseAffineWarp toMean(model.frameMesh, meanWithBorder, width, height);
	toMean.clipSpans(bx0, by0, bx1, by1);
	std::atomic<std::size_t> done{0};
	std::mutex progressMutex;
	parallelFor(m, threads, [&](std::size_t i) {
		Image8 img = images(i);
		if (img.width != width || img.height != height)
			throw Error(samples[i].image, 0, "is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
			                                     ", the other images are " + std::to_string(width) + "x" + std::to_string(height));
		PiecewiseAffineWarp warp = toMean;
		warp.setSource(withFrameBorder(shapes[i], width, height));
		thread_local Image frame;  // reused: one 1280×720 float frame is 11 MB of page faults
		if (frame.width != width || frame.height != height) frame = Image(width, height, 3);
		warp.applyLanczos3(img, frame);  // D80: a bilinear warp here loses a third of the face's fine detail
		for (std::size_t r = 0; r < model.regions.size(); ++r)
			fillColumn(model.regions[r], frame, model.alignedShapes[i], data[r], Eigen::Index(i));
		std::size_t d = ++done;
		std::lock_guard<std::mutex> lock(progressMutex);
		progress.report(0.7 * double(d) / double(m), "warping images");
	});
	return data;
}

}  // namespace

FaceModel buildFaceModel(const Scheme& scheme, const std::vector<Points>& shapes, const std::vector<SampleInfo>& samples,
                         int width, int height, const ImageSource& images, const BuildOptions& options,
                         ProgressSink& progress) {
	const std::size_t m = shapes.size();
	if (m < 2) throw Error("a face model needs at least 2 training images, got " + std::to_string(m));
	if (samples.size() != m) throw std::logic_error("buildFaceModel: samples and shapes differ in count");
	if (width < 8 || height < 8 || long(width) * height > 50'000'000L)
		throw Error("absurd image size " + std::to_string(width) + "x" + std::to_string(height));
	const int k = scheme.pointCount();
	for (std::size_t i = 0; i < m; ++i) checkShape(shapes[i], k, width, height, samples[i].image);

	FaceModel model;
	model.scheme = scheme;
	model.width = width;
	model.height = height;
	model.samples = samples;

	progress.report(0.0, "aligning shapes");
	ProcrustesResult gpa = generalizedProcrustes(shapes, scheme.weights, options.procrustes);
	model.meanShape = gpa.mean;
	model.alignedShapes = gpa.aligned;
	model.referenceIndex = gpa.reference;
	model.procrustesIterations = gpa.iterations;
	model.procrustesChange = gpa.lastChange;
	model.faceMesh = delaunayTriangulation(model.meanShape);
	const Points meanWithBorder = withFrameBorder(model.meanShape, width, height);
	model.frameMesh = delaunayTriangulation(meanWithBorder);
	if (options.baseface >= long(shapes.size())) throw std::logic_error("buildFaceModel: baseface index out of range");
	model.basefaceIndex = options.baseface >= 0 ? std::size_t(options.baseface) : nearestShape(model.alignedShapes, model.meanShape);
	if (options.closedEyes >= long(shapes.size())) throw std::logic_error("buildFaceModel: closed-eyes index out of range");
	model.closedEyesIndex = options.closedEyes;

	model.regions = regionMasks(scheme, model.meanShape, width, height);

	std::vector<Eigen::MatrixXf> data = appearanceData(model, shapes, samples, images, meanWithBorder, options.threads, progress);

	// The baseface: the image nearest to the mean, warped to it over the whole frame.
	{
		PiecewiseAffineWarp warp(model.frameMesh, meanWithBorder, width, height);
		warp.setSource(withFrameBorder(shapes[model.basefaceIndex], width, height));
		model.baseface = Image8(width, height, 3);
		warp.apply(images(model.basefaceIndex), model.baseface);
	}
	for (std::size_t r = 0; r < model.regions.size(); ++r) {
		RegionModel& region = model.regions[r];
		progress.report(0.7 + 0.3 * double(r) / double(model.regions.size()), "PCA " + region.name);
		auto it = options.regionPca.find(region.name);
		region.pca = correlationPca(data[r], it != options.regionPca.end() ? it->second : options.pca);
		data[r] = Eigen::MatrixXf();  // free as we go
		cacheAppearances(region, m);
	}
	progress.report(1.0, "done");
	return model;
}

void quantizeAppearance(const float* values, std::size_t count, std::uint8_t* out) {
	for (std::size_t j = 0; j < count; ++j) {
		const float v = values[j] + 0.5f;
		out[j] = std::uint8_t(!(v > 0.f) ? 0.f : (v >= 255.f ? 255.f : v));  // NaN (a damaged model) → 0
	}
}

bool RegionModel::readCachedAppearance(std::size_t sample, std::uint8_t* out) const {
	const std::size_t q3 = std::size_t(appearanceSize());
	if (appearanceSource) {
		appearanceSource->read(sample, out);
		return true;
	}
	if (sampleAppearances.size() < (sample + 1) * q3) return false;
	std::memcpy(out, &sampleAppearances[sample * q3], q3);
	return true;
}

Eigen::VectorXf RegionModel::cachedAppearance(std::size_t sample) const {
	const std::size_t q3 = std::size_t(appearanceSize());
	std::vector<std::uint8_t> bytes(q3);
	if (!readCachedAppearance(sample, bytes.data())) return {};
	Eigen::VectorXf a(static_cast<Eigen::Index>(q3));
	for (std::size_t j = 0; j < q3; ++j) a(Eigen::Index(j)) = bytes[j];
	return a;
}

Eigen::VectorXf gatherAppearance(const RegionModel& r, const Image& frame) {
	const Eigen::Index q = r.pixelCount();
	Eigen::VectorXf a(3 * q);
	for (Eigen::Index p = 0; p < q; ++p) {
		const float* px = &frame.data[std::size_t(r.pixels[p]) * 3];
		a(p) = px[0];
		a(q + p) = px[1];
		a(2 * q + p) = px[2];
	}
	return a;
}

void scatterAppearance(const RegionModel& r, const Eigen::Ref<const Eigen::VectorXf>& a, Image& frame) {
	const Eigen::Index q = r.pixelCount();
	for (Eigen::Index p = 0; p < q; ++p) {
		float* px = &frame.data[std::size_t(r.pixels[p]) * 3];
		px[0] = a(p);
		px[1] = a(q + p);
		px[2] = a(2 * q + p);
	}
}

Eigen::VectorXf combinedVector(const RegionModel& r, const Image& frame, const Points& aligned) {
	const Eigen::Index q = r.pixelCount();
	Eigen::VectorXf c(3 * q + 2 * aligned.rows());
	c.head(3 * q) = gatherAppearance(r, frame);
	for (Eigen::Index i = 0; i < aligned.rows(); ++i) {
		c(3 * q + 2 * i) = float(aligned(i, 0));
		c(3 * q + 2 * i + 1) = float(aligned(i, 1));
	}
	return c;
}

Eigen::MatrixXf projectCombined(const RegionModel& region, const Eigen::Ref<const Eigen::MatrixXf>& combined) {
	pinEigenBlocking();
	const auto& p = region.pca;
	Eigen::MatrixXf h = (combined.colwise() - p.mean).array().colwise() / p.sigma.array();
	return p.basis.transpose() * h;
}

Projection projectImage(const FaceModel& model, const Image8& image, const Points& shape, bool coefficients) {
	if (shape.rows() != model.pointCount())
		throw Error("shape has " + std::to_string(shape.rows()) + " points, the model has " + std::to_string(model.pointCount()));
	Projection p;
	p.alignedShape = alignSimilarity(shape, model.meanShape, model.scheme.weights).apply(shape);
	PiecewiseAffineWarp warp(model.frameMesh, withFrameBorder(model.meanShape, model.width, model.height), model.width, model.height);
	warp.setSource(withFrameBorder(shape, image.width, image.height));
	p.shapeFree = Image(model.width, model.height, 3);
	warp.applyLanczos3(image, p.shapeFree);  // as the model's images were (D80)
	if (coefficients)
		for (const RegionModel& r : model.regions) p.coefficients.push_back(pcaProject(r.pca, combinedVector(r, p.shapeFree, p.alignedShape)));
	return p;
}

Eigen::VectorXf synthesizeAppearance(const RegionModel& region, const Eigen::Ref<const Eigen::VectorXf>& alpha) {
	return pcaReconstruct(region.pca, alpha, 0, region.appearanceSize());
}

Points synthesizeShape(const FaceModel& model, const Eigen::Ref<const Eigen::VectorXf>& beta, int region) {
	const RegionModel& r = model.regions.at(region);
	Eigen::VectorXf s = pcaReconstruct(r.pca, beta, r.appearanceSize(), 2 * model.pointCount());
	Points out(model.pointCount(), 2);
	for (int i = 0; i < model.pointCount(); ++i) {
		out(i, 0) = s(2 * i);
		out(i, 1) = s(2 * i + 1);
	}
	return out;
}

Eigen::VectorXf sampleCoefficients(const RegionModel& region, std::size_t sample) {
	return region.pca.trainingCoefficients.row(Eigen::Index(sample)).transpose();
}

Eigen::MatrixXf synthesizeAppearances(const RegionModel& region, const Eigen::Ref<const Eigen::MatrixXf>& coefficients) {
	pinEigenBlocking();  // the same rounding on every machine (D74)
	const auto& p = region.pca;
	const Eigen::Index q3 = region.appearanceSize(), l = std::min<Eigen::Index>(coefficients.rows(), p.basis.cols());
	Eigen::MatrixXf a = p.basis.topLeftCorner(q3, l) * coefficients.topRows(l);
	for (Eigen::Index c = 0; c < a.cols(); ++c) a.col(c) = p.mean.head(q3) + p.sigma.head(q3).cwiseProduct(a.col(c));
	return a;
}

Image compositeAppearance(const FaceModel& model, const std::vector<Eigen::VectorXf>& coefficients) {
	if (coefficients.size() != model.regions.size()) throw std::logic_error("compositeAppearance: one coefficient vector per region");
	std::vector<Eigen::VectorXf> appearances;
	for (std::size_t r = 0; r < model.regions.size(); ++r) appearances.push_back(synthesizeAppearance(model.regions[r], coefficients[r]));
	return compositeRegions(model, appearances);
}

Image compositeRegions(const FaceModel& model, const std::vector<Eigen::VectorXf>& appearances) {
	if (appearances.size() != model.regions.size()) throw std::logic_error("compositeRegions: one appearance per region");
	Image frame = toFloat(model.baseface);
	for (std::size_t ri = 0; ri < model.regions.size(); ++ri) {
		const RegionModel& r = model.regions[ri];
		const Eigen::VectorXf& a = appearances[ri];
		const Eigen::Index q = r.pixelCount();
		for (Eigen::Index p = 0; p < q; ++p) {
			float* px = &frame.data[std::size_t(r.pixels[p]) * 3];
			const float w = r.alpha[p];
			for (int c = 0; c < 3; ++c) px[c] = w * a(c * q + p) + (1 - w) * px[c];
		}
	}
	for (float& v : frame.data) v = v < 0.f ? 0.f : (v > 255.f ? 255.f : v);
	return frame;
}

Image8 warpFromMean(const FaceModel& model, const Image& meanFrame, const Points& shape) {
	PiecewiseAffineWarp warp(model.frameMesh, withFrameBorder(shape, model.width, model.height), model.width, model.height);
	warp.setSource(withFrameBorder(model.meanShape, model.width, model.height));
	Image8 out(model.width, model.height, 3);
	warp.apply(meanFrame, out);
	return out;
}

}  // namespace talkhead
