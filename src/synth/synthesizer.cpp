// SPDX-License-Identifier: GPL-3.0-or-later
#include "synth/synthesizer.h"

#include <algorithm>
#include <stdexcept>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>

#include "base/error.h"
#include "base/memory.h"
#include "base/parallel.h"
#include "geometry/scheme.h"
#include "phonetics/labels.h"
#include "warp/piecewise_affine.h"

namespace talkhead {

namespace {
// CPU time of the calling thread (what the drawing costs, whatever else runs on the machine).
double threadCpuSeconds() {
	timespec t{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// D41: the anchors' distance outside everything that moves, as a fraction of the mean shape's larger side.
constexpr double kAnchorMargin = 0.15;

// Luma pixel coordinates → 4:2:0 chroma sample coordinates (a chroma sample is centred on its 2×2 block).
Points toChroma(const Points& p) { return (p.array() - 0.5) * 0.5; }

// o = a (1 − w) + b w with w = wb / 256 (wb = 0: a exactly; 256: b exactly).
inline void blendRow(const std::uint8_t* a, const std::uint8_t* b, int wb, std::uint8_t* o, std::size_t n) {
	if (wb == 0) {
		std::memcpy(o, a, n);
		return;
	}
	const int wa = 256 - wb;
	for (std::size_t i = 0; i < n; ++i) o[i] = std::uint8_t((a[i] * wa + b[i] * wb + 128) >> 8);
}
}  // namespace

namespace {
// Face points, then the static anchors (D41), then the frame border: the vertices of the synthesizer's mesh.
Points withAnchors(const Points& face, const Points& anchors, int width, int height) {
	Points p(face.rows() + anchors.rows(), 2);
	p << face, anchors;
	return withFrameBorder(p, width, height);
}

// The scheme's eyes: the model's, else the shipped scheme of the same name and points (models built before
// schemes had 'eye' lines).
// (And its brows, the same way.)
Scheme partsOf(const FaceModel& model) {
	Scheme parts;
	parts.eyes = model.scheme.eyes;
	parts.brows = model.scheme.brows;
	if (!parts.eyes.empty() || !parts.brows.empty()) return parts;
	try {
		const Scheme s = loadScheme(model.scheme.name);
		if (s.pointNames == model.scheme.pointNames) parts.eyes = s.eyes, parts.brows = s.brows;
	} catch (const Error&) {
	}
	return parts;
}

// y of a polyline (points in order of x, as lids run corner to corner) at x; NaN outside its x range.
double polylineY(const std::vector<Eigen::RowVector2d>& line, double x) {
	for (std::size_t i = 0; i + 1 < line.size(); ++i) {
		const double xa = line[i](0), xb = line[i + 1](0);
		if ((x >= std::min(xa, xb) && x <= std::max(xa, xb)) && xa != xb) return line[i](1) + (x - xa) / (xb - xa) * (line[i + 1](1) - line[i](1));
	}
	return std::nan("");
}

std::vector<Eigen::RowVector2d> lidLine(const Points& p, const EyeSpec& e, bool upper) {
	std::vector<Eigen::RowVector2d> line{p.row(e.corner0)};
	for (int i : upper ? e.upper : e.lower) line.push_back(p.row(i));
	line.push_back(p.row(e.corner1));
	return line;
}

// The closed lid of one eye in the mean-shape frame (D42): between the upper lid (raised a little, to
// cover its lash line) and the lower lid, the skin of a band just above the upper lid, column by column,
// shaded slightly toward a dark lash line along the lower lid, where a shut eye's lashes meet. Soft edges.
// Luma, chroma and chroma-resolution alpha of a patch whose RGB and alpha are set.
void finishPatch(ClosedLidPatch& patch, YuvRange range) {
	const int cw = patch.w / 2, ch = patch.h / 2;
	patch.y.resize(std::size_t(patch.w) * patch.h);
	patch.uv.resize(std::size_t(cw) * ch * 2);
	rgbToYuv420(patch.rgb.data(), std::size_t(patch.w) * 3, patch.w, patch.h, range, patch.y.data(), std::size_t(patch.w), patch.uv.data(),
	            patch.uv.data() + 1, std::size_t(cw) * 2, 2);
	patch.alphaC.resize(std::size_t(cw) * ch);
	for (int y = 0; y < ch; ++y)
		for (int x = 0; x < cw; ++x) {
			const std::size_t a = std::size_t(2 * y) * patch.w + std::size_t(2 * x);
			patch.alphaC[std::size_t(y) * cw + std::size_t(x)] = 0.25f * (patch.alpha[a] + patch.alpha[a + 1] + patch.alpha[a + patch.w] + patch.alpha[a + patch.w + 1]);
		}
}

// D50: the shut eye from the corpus's closed-eyes image `closed` (its appearance composited in the mean
// frame): the lid's skin from 0.3 eye widths above the open upper lid down to just below the lower lid,
// copied as it is: warped to the shut lids' shape it gives back the closed-eyes image's own lid, crease
// and lashes. In the open eye's slit the shut image has no area of its own (its lash line is smeared
// across it), so this patch comes in only as the lids finish closing (from 60 % shut), over the drawn lid
// of D42 (whose skin is then taken from the shut image's lid), which covers the half-closed eye.
ClosedLidPatch closedLidFrom(const FaceModel& m, const Image8& closed, const EyeSpec& e, int rx0, int ry0, int rx1, int ry1, YuvRange range) {
	ClosedLidPatch patch;
	const auto up = lidLine(m.meanShape, e, true), lo = lidLine(m.meanShape, e, false);
	const double width = (m.meanShape.row(e.corner1) - m.meanShape.row(e.corner0)).norm();
	if (!(width > 2)) return patch;
	const double above = 0.30 * width, below = 0.05 * width, feather = std::max(1.0, 0.08 * width);
	double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
	for (const auto* line : {&up, &lo})
		for (const auto& q : *line) xmin = std::min(xmin, q(0)), xmax = std::max(xmax, q(0)), ymin = std::min(ymin, q(1)), ymax = std::max(ymax, q(1));
	const int x0 = std::max(rx0, (int(std::floor(xmin - 2 * feather)) - 1) & ~1), y0 = std::max(ry0, (int(std::floor(ymin - above - feather)) - 1) & ~1);
	const int x1 = std::min(rx1, (int(std::ceil(xmax + 2 * feather)) + 2) & ~1), y1 = std::min(ry1, (int(std::ceil(ymax + below + feather)) + 2) & ~1);
	if (x1 - x0 < 2 || y1 - y0 < 2) return patch;
	patch.x0 = x0, patch.y0 = y0, patch.w = x1 - x0, patch.h = y1 - y0;
	patch.alpha.assign(std::size_t(patch.w) * patch.h, 0.f);
	patch.rgb.resize(std::size_t(patch.w) * patch.h * 3);
	patch.from = 0.6;
	for (int x = x0; x < x1; ++x) {
		const double xc = std::clamp(double(x), xmin, xmax);
		const double yu = polylineY(up, xc), yl = polylineY(lo, xc);
		const double top = (std::isnan(yu) ? ymin : yu) - above, bottom = (std::isnan(yl) ? ymax : yl) + below;
		const double side = std::min(x - (xmin - 2 * feather), (xmax + 2 * feather) - x) / feather;
		for (int y = y0; y < y1; ++y) {
			const std::size_t i = std::size_t(y - y0) * std::size_t(patch.w) + std::size_t(x - x0);
			const double inside = std::min({(double(y) - top) / feather, (bottom - double(y)) / feather, side});
			patch.alpha[i] = float(std::clamp(inside, 0.0, 1.0));
			for (int c = 0; c < 3; ++c) patch.rgb[3 * i + std::size_t(c)] = closed.row(y)[3 * x + c];
		}
	}
	finishPatch(patch, range);
	return patch;
}

ClosedLidPatch closedLid(const FaceModel& m, const Image8& b, const EyeSpec& e, int rx0, int ry0, int rx1, int ry1, YuvRange range) {
	ClosedLidPatch patch;
	const auto up = lidLine(m.meanShape, e, true), lo = lidLine(m.meanShape, e, false);
	const double width = (m.meanShape.row(e.corner1) - m.meanShape.row(e.corner0)).norm();
	if (!(width > 2)) return patch;
	const double cover = 0.12 * width, below = 0.03 * width, feather = std::max(1.0, 0.06 * width), band = std::max(2.0, 0.15 * width);
	double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
	for (const auto* line : {&up, &lo})
		for (const auto& q : *line) xmin = std::min(xmin, q(0)), xmax = std::max(xmax, q(0)), ymin = std::min(ymin, q(1)), ymax = std::max(ymax, q(1));
	const int x0 = std::max(rx0, (int(std::floor(xmin - feather)) - 1) & ~1), y0 = std::max(ry0, (int(std::floor(ymin - cover - feather)) - 1) & ~1);
	const int x1 = std::min(rx1, (int(std::ceil(xmax + feather)) + 2) & ~1), y1 = std::min(ry1, (int(std::ceil(ymax + below + feather)) + 2) & ~1);
	if (x1 - x0 < 2 || y1 - y0 < 2) return patch;
	patch.x0 = x0, patch.y0 = y0, patch.w = x1 - x0, patch.h = y1 - y0;
	patch.alpha.assign(std::size_t(patch.w) * patch.h, 0.f);
	patch.rgb.resize(std::size_t(patch.w) * patch.h * 3);
	// Per column: the lid's top and bottom, and the skin just above the covered lid margin (a band below the
	// crease), then smoothed across columns so no crease or lash of the open eye streaks the lid.
	const int n = x1 - x0;
	const std::size_t cols = static_cast<std::size_t>(n);
	std::vector<double> tops(cols), bottoms(cols), lashes(cols), skin(cols * 3), smooth(cols * 3);
	for (int x = x0; x < x1; ++x) {
		const std::size_t j = std::size_t(x - x0);
		const double xc = std::clamp(double(x), xmin, xmax);
		const double yu = polylineY(up, xc), yl = polylineY(lo, xc);
		tops[j] = (std::isnan(yu) ? ymin : yu) - cover;
		bottoms[j] = (std::isnan(yl) ? ymax : yl) + below;
		lashes[j] = (std::isnan(yl) ? ymax : yl) - 0.02 * width;
		std::vector<int> column[3];
		for (int y = int(std::floor(tops[j] - band)); y < int(std::floor(tops[j])); ++y) {
			const int yy = std::clamp(y, 0, b.height - 1), xx = std::clamp(x, 0, b.width - 1);
			for (int c = 0; c < 3; ++c) column[c].push_back(b.row(yy)[3 * xx + c]);
		}
		for (int c = 0; c < 3; ++c) {  // the median: robust to a stray line in the band
			auto& v = column[c];
			std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
			skin[3 * j + std::size_t(c)] = v.empty() ? 128 : v[v.size() / 2];
		}
	}
	const int reach = std::max(1, int(0.12 * width));
	for (int j = 0; j < n; ++j)
		for (int c = 0; c < 3; ++c) {
			double sum = 0;
			int count = 0;
			for (int k = std::max(0, j - reach); k <= std::min(n - 1, j + reach); ++k) sum += skin[3 * std::size_t(k) + std::size_t(c)], ++count;
			smooth[3 * std::size_t(j) + std::size_t(c)] = sum / count;
		}
	const double sigma = std::max(0.8, 0.03 * width);
	for (int x = x0; x < x1; ++x) {
		const std::size_t j = std::size_t(x - x0);
		const double top = tops[j], bottom = bottoms[j];
		const double side = std::min(x - (xmin - feather), (xmax + feather) - x) / feather;  // fade at the corners
		for (int y = y0; y < y1; ++y) {
			const std::size_t i = std::size_t(y - y0) * std::size_t(patch.w) + j;
			const double inside = std::min({(double(y) - (top - feather)) / feather, ((bottom + feather) - double(y)) / feather, side});
			patch.alpha[i] = float(std::clamp(inside, 0.0, 1.0));
			const double t = std::clamp((double(y) - top) / std::max(1.0, bottom - top), 0.0, 1.0);
			const double d = double(y) - lashes[j];
			const double shade = (1 - 0.06 * t) * (1 - 0.7 * std::exp(-(d * d) / (2 * sigma * sigma)) * std::clamp(side, 0.0, 1.0));
			for (int c = 0; c < 3; ++c)
				patch.rgb[3 * i + std::size_t(c)] = std::uint8_t(std::clamp(smooth[3 * j + std::size_t(c)] * shade + 0.5, 0.0, 255.0));
		}
	}
	finishPatch(patch, range);
	return patch;
}
}  // namespace

Synthesizer::Synthesizer(const FaceModel& model, const SynthOptions& o) : model_(model), o_(o) {
	width_ = o.width > 0 ? o.width : model.width;
	height_ = o.height > 0 ? o.height : model.height;
	scaleX_ = double(width_) / model.width;
	scaleY_ = double(height_) / model.height;
	// The face box: every region pixel, grown by one and with even corners (whole chroma blocks).
	int x0 = model.width, y0 = model.height, x1 = 0, y1 = 0;
	for (const auto& r : model.regions)
		for (std::int32_t idx : r.pixels) {
			const int x = idx % model.width, y = idx / model.width;
			x0 = std::min(x0, x);
			y0 = std::min(y0, y);
			x1 = std::max(x1, x + 1);
			y1 = std::max(y1, y + 1);
		}
	if (x1 > x0 && y1 > y0) {
		roiX0_ = std::max(0, x0 - 1) & ~1;
		roiY0_ = std::max(0, y0 - 1) & ~1;
		roiX1_ = std::min(model.width, (x1 + 2) & ~1);
		roiY1_ = std::min(model.height, (y1 + 2) & ~1);
	}
	{
		const Eigen::RowVector2d lo = model.meanShape.colwise().minCoeff(), hi = model.meanShape.colwise().maxCoeff();
		faceSize_ = std::max(1.0, (hi - lo).maxCoeff());
		centre_ = model.meanShape.colwise().mean();
	}
	const Scheme parts = partsOf(model);
	eyes_ = parts.eyes;
	brows_ = parts.brows;
	if (eyes_.size() >= 2) {
		auto centre = [&](const EyeSpec& e) { return (model.meanShape.row(e.corner0) + model.meanShape.row(e.corner1)) / 2; };
		eyeDistance_ = (centre(eyes_[0]) - centre(eyes_[1])).norm();
	}
	if (!(eyeDistance_ > 0)) eyeDistance_ = 0.3 * faceSize_;
	eyeMid_ = centre_;
	if (o.modulator && o.modulator->curves().hasHead() && eyes_.size() >= 2) {
		stabilise_ = true;
		stabiliseWeights_ = Eigen::VectorXd::Zero(model.pointCount());
		for (const EyeSpec& e : eyes_) stabiliseWeights_(e.corner0) = stabiliseWeights_(e.corner1) = 1;
		if (model.scheme.name == "ibug-68" && model.pointCount() == 68) {  // and the nose, as talkhead track registers heads
			stabiliseWeights_(27) = 0.5, stabiliseWeights_(30) = 1;
			for (int i : {31, 33, 35}) stabiliseWeights_(i) = 0.5;
		}
	}
	if (eyes_.size() >= 2)
		eyeMid_ = (model.meanShape.row(eyes_[0].corner0) + model.meanShape.row(eyes_[0].corner1) + model.meanShape.row(eyes_[1].corner0) +
		           model.meanShape.row(eyes_[1].corner1)) / 4;
	// D41: anchors a quarter of the face's size outside everything that moves (every training shape and the
	// face box), fixed in every frame.
	{
		std::vector<Points> extent = model.alignedShapes;
		extent.push_back(model.meanShape);
		// Every pixel the regions paste: per row, the outer corners of its leftmost and rightmost pixels.
		std::vector<int> left(std::size_t(model.height), model.width), right(std::size_t(model.height), -1);
		for (const auto& r : model.regions)
			for (std::int32_t idx : r.pixels) {
				const std::size_t y = std::size_t(idx / model.width);
				left[y] = std::min(left[y], idx % model.width);
				right[y] = std::max(right[y], idx % model.width);
			}
		std::vector<double> corners;
		for (int y = 0; y < model.height; ++y)
			if (right[std::size_t(y)] >= 0)
				corners.insert(corners.end(), {double(left[std::size_t(y)]), double(y), double(left[std::size_t(y)]), y + 1.0,
				                               right[std::size_t(y)] + 1.0, double(y), right[std::size_t(y)] + 1.0, y + 1.0});
		extent.push_back(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>(corners.data(), Eigen::Index(corners.size() / 2), 2));
		// Head motion (D42) moves everything by up to its rotation about the centre plus its shift: the
		// anchors move out by as much.
		double headRoom = 0;
		if (o.modulator) {
			sizedForHead_ = true;
			headAngle_ = o.modulator->maxAngle();
			headShift_ = o.modulator->maxShift();
			sizedForBlinks_ = !o.modulator->blinks().empty();
			double radius = 0;
			for (Eigen::Index i = 0; i < model.meanShape.rows(); ++i) radius = std::max(radius, (model.meanShape.row(i) - centre_).norm());
			// (Curves turn about the point between the eyes: up to |eyeMid − centre| further out.)
			headRoom = o.modulator->maxAngle() * (radius + (eyeMid_ - centre_).norm()) * 1.5 + o.modulator->maxShift() * faceSize_ +
			           o.modulator->maxCurveShift() * eyeDistance_ + o.modulator->maxCurveScale() * (radius + (eyeMid_ - centre_).norm());
		}
		anchors_ = anchorRing(extent, kAnchorMargin * faceSize_ + headRoom, model.width, model.height);
	}
	{
		// D48: the scheme's action-unit templates, when an emotion or an event needs them.
		const bool auEvents = o.modulator && (!o.modulator->auEvents().empty() || !o.modulator->curves().aus.empty());
		if (o.emotionSource != EmotionSource::Corpus || auEvents) {
			Scheme scheme = model.scheme;
			scheme.eyes = parts.eyes;
			auTemplates_ = findAuTemplates(scheme);
			if (!auTemplates_ && (auEvents || o.emotionSource == EmotionSource::ActionUnits))
				throw Error("no action-unit templates for scheme " + scheme.name + " (models/au-templates/" + scheme.name +
				            ".tsv; make them from a corpus with the emotions with 'talkhead corpus au-templates')");
			if (auTemplates_) auFrame_ = eyeFrame(scheme, model.meanShape);
			if (auEvents)
				for (const AuEvent& e : o.modulator->auEvents()) {
					const int a = auTemplates_->find(e.au);
					if (a < 0) throw Error("the action-unit templates of scheme " + scheme.name + " have no " + e.au);
					auEventIndex_.push_back(a);
				}
			if (o.modulator)
				for (const ControlCurves::Au& c : o.modulator->curves().aus) {
					const int a = auTemplates_->find(c.au);
					if (a < 0) throw Error("the action-unit templates of scheme " + scheme.name + " have no " + c.au);
					auCurveIndex_.push_back(a);
				}
		}
	}
	const int k = model.pointCount();
	anchorsOut_ = anchors_;
	anchorsOut_.col(0) *= scaleX_;
	anchorsOut_.col(1) *= scaleY_;
	anchorsOutChroma_ = toChroma(anchorsOut_);
	const int cw = (model.width + 1) / 2, ch = (model.height + 1) / 2;
	meanSource_ = withAnchors(model.meanShape, anchors_, model.width, model.height);
	meanSourceChroma_ = withAnchors(toChroma(model.meanShape), toChroma(anchors_), cw, ch);
	mesh_ = delaunayTriangulation(meanSource_);
	movingMesh_.vertexCount = mesh_.vertexCount;
	for (const Triangle& t : mesh_.triangles)
		if (t[0] < k || t[1] < k || t[2] < k) movingMesh_.triangles.push_back(t);
	if (o.warpPath == WarpPath::Direct && !model.baseface.empty()) {
		baseY_.resize(std::size_t(model.width) * model.height);
		baseUV_.resize(std::size_t(cw) * ch * 2);
		rgbToYuv420(model.baseface.data.data(), std::size_t(model.width) * 3, model.width, model.height, o.yuvRange, baseY_.data(),
		            std::size_t(model.width), baseUV_.data(), baseUV_.data() + 1, std::size_t(cw) * 2, 2);
		// The background: the mean shape's frame, whose static triangles every frame shares.
		Points mean = model.meanShape;
		mean.col(0) *= scaleX_;
		mean.col(1) *= scaleY_;
		backgroundYuv_.resize(width_, height_);
		PiecewiseAffineWarp luma(mesh_, anchored(mean, false), width_, height_);
		luma.setSource(meanSource_);
		std::uint8_t* y[1] = {backgroundYuv_.y.data()};
		luma.applyPlanes(baseY_.data(), model.width, model.height, std::size_t(model.width), 1, y, std::size_t(width_));
		const int outCw = backgroundYuv_.chromaWidth(), outCh = backgroundYuv_.chromaHeight();
		PiecewiseAffineWarp chroma(mesh_, anchored(toChroma(mean), true), outCw, outCh);
		chroma.setSource(meanSourceChroma_);
		std::uint8_t* uv[2] = {backgroundYuv_.u.data(), backgroundYuv_.v.data()};
		chroma.applyPlanes(baseUV_.data(), cw, ch, std::size_t(cw) * 2, 2, uv, std::size_t(outCw));
	}
	if (o.modulator && !o.modulator->blinks().empty() && !model.baseface.empty()) {
		// D50: the corpus's closed-eyes image, in the mean frame, gives the shut lid where the model has one.
		Image8 closed;
		if (model.closedEyesIndex >= 0 && std::size_t(model.closedEyesIndex) < model.sampleCount()) {
			std::vector<Eigen::VectorXf> a(model.regions.size());
			for (std::size_t r = 0; r < model.regions.size(); ++r) {
				const RegionModel& reg = model.regions[r];
				if (reg.hasAppearanceCache()) {
					std::vector<std::uint8_t> bytes(std::size_t(reg.appearanceSize()));
					reg.readCachedAppearance(std::size_t(model.closedEyesIndex), bytes.data());
					a[r] = Eigen::Map<const Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>>(bytes.data(), Eigen::Index(bytes.size())).cast<float>();
				} else {
					Eigen::MatrixXf c(reg.pca.components(), 1);
					c.col(0) = sampleCoefficients(reg, std::size_t(model.closedEyesIndex));
					a[r] = synthesizeAppearances(reg, c).col(0);
				}
			}
			closed = toU8(compositeRegions(model, a));
		}
		for (const EyeSpec& e : eyes_) {
			eyePatches_.push_back(closedLid(model, closed.empty() ? model.baseface : closed, e, roiX0_, roiY0_, roiX1_, roiY1_, o.yuvRange));
			if (!closed.empty()) eyePatches_.push_back(closedLidFrom(model, closed, e, roiX0_, roiY0_, roiX1_, roiY1_, o.yuvRange));
		}
	}
}

Points Synthesizer::anchored(const Points& face, bool chroma) const {
	return chroma ? withAnchors(face, anchorsOutChroma_, (width_ + 1) / 2, (height_ + 1) / 2) : withAnchors(face, anchorsOut_, width_, height_);
}

const Image8& Synthesizer::backgroundRgb() const {
	std::call_once(backgroundRgbOnce_, [&] {
		Points mean = model_.meanShape;
		mean.col(0) *= scaleX_;
		mean.col(1) *= scaleY_;
		PiecewiseAffineWarp warp(mesh_, anchored(mean, false), width_, height_);
		warp.setSource(meanSource_);
		backgroundRgb_ = Image8(width_, height_, 3);
		warp.apply(model_.baseface, backgroundRgb_);
	});
	return backgroundRgb_;
}

namespace {
// The homorganic group (first phone) of a CDV, from phonetics/visemes.tsv.
std::string groupOf(const std::string& cdv) {
	for (const auto& v : visemeLabels())
		if (v.label == cdv) return v.group.empty() ? v.label : v.group.front();
	return cdv;
}
}  // namespace

bool Synthesizer::fromActionUnits(const Keypose& key) const {
	if (!auTemplates_ || o_.emotionSource == EmotionSource::Corpus) return false;
	const std::string& emotion = emotionOf(key).label();
	if (emotion == "neutral" || !defaultAuProfiles().count(emotion)) return false;
	if (o_.emotionSource == EmotionSource::ActionUnits) return true;
	for (const auto& s : model_.samples)
		if (s.emotion == emotion) return false;
	return true;
}

std::pair<long, long> Synthesizer::resolvePair(const Keypose& key) const {
	if (fromActionUnits(key)) return {resolve(key, "neutral"), -1};
	const long sample = resolve(key);
	// Intensity (D43): between the neutral keypose of the same CDV and context (0) and the emotion's (1).
	const double intensity = intensityOf(key);
	if (emotionOf(key).isNeutral() || intensity == 1.0) return {sample, -1};
	return {sample, resolve(key, "neutral")};
}

Emotion Synthesizer::emotionOf(const Keypose& key) const { return key.emotion.value_or(o_.emotion); }
double Synthesizer::intensityOf(const Keypose& key) const { return key.intensity.value_or(o_.intensity); }
std::string Synthesizer::indexKey(const Keypose& key) const {
	return key.cdv + "\t" + emotionOf(key).label() + "\t" + std::to_string(intensityOf(key)) + (key.sample >= 0 ? "\t#" + std::to_string(key.sample) : "");
}

long Synthesizer::resolve(const Keypose& key) const { return resolve(key, emotionOf(key).label()); }

long Synthesizer::resolve(const Keypose& key, const std::string& emotion) const {
	// Fallbacks (issue 5): the emotion's entry, then neutral for that CDV, then the group's other CDVs;
	// among several samples of one entry, the best phone context (FaceModel::findSample).
	const std::string& cdv = key.cdv;
	const auto* context = &key.context;
	if (key.sample >= 0 && std::size_t(key.sample) < model_.sampleCount() && model_.samples[std::size_t(key.sample)].emotion == emotion) return key.sample;
	long sample = model_.findSample(emotion, cdv, context);
	if (sample < 0) sample = model_.findSample("neutral", cdv, context);
	if (sample < 0)
		for (const auto& v : visemeLabels())
			if (sample < 0 && v.label != cdv && groupOf(v.label) == groupOf(cdv)) {
				sample = model_.findSample(emotion, v.label, context);
				if (sample < 0) sample = model_.findSample("neutral", v.label, context);
			}
	if (sample < 0) {
		// Last resort: the emotion's silence, then anything of the emotion, then the first sample.
		sample = model_.findSample(emotion, "sil");
		for (std::size_t i = 0; sample < 0 && i < model_.sampleCount(); ++i)
			if (model_.samples[i].emotion == emotion) sample = long(i);
		if (sample < 0) sample = 0;
	}
	return sample;
}

const KeyposeImage& Synthesizer::keypose(const std::string& cdv) {
	Keypose k{Ticks(0), cdv, 0, 0};
	k.context = {"", "", "", "", ""};  // no context: the corpus's first sample of the CDV
	prepare({k});
	return cached(k);
}

const KeyposeImage& Synthesizer::cached(const Keypose& key) const {
	std::lock_guard<std::mutex> lock(mutex_);
	auto it = index_.find(indexKey(key));
	if (it != index_.end()) {
		auto jt = it->second.find(key.context);
		if (jt != it->second.end()) return *jt->second;
	}
	throw std::logic_error("Synthesizer: keypose not prepared: " + key.cdv);
}

std::vector<std::string> Synthesizer::substitutions() const {
	std::lock_guard<std::mutex> lock(mutex_);
	return substitutions_;
}

std::vector<std::string> Synthesizer::substitutionsFor(const std::vector<Keypose>& keys) const {
	std::vector<std::string> out;
	for (const auto& k : keys) {
		const SampleInfo& s = model_.samples[std::size_t(resolve(k))];
		const std::string& emotion = emotionOf(k).label();
		const std::string line = emotion + " " + k.cdv + " -> " + s.emotion + " " + s.cdv;
		if ((s.emotion != emotion || s.cdv != k.cdv) && std::find(out.begin(), out.end(), line) == out.end()) out.push_back(line);
	}
	return out;
}

std::vector<Keypose> Synthesizer::keyposesBetween(const std::vector<Keypose>& keys, Ticks from, Ticks to, int margin) {
	if (keys.empty()) return {};
	std::size_t i0 = 0, i1 = 0;
	while (i0 + 1 < keys.size() && keys[i0 + 1].time <= from) ++i0;
	i1 = i0;
	while (i1 + 1 < keys.size() && keys[i1].time <= to) ++i1;
	i0 -= std::min(i0, std::size_t(margin));
	i1 = std::min(keys.size() - 1, i1 + std::size_t(margin));
	return std::vector<Keypose>(keys.begin() + long(i0), keys.begin() + long(i1) + 1);
}

KeyposeImage Synthesizer::makeKeypose(long sample, const Points& shape, const std::vector<const std::uint8_t*>& cached8,
                                      const std::vector<Eigen::VectorXf>& synthesized) const {
	KeyposeImage k;
	const SampleInfo& s = model_.samples[std::size_t(sample)];
	k.usedEmotion = s.emotion;
	k.usedCdv = s.cdv;
	k.shape = shape;
	const std::size_t nr = model_.regions.size();
	if (o_.warpPath == WarpPath::Keypose) {
		std::vector<Eigen::VectorXf> a(nr);
		for (std::size_t r = 0; r < nr; ++r) {
			if (cached8[r]) {
				a[r].resize(model_.regions[r].appearanceSize());
				for (Eigen::Index j = 0; j < a[r].size(); ++j) a[r](j) = cached8[r][j];
			} else {
				a[r] = synthesized[r];
			}
		}
		PiecewiseAffineWarp warp(mesh_, withAnchors(k.shape, anchors_, model_.width, model_.height), model_.width, model_.height);
		warp.setSource(meanSource_);
		k.image = Image8(model_.width, model_.height, 3);
		warp.apply(compositeRegions(model_, a), k.image);
		return k;
	}
	// Spec §5.3 in the face box only (the baseface elsewhere): regions pasted coarse → fine through their
	// soft masks, in float, then rounded to 8 bits.
	const int rw = roiX1_ - roiX0_, rh = roiY1_ - roiY0_, W = model_.width;
	thread_local std::vector<float> crop;  // reused: fresh pages cost more than the compositing here
	crop.resize(std::size_t(rw) * rh * 3);
	for (int y = 0; y < rh; ++y) {
		const std::uint8_t* b = model_.baseface.row(roiY0_ + y) + std::size_t(roiX0_) * 3;
		for (int i = 0; i < rw * 3; ++i) crop[std::size_t(y) * rw * 3 + std::size_t(i)] = b[i];
	}
	for (std::size_t r = 0; r < nr; ++r) {
		const RegionModel& reg = model_.regions[r];
		const std::size_t q = reg.pixels.size();
		for (std::size_t p = 0; p < q; ++p) {
			const int idx = reg.pixels[p], x = idx % W - roiX0_, y = idx / W - roiY0_;
			float* px = &crop[(std::size_t(y) * rw + std::size_t(x)) * 3];
			const float w = reg.alpha[p];
			for (std::size_t c = 0; c < 3; ++c) {
				const float a = cached8[r] ? float(cached8[r][c * q + p]) : synthesized[r](Eigen::Index(c * q + p));
				px[c] = w * a + (1 - w) * px[c];
			}
		}
	}
	k.rgb.resize(crop.size());
	for (std::size_t i = 0; i < crop.size(); ++i) {
		const float v = crop[i] + 0.5f;
		k.rgb[i] = std::uint8_t(v <= 0.f ? 0.f : (v >= 255.f ? 255.f : v));
	}
	const int cw = (rw + 1) / 2, ch = (rh + 1) / 2;
	k.y.resize(std::size_t(rw) * rh);
	k.uv.resize(std::size_t(cw) * ch * 2);
	if (rw > 0 && rh > 0)
		rgbToYuv420(k.rgb.data(), std::size_t(rw) * 3, rw, rh, o_.yuvRange, k.y.data(), std::size_t(rw), k.uv.data(), k.uv.data() + 1,
		            std::size_t(cw) * 2, 2);
	return k;
}

void Synthesizer::prepare(const std::vector<Keypose>& keys) {
	// The (CDV, context) pairs not seen yet, their (sample, neutral sample) pairs, the pairs without an
	// image yet, and the samples those need.
	using Pair = std::pair<long, long>;
	std::vector<std::pair<const Keypose*, ImageKey>> fresh;
	std::vector<ImageKey> pairs;
	std::vector<long> samples;
	{
		std::lock_guard<std::mutex> lock(mutex_);
		for (const auto& k : keys) {
			auto it = index_.find(indexKey(k));
			if (it != index_.end() && it->second.count(k.context)) continue;
			if (std::any_of(fresh.begin(), fresh.end(), [&](const auto& f) { return indexKey(*f.first) == indexKey(k) && f.first->context == k.context; }))
				continue;
			const Pair pair = resolvePair(k);
			const bool au = fromActionUnits(k);
			const ImageKey key{pair.first, pair.second, pair.second < 0 && !au ? 1.0 : intensityOf(k), au ? emotionOf(k).label() : std::string()};
			fresh.push_back({&k, key});
			if (images_.count(key) || std::find(pairs.begin(), pairs.end(), key) != pairs.end()) continue;
			pairs.push_back(key);
			for (long sample : {pair.first, pair.second})
				if (sample >= 0 && std::find(samples.begin(), samples.end(), sample) == samples.end()) samples.push_back(sample);
		}
	}
	if (fresh.empty()) return;
	// Appearances: each sample's 8-bit reconstruction from the model's cache (read from disk on demand),
	// or, for a model without one, one GEMM per region for all the keyposes (the basis is read once).
	std::vector<Eigen::MatrixXf> synthesized(model_.regions.size());
	for (std::size_t r = 0; r < model_.regions.size(); ++r) {
		const RegionModel& reg = model_.regions[r];
		if (reg.hasAppearanceCache()) continue;
		Eigen::MatrixXf c(reg.pca.components(), Eigen::Index(samples.size()));
		for (std::size_t j = 0; j < samples.size(); ++j) c.col(Eigen::Index(j)) = sampleCoefficients(reg, std::size_t(samples[j]));
		synthesized[r] = synthesizeAppearances(reg, c);
	}
	auto column = [&](long sample) { return Eigen::Index(std::find(samples.begin(), samples.end(), sample) - samples.begin()); };
	std::vector<std::unique_ptr<KeyposeImage>> made(pairs.size());
	parallelFor(pairs.size(), 0, [&](std::size_t j) {
		const std::size_t nr = model_.regions.size();
		auto load = [&](long sample, std::vector<std::vector<std::uint8_t>>& bytes, std::vector<const std::uint8_t*>& cached8,
		                std::vector<Eigen::VectorXf>& synth) {
			bytes.resize(nr), cached8.assign(nr, nullptr), synth.resize(nr);
			for (std::size_t r = 0; r < nr; ++r) {
				const RegionModel& reg = model_.regions[r];
				if (reg.hasAppearanceCache()) {
					bytes[r].resize(std::size_t(reg.appearanceSize()));
					reg.readCachedAppearance(std::size_t(sample), bytes[r].data());
					cached8[r] = bytes[r].data();
				} else {
					synth[r] = synthesized[r].col(column(sample));
				}
			}
		};
		std::vector<std::vector<std::uint8_t>> bytes, baseBytes;
		std::vector<const std::uint8_t*> cached8, baseCached8;
		std::vector<Eigen::VectorXf> synth, baseSynth;
		const auto& [sample, base, intensity, auEmotion] = pairs[j];
		load(sample, bytes, cached8, synth);
		if (!auEmotion.empty()) {  // D48: the neutral sample, its shape moved by the emotion's action units
			Points shape = model_.alignedShapes[std::size_t(sample)];
			applyActionUnits(shape, *auTemplates_, profileWeights(*auTemplates_, defaultAuProfiles().at(auEmotion), intensity), auFrame_);
			made[j] = std::make_unique<KeyposeImage>(makeKeypose(sample, shape, cached8, synth));
			made[j]->usedEmotion = auEmotion + " (action units)";
			return;
		}
		if (base < 0) {
			made[j] = std::make_unique<KeyposeImage>(makeKeypose(sample, model_.alignedShapes[std::size_t(sample)], cached8, synth));
			return;
		}
		// D43: shape and appearance of neutral + intensity × (emotion − neutral), per region.
		load(base, baseBytes, baseCached8, baseSynth);
		std::vector<Eigen::VectorXf> mixed(nr);
		const float t = float(intensity);
		for (std::size_t r = 0; r < nr; ++r) {
			const Eigen::Index n = model_.regions[r].appearanceSize();
			auto value = [&](const std::vector<const std::uint8_t*>& c8, const std::vector<Eigen::VectorXf>& sy, Eigen::Index i) {
				return c8[r] ? float(c8[r][i]) : sy[r](i);
			};
			mixed[r].resize(n);
			for (Eigen::Index i = 0; i < n; ++i) {
				const float b = value(baseCached8, baseSynth, i);
				mixed[r](i) = b + t * (value(cached8, synth, i) - b);
			}
		}
		const Points& a = model_.alignedShapes[std::size_t(sample)];
		const Points& b = model_.alignedShapes[std::size_t(base)];
		const std::vector<const std::uint8_t*> none(nr, nullptr);
		made[j] = std::make_unique<KeyposeImage>(makeKeypose(sample, b + intensity * (a - b), none, mixed));
	});
	std::lock_guard<std::mutex> lock(mutex_);
	for (std::size_t j = 0; j < pairs.size(); ++j) images_.emplace(pairs[j], std::move(made[j]));
	for (const auto& [k, key] : fresh) {
		const KeyposeImage* image = images_.at(key).get();
		index_[indexKey(*k)][k->context] = image;
		const std::string& emotion = emotionOf(*k).label();
		const std::string line = emotion + " " + k->cdv + " -> " + image->usedEmotion + " " + image->usedCdv;
		const bool asked = o_.emotionSource == EmotionSource::ActionUnits && image->usedEmotion == emotion + " (action units)";
		if (!asked && (image->usedEmotion != emotion || image->usedCdv != k->cdv) &&
		    std::find(substitutions_.begin(), substitutions_.end(), line) == substitutions_.end())
			substitutions_.push_back(line);
	}
}

Points Synthesizer::trajectory(const Points& s, const Points& t, double u, Trajectory kind) {
	u = std::clamp(u, 0.0, 1.0);
	// Eq. 5.5 with zero tangents: P(t) = S + (T − S)(3t² − 2t³); linear: S + (T − S)t. (Monotone with no
	// neighbours to look at is the zero-tangent curve.)
	const double h = kind == Trajectory::Linear ? u : u * u * (3 - 2 * u);
	return s + (t - s) * h;
}

Points Synthesizer::monotoneTrajectory(const std::array<const Points*, 4>& p, const std::array<double, 4>& k, double u) {
	u = std::clamp(u, 0.0, 1.0);
	const Points &s = *p[1], &t = *p[2];
	const double h = k[2] - k[1];
	if (!(h > 0)) return u < 1 ? s : t;
	// Fritsch–Carlson (the weighted harmonic mean of the two chords' slopes, as PCHIP): zero at a turning
	// point or where a chord is flat, and never more than three times a chord's slope, so no overshoot.
	auto tangent = [](const Points* a, double ka, const Points& b, double kb, const Points* c, double kc, Eigen::Index r, int col) {
		if (!a || !c || !(kb - ka > 0) || !(kc - kb > 0)) return 0.0;
		const double h0 = kb - ka, h1 = kc - kb;
		const double d0 = (b(r, col) - (*a)(r, col)) / h0, d1 = ((*c)(r, col) - b(r, col)) / h1;
		if (!(d0 * d1 > 0)) return 0.0;
		const double w1 = 2 * h1 + h0, w2 = h1 + 2 * h0;
		return (w1 + w2) / (w1 / d0 + w2 / d1);
	};
	const double u2 = u * u, u3 = u2 * u;
	const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
	Points out(s.rows(), s.cols());
	for (Eigen::Index r = 0; r < s.rows(); ++r)
		for (int c = 0; c < int(s.cols()); ++c) {
			const double ms = tangent(p[0], k[0], s, k[1], &t, k[2], r, c), mt = tangent(&s, k[1], t, k[2], p[3], k[3], r, c);
			out(r, c) = h00 * s(r, c) + h10 * h * ms + h01 * t(r, c) + h11 * h * mt;
		}
	return out;
}

Synthesizer::Between Synthesizer::locate(Ticks tau, const std::vector<Keypose>& keys, Points& points) const {
	if (keys.empty()) throw std::logic_error("renderFrame: no keyposes");
	// The bracketing keyposes; before the first and after the last the face holds.
	std::size_t i = 0;
	while (i + 1 < keys.size() && keys[i + 1].time <= tau) ++i;
	Between f;
	f.src = &cached(keys[i]);
	const bool hold = tau <= keys.front().time || i + 1 >= keys.size();
	f.dst = hold ? f.src : &cached(keys[i + 1]);
	f.u = hold ? 0 : double((tau - keys[i].time).count()) / double((keys[i + 1].time - keys[i].time).count());
	f.w = o_.dissolve == Trajectory::Hermite ? f.u * f.u * (3 - 2 * f.u) : f.u;
	f.w256 = int(std::lround(std::clamp(f.w, 0.0, 1.0) * 256));
	if (o_.trajectory == Trajectory::Monotone && !hold) {
		const Points* before = i > 0 ? &cached(keys[i - 1]).shape : nullptr;
		const Points* after = i + 2 < keys.size() ? &cached(keys[i + 2]).shape : nullptr;
		auto seconds = [&](std::size_t j) { return toSeconds(keys[j].time); };
		points = monotoneTrajectory({before, &f.src->shape, &f.dst->shape, after},
		                            {before ? seconds(i - 1) : 0.0, seconds(i), seconds(i + 1), after ? seconds(i + 2) : 0.0}, f.u);
	} else {
		points = trajectory(f.src->shape, f.dst->shape, f.u, o_.trajectory);
	}
	if (stabilise_) {  // D55: a tracked head: the pose is the driver's; the exemplars' own (up to ±1.7° on franck) is removed
		const Similarity t = alignSimilarity(points, model_.meanShape, stabiliseWeights_);
		points = t.apply(points);
	}
	if (o_.modulator) {  // D42: lids, then the head, in model pixels
		f.closure = eyes_.empty() ? 0.0 : o_.modulator->eyeClosure(tau);
		if (f.closure > 0) closeEyes(points, f.closure);
		// Brows (D46): raised 10 % of the eye distance, all along; a frown lowers them 6 % and draws the
		// inner ends 5 % toward the midline, fading to half the lowering and none of the pull at the outer end.
		const auto [raise, frown] = o_.modulator->brows(tau);
		if (raise > 0 || frown > 0)
			for (const BrowSpec& b : brows_)
				for (std::size_t k = 0; k < b.points.size(); ++k) {
					const double inner = 1 - double(k) / double(b.points.size() - 1);
					const int i = b.points[k];
					const double toward = points(i, 0) < centre_(0) ? 1.0 : -1.0;
					points(i, 1) += eyeDistance_ * (-0.10 * raise + 0.06 * frown * (0.5 + 0.5 * inner));
					points(i, 0) += eyeDistance_ * 0.05 * frown * inner * toward;
				}
		if (!auEventIndex_.empty()) {  // D48: action units from a control track
			std::vector<AuWeight> w;
			const auto& all = o_.modulator->auEvents();
			for (const auto& [e, weight] : o_.modulator->actionUnits(tau)) w.push_back({auEventIndex_[std::size_t(e - all.data())], weight, e->side});
			applyActionUnits(points, *auTemplates_, w, auFrame_);
		}
		if (!auCurveIndex_.empty()) {  // D55: action units from a tracked video
			std::vector<AuWeight> w;
			const auto& curves = o_.modulator->curves().aus;
			for (const auto& [k, weight] : o_.modulator->curveActionUnits(tau)) w.push_back({auCurveIndex_[k], weight, curves[k].side});
			applyActionUnits(points, *auTemplates_, w, auFrame_);
		}
		const HeadMotion h = o_.modulator->head(tau);
		if (h.angle != 0 || h.dx != 0 || h.dy != 0) {
			const double c = std::cos(h.angle), s = std::sin(h.angle);
			for (Eigen::Index i = 0; i < points.rows(); ++i) {
				const double x = points(i, 0) - centre_(0), y = points(i, 1) - centre_(1);
				points(i, 0) = centre_(0) + c * x - s * y + h.dx * faceSize_;
				points(i, 1) = centre_(1) + s * x + c * y + h.dy * faceSize_;
			}
		}
		if (h.roll != 0 || h.x != 0 || h.y != 0 || h.scale != 1) {  // D55: a tracked head, about the point between the eyes
			const double c = std::cos(h.roll) * h.scale, s = std::sin(h.roll) * h.scale;
			for (Eigen::Index i = 0; i < points.rows(); ++i) {
				const double x = points(i, 0) - eyeMid_(0), y = points(i, 1) - eyeMid_(1);
				points(i, 0) = eyeMid_(0) + c * x - s * y + h.x * eyeDistance_;
				points(i, 1) = eyeMid_(1) + s * x + c * y + h.y * eyeDistance_;
			}
		}
	}
	points.col(0) *= scaleX_;
	points.col(1) *= scaleY_;
	return f;
}

void Synthesizer::setModulator(std::shared_ptr<const ShapeModulator> m) {
	if (m) {
		if (!sizedForHead_ || m->maxAngle() > headAngle_ + 1e-12 || m->maxShift() > headShift_ + 1e-12)
			throw std::logic_error("Synthesizer::setModulator: the new plan moves the head further than the face box allows");
		if (!m->blinks().empty() && !sizedForBlinks_) throw std::logic_error("Synthesizer::setModulator: blinks, but the synthesizer was made without");
		if (!m->auEvents().empty() || !m->curves().empty())
			throw std::logic_error("Synthesizer::setModulator: action-unit events and curves are fixed at construction");
	}
	o_.modulator = std::move(m);
}

void Synthesizer::closeEyes(Points& points, double closure) const {
	// Each upper-lid point comes down to 95 % of the way to the lower lid below it.
	for (const EyeSpec& e : eyes_) {
		const auto lower = lidLine(points, e, false);
		for (int i : e.upper) {
			const double yl = polylineY(lower, points(i, 0));
			if (std::isnan(yl)) continue;
			const double target = points(i, 1) + 0.95 * (yl - points(i, 1));
			points(i, 1) += closure * (target - points(i, 1));
		}
	}
}

void Synthesizer::drawClosedLids(std::uint8_t* meanY, std::uint8_t* meanUV, std::uint8_t* meanRgb, double closure) const {
	// The closed lid dissolves in faster than the lids close, so no half-open iris is squashed into the slit.
	const int W = model_.width, cw = (W + 1) / 2;
	for (const ClosedLidPatch& p : eyePatches_) {
		const double s = p.from > 0 ? std::clamp((closure - p.from) / (1 - p.from), 0.0, 1.0) : 0.0;
		const float w = float(p.from > 0 ? s * s * (3 - 2 * s) : std::min(1.0, 1.6 * closure));
		for (int y = 0; y < p.h; ++y)
			for (int x = 0; x < p.w; ++x) {
				const std::size_t i = std::size_t(y) * std::size_t(p.w) + std::size_t(x);
				const float a = p.alpha[i] * w;
				if (a <= 0) continue;
				const std::size_t o = std::size_t(p.y0 + y) * std::size_t(W) + std::size_t(p.x0 + x);
				if (meanY) meanY[o] = std::uint8_t(float(meanY[o]) + a * (float(p.y[i]) - float(meanY[o])) + 0.5f);
				if (meanRgb)
					for (int c = 0; c < 3; ++c) {
						std::uint8_t& v = meanRgb[3 * o + std::size_t(c)];
						v = std::uint8_t(float(v) + a * (float(p.rgb[3 * i + std::size_t(c)]) - float(v)) + 0.5f);
					}
			}
		if (!meanUV) continue;
		for (int y = 0; y < p.h / 2; ++y)
			for (int x = 0; x < p.w / 2; ++x) {
				const std::size_t i = std::size_t(y) * std::size_t(p.w / 2) + std::size_t(x);
				const float a = p.alphaC[i] * w;
				if (a <= 0) continue;
				const std::size_t o = (std::size_t(p.y0 / 2 + y) * std::size_t(cw) + std::size_t(p.x0 / 2 + x)) * 2;
				for (int c = 0; c < 2; ++c)
					meanUV[o + std::size_t(c)] = std::uint8_t(float(meanUV[o + std::size_t(c)]) + a * (float(p.uv[2 * i + std::size_t(c)]) - float(meanUV[o + std::size_t(c)])) + 0.5f);
			}
	}
}

namespace {
// Points a workspace's warp at a new destination shape (made on first use).
void placeWarp(std::unique_ptr<PiecewiseAffineWarp>& warp, const TriangleMesh& mesh, const Points& destination, int width, int height) {
	if (!warp) warp = std::make_unique<PiecewiseAffineWarp>(mesh, destination, width, height);
	else warp->setDestination(destination);
}
}  // namespace

void Synthesizer::renderFrame(Ticks tau, const std::vector<Keypose>& keys, Workspace& ws, Image8& out, Points& points,
                              bool outHoldsFrame) const {
	const Between f = locate(tau, keys, points);
	if (out.width != width_ || out.height != height_ || out.channels != 3) out = Image8(width_, height_, 3), outHoldsFrame = false;
	const double t0 = threadCpuSeconds();
	// The static background, then the moving triangles over it (D41).
	if (!outHoldsFrame) {
		const Image8& background = backgroundRgb();
		std::memcpy(out.data.data(), background.data.data(), out.data.size());
	}
	placeWarp(ws.warp, movingMesh_, anchored(points, false), width_, height_);
	if (o_.warpPath == WarpPath::Keypose) {
		auto source = [&](const KeyposeImage* k) { return withAnchors(k->shape, anchors_, model_.width, model_.height); };
		if (f.u <= 0) {
			ws.warp->setSource(source(f.src));
			ws.warp->apply(f.src->image, out);
		} else {  // F = K_f (1 − t) + K_b t, K_f = source warped S → P(t), K_b = target warped T → P(t), in one pass
			ws.warp->dissolve(f.src->image, source(f.src), f.dst->image, source(f.dst), f.w, out);
		}
		if (f.closure > 0 && !eyePatches_.empty()) {
			// The shut lids live in the mean frame, which this order never builds: during a blink, the frame
			// goes back to the mean shape, gets its lids there, and is warped forward again (blink frames only).
			PiecewiseAffineWarp back(mesh_, meanSource_, model_.width, model_.height);
			back.setSource(anchored(points, false));
			if (ws.meanRgb.width != model_.width || ws.meanRgb.height != model_.height) ws.meanRgb = Image8(model_.width, model_.height, 3);
			back.apply(out, ws.meanRgb);  // the direct path's buffer, unused by this order
			drawClosedLids(nullptr, nullptr, ws.meanRgb.data.data(), f.closure);
			ws.warp->setSource(meanSource_);
			ws.warp->apply(ws.meanRgb, out);
		}
		ws.warpSeconds += threadCpuSeconds() - t0;
		return;
	}
	// Direct: dissolve the two composited appearances in the mean-shape frame, then one warp s̄ → P(t).
	if (ws.meanRgb.empty()) ws.meanRgb = model_.baseface;
	const int rw = roiX1_ - roiX0_;
	for (int y = roiY0_; y < roiY1_; ++y) {
		const std::size_t at = std::size_t(y - roiY0_) * rw * 3;
		blendRow(f.src->rgb.data() + at, f.dst->rgb.data() + at, f.w256, ws.meanRgb.row(y) + std::size_t(roiX0_) * 3, std::size_t(rw) * 3);
	}
	if (f.closure > 0) drawClosedLids(nullptr, nullptr, ws.meanRgb.data.data(), f.closure);
	ws.warp->setSource(meanSource_);
	ws.warp->apply(ws.meanRgb, out);
	ws.warpSeconds += threadCpuSeconds() - t0;
}

void Synthesizer::renderFrameYuv(Ticks tau, const std::vector<Keypose>& keys, Workspace& ws, YuvImage& out, Points& points,
                                 bool outHoldsFrame) const {
	if (o_.warpPath == WarpPath::Keypose) {
		renderFrame(tau, keys, ws, ws.rgb, points);
		rgbToYuv420(ws.rgb, out, o_.yuvRange);
		return;
	}
	const Between f = locate(tau, keys, points);
	if (out.width != width_ || out.height != height_) outHoldsFrame = false;
	out.resize(width_, height_);
	const double t0 = threadCpuSeconds();
	const int W = model_.width, H = model_.height, cw = (W + 1) / 2, ch = (H + 1) / 2;
	const int outCw = out.chromaWidth(), outCh = out.chromaHeight();
	// The static background, then the moving triangles over it (D41).
	if (!outHoldsFrame) {
		std::memcpy(out.y.data(), backgroundYuv_.y.data(), out.y.size());
		std::memcpy(out.u.data(), backgroundYuv_.u.data(), out.u.size());
		std::memcpy(out.v.data(), backgroundYuv_.v.data(), out.v.size());
	}
	placeWarp(ws.warp, movingMesh_, anchored(points, false), width_, height_);
	placeWarp(ws.chromaWarp, movingMesh_, anchored(toChroma(points), true), outCw, outCh);
	if (ws.meanY.empty()) {
		resizePrefaulted(ws.meanY, baseY_.size());
		resizePrefaulted(ws.meanUV, baseUV_.size());
		std::memcpy(ws.meanY.data(), baseY_.data(), baseY_.size());
		std::memcpy(ws.meanUV.data(), baseUV_.data(), baseUV_.size());
	}
	// Eq. 5.4 in the mean-shape frame (luma and chroma), then one warp of each plane s̄ → P(t).
	const int rw = roiX1_ - roiX0_, rcw = (rw + 1) / 2;
	for (int y = roiY0_; y < roiY1_; ++y) {
		const std::size_t at = std::size_t(y - roiY0_) * rw;
		blendRow(f.src->y.data() + at, f.dst->y.data() + at, f.w256, ws.meanY.data() + std::size_t(y) * W + roiX0_, std::size_t(rw));
	}
	for (int y = roiY0_ / 2; y < (roiY1_ + 1) / 2; ++y) {
		const std::size_t at = std::size_t(y - roiY0_ / 2) * rcw * 2;
		blendRow(f.src->uv.data() + at, f.dst->uv.data() + at, f.w256, ws.meanUV.data() + (std::size_t(y) * cw + std::size_t(roiX0_ / 2)) * 2,
		         std::size_t(rcw) * 2);
	}
	if (f.closure > 0) drawClosedLids(ws.meanY.data(), ws.meanUV.data(), nullptr, f.closure);
	ws.warp->setSource(meanSource_);
	std::uint8_t* luma[1] = {out.y.data()};
	ws.warp->applyPlanes(ws.meanY.data(), W, H, std::size_t(W), 1, luma, std::size_t(width_));
	ws.chromaWarp->setSource(meanSourceChroma_);
	std::uint8_t* chroma[2] = {out.u.data(), out.v.data()};
	ws.chromaWarp->applyPlanes(ws.meanUV.data(), cw, ch, std::size_t(cw) * 2, 2, chroma, std::size_t(outCw));
	ws.warpSeconds += threadCpuSeconds() - t0;
}

}  // namespace talkhead
