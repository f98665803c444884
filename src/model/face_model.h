// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "base/progress.h"
#include "geometry/scheme.h"
#include "geometry/shape.h"
#include "image/image.h"
#include "model/pca.h"

namespace talkhead {

// Labels of one training image; the model looks appearances up by (emotion, cdv).
struct SampleInfo {
	std::string image;  // file name (for reports)
	std::string emotion;
	std::string cdv;
	std::string word;
	std::array<std::string, 5> context;
};

// Reads one sample's 8-bit appearance (3q bytes) of one region from wherever the cache lives (a model
// file opened for rendering keeps it on disk). Thread-safe; throws Error naming the file on damage.
class AppearanceSource {
public:
	virtual ~AppearanceSource() = default;
	virtual void read(std::size_t sample, std::uint8_t* out) const = 0;
};

// One face region's appearance model (Costa 2015 §4.1.3): its pixels in the mean-shape frame, its soft
// mask, and a correlation PCA over the combined vector c = [a; s] with a RGB channel-planar over the
// region's q pixels (Eq. 4.4) and s the full aligned shape (2k), so n = 3q + 2k.
struct RegionModel {
	std::string name;
	std::vector<std::int32_t> pixels;  // q pixel indices (y·width + x) in the model frame, ascending
	std::vector<float> alpha;          // q soft-mask values in (0, 1]
	CorrelationPca pca;
	// Every training sample's appearance reconstructed from its kept components (Eq. 5.2), 8-bit,
	// channel-planar, sample after sample (samples × 3q): keyposes need no basis product at render time.
	std::vector<std::uint8_t> sampleAppearances;
	// The same cache left on disk (render loads): read sample by sample, each checksum-verified.
	std::shared_ptr<const AppearanceSource> appearanceSource;

	Eigen::Index pixelCount() const { return Eigen::Index(pixels.size()); }
	bool hasAppearanceCache() const { return !sampleAppearances.empty() || appearanceSource != nullptr; }
	// Sample i's cached appearance (3q bytes, channel-planar) into out; false when the model has no cache.
	bool readCachedAppearance(std::size_t sample, std::uint8_t* out) const;
	// Sample i's cached appearance as floats (3q), or an empty vector when the model has no cache.
	Eigen::VectorXf cachedAppearance(std::size_t sample) const;
	Eigen::Index appearanceSize() const { return 3 * pixelCount(); }
};

// The "expressive speech face model" database of spec §4.8.
struct FaceModel {
	Scheme scheme;
	int width = 0, height = 0;           // model frame = the training images' size
	Points meanShape;                    // s̄, in the reference image's pixel frame
	std::vector<Points> alignedShapes;   // one per training image
	std::vector<SampleInfo> samples;     // one per training image
	std::size_t referenceIndex = 0;      // GPA's normalising shape
	int procrustesIterations = 0;
	double procrustesChange = 0;
	TriangleMesh faceMesh;               // Delaunay of s̄ (k vertices)
	TriangleMesh frameMesh;              // Delaunay of s̄ + 8 frame-border points (k + 8 vertices)
	Image8 baseface;                     // the image nearest to s̄, warped to s̄, full frame
	std::size_t basefaceIndex = 0;
	long closedEyesIndex = -1;           // training image with the eyes shut (blinks take the lid from it, D50); −1 = none
	std::vector<RegionModel> regions;    // coarse → fine

	int pointCount() const { return int(meanShape.rows()); }
	std::size_t sampleCount() const { return samples.size(); }
	// Index of the training sample with these labels, or −1. Where several samples share them (a corpus
	// from video keeps --per-cdv N), the one whose phone context (two before, own, two after) best matches
	// `context`: the adjacent phones weigh 4, the outer ones 1, the own phone 2; ties (and no context)
	// keep the corpus's order, which lists the most typical frame first.
	long findSample(const std::string& emotion, const std::string& cdv, const std::array<std::string, 5>* context = nullptr) const;
	// The region with this name, or −1.
	int regionIndex(const std::string& name) const;
};

struct BuildOptions {
	PcaOptions pca;                                // default for every region
	std::map<std::string, PcaOptions> regionPca;   // per-region overrides
	unsigned threads = 0;                          // 0 = all cores
	ProcrustesOptions procrustes;
	long baseface = -1;                            // training image used as the baseface; −1 = the one nearest s̄
	long closedEyes = -1;                          // training image with the eyes shut; −1 = none
};

// Provides training image i (8-bit RGB, all the same size) on demand; called from worker threads.
using ImageSource = std::function<Image8(std::size_t)>;

// Builds the model: weighted GPA of the shapes, Delaunay meshes on s̄, region masks, warps every image
// to s̄, and one correlation PCA per region. shapes[i] are in image i's pixels, in the scheme's order.
FaceModel buildFaceModel(const Scheme& scheme, const std::vector<Points>& shapes, const std::vector<SampleInfo>& samples,
                         int width, int height, const ImageSource& images, const BuildOptions& options,
                         ProgressSink& progress);

// Analysis: an image and its shape projected into the model.
struct Projection {
	Points alignedShape;                          // the shape similarity-aligned to s̄
	Image shapeFree;                              // the image warped to s̄ (model frame, float)
	std::vector<Eigen::VectorXf> coefficients;    // α per region (α_i = hᵀh_i over the full [a; s])
};
// coefficients = false: only the aligned shape and the shape-free image (for batch projection).
Projection projectImage(const FaceModel& model, const Image8& image, const Points& shape, bool coefficients = true);
// The region's combined vector c = [a; s] (n) of a shape-free image and its aligned shape.
Eigen::VectorXf combinedVector(const RegionModel& region, const Image& shapeFree, const Points& alignedShape);
// Batch projection: α for the columns of `combined` (n × count) → l × count, one GEMM.
Eigen::MatrixXf projectCombined(const RegionModel& region, const Eigen::Ref<const Eigen::MatrixXf>& combined);

// Synthesis: shape-free appearance of a region, channel-planar (3q), â = ā + D_a Σ α_i e_i (Eq. 5.2).
Eigen::VectorXf synthesizeAppearance(const RegionModel& region, const Eigen::Ref<const Eigen::VectorXf>& alpha);
// Synthesis: ŝ = s̄ + D_s Σ β_i f_i (Eq. 5.3) from a region's components (the face region by default).
Points synthesizeShape(const FaceModel& model, const Eigen::Ref<const Eigen::VectorXf>& beta, int region = 0);
// Appearance of a training sample (its stored coefficients), per region.
Eigen::VectorXf sampleCoefficients(const RegionModel& region, std::size_t sample);

// Appearance values → 8-bit as the render-time cache stores them: rounded, clamped to [0, 255], NaN → 0.
void quantizeAppearance(const float* values, std::size_t count, std::uint8_t* out);

// Appearances of many coefficient vectors at once (one GEMM): coefficients l × count → 3q × count.
Eigen::MatrixXf synthesizeAppearances(const RegionModel& region, const Eigen::Ref<const Eigen::MatrixXf>& coefficients);

// Spec §5.3: the baseface with every region's appearance pasted coarse → fine through its soft mask,
// in the mean-shape frame, clamped to [0, 255]. coefficients: one vector per region.
Image compositeAppearance(const FaceModel& model, const std::vector<Eigen::VectorXf>& coefficients);
// The same from already synthesised region appearances (3q each, channel-planar).
Image compositeRegions(const FaceModel& model, const std::vector<Eigen::VectorXf>& appearances);
// Writes a region's planar appearance vector into an interleaved model-frame image (ROI pixels only).
void scatterAppearance(const RegionModel& region, const Eigen::Ref<const Eigen::VectorXf>& appearance, Image& frame);
// Reads a region's planar appearance vector out of a model-frame image.
Eigen::VectorXf gatherAppearance(const RegionModel& region, const Image& frame);

// Warps a model-frame image from s̄ to `shape` over the frame mesh (full frame, border points fixed).
Image8 warpFromMean(const FaceModel& model, const Image& meanFrame, const Points& shape);

}  // namespace talkhead
