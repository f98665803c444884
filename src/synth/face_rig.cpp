// SPDX-License-Identifier: GPL-3.0-or-later
// The face rig (issue 30: the synthesizer split in three): what frames are drawn on, made once per model,
// output size and options — the face box, the scheme's eyes and brows, the static anchors and meshes
// (D41), the background, the baseface in YUV, the action-unit templates (D48) and the closed lids (D42, D50).
#include "synth/face_rig.h"

#include <algorithm>
#include <cmath>

#include "base/error.h"
#include "geometry/scheme.h"
#include "warp/piecewise_affine.h"
#include "warp/prefilter.h"

namespace talkhead {

namespace {
// D41: the anchors' distance outside everything that moves, as a fraction of the mean shape's larger side.
constexpr double kAnchorMargin = 0.15;
}  // namespace

Points withAnchors(const Points& face, const Points& anchors, int width, int height) {
	Points p(face.rows() + anchors.rows(), 2);
	p << face, anchors;
	return withFrameBorder(p, width, height);
}

Points toChroma(const Points& p) { return (p.array() - 0.5) * 0.5; }

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


namespace {

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


ClosedLidPatch closedLid(const FaceModel& m, const Image8& b, const EyeSpec& e, int rx0, int ry0, int rx1, int ry1, YuvRange range, double lash) {
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
			const double shade = (1 - 0.06 * t) * (1 - lash * std::exp(-(d * d) / (2 * sigma * sigma)) * std::clamp(side, 0.0, 1.0));
			for (int c = 0; c < 3; ++c)
				patch.rgb[3 * i + std::size_t(c)] = std::uint8_t(std::clamp(smooth[3 * j + std::size_t(c)] * shade + 0.5, 0.0, 255.0));
		}
	}
	finishPatch(patch, range);
	return patch;
}
}  // namespace

FaceRig::FaceRig(const Face& face, const SynthOptions& o) : model_(face.model()) {
	placeFace(model_, o);
	placeAnchors(model_, o);
	loadActionUnits(face, o);
	makeMeshes(model_, o);
	makeClosedLids(face, o);
}

// The output size, the face box, the mean shape's size and centre, the eyes and brows, a tracked head's pivot.
void FaceRig::placeFace(const FaceModel& model, const SynthOptions& o) {
	width = o.width > 0 ? o.width : model.width;
	height = o.height > 0 ? o.height : model.height;
	scaleX = double(width) / model.width;
	scaleY = double(height) / model.height;
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
		roiX0 = std::max(0, x0 - 1) & ~1;
		roiY0 = std::max(0, y0 - 1) & ~1;
		roiX1 = std::min(model.width, (x1 + 2) & ~1);
		roiY1 = std::min(model.height, (y1 + 2) & ~1);
	}
	{
		const Eigen::RowVector2d lo = model.meanShape.colwise().minCoeff(), hi = model.meanShape.colwise().maxCoeff();
		faceSize = std::max(1.0, (hi - lo).maxCoeff());
		centre = model.meanShape.colwise().mean();
	}
	eyes = model.scheme.eyes;  // a loaded model's from its shipped scheme (completeSchemeParts)
	brows = model.scheme.brows;
	if (eyes.size() >= 2) {
		auto centre = [&](const EyeSpec& e) { return (model.meanShape.row(e.corner0) + model.meanShape.row(e.corner1)) / 2; };
		eyeDistance = (centre(eyes[0]) - centre(eyes[1])).norm();
	}
	if (!(eyeDistance > 0)) eyeDistance = 0.3 * faceSize;
	eyeMid = centre;
	if (o.modulator && o.modulator->curves().hasHead() && eyes.size() >= 2) {
		stabilise = true;
		stabiliseWeights = Eigen::VectorXd::Zero(model.pointCount());
		for (const EyeSpec& e : eyes) stabiliseWeights(e.corner0) = stabiliseWeights(e.corner1) = 1;
		if (model.scheme.name == "ibug-68" && model.pointCount() == 68) {  // and the nose, as talkhead track registers heads
			stabiliseWeights(27) = 0.5, stabiliseWeights(30) = 1;
			for (int i : {31, 33, 35}) stabiliseWeights(i) = 0.5;
		}
	}
	if (eyes.size() >= 2)
		eyeMid = (model.meanShape.row(eyes[0].corner0) + model.meanShape.row(eyes[0].corner1) + model.meanShape.row(eyes[1].corner0) +
		           model.meanShape.row(eyes[1].corner1)) / 4;
}

// D41: the static anchors, outside everything that moves (head motion included).
void FaceRig::placeAnchors(const FaceModel& model, const SynthOptions& o) {
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
			sizedForHead = true;
			headAngle = o.modulator->maxAngle();
			headShift = o.modulator->maxShift();
			sizedForBlinks = !o.modulator->blinks().empty();
			double radius = 0;
			for (Eigen::Index i = 0; i < model.meanShape.rows(); ++i) radius = std::max(radius, (model.meanShape.row(i) - centre).norm());
			// (Curves turn about the point between the eyes: up to |eyeMid − centre| further out.)
			headRoom = o.modulator->maxAngle() * (radius + (eyeMid - centre).norm()) * 1.5 + o.modulator->maxShift() * faceSize +
			           o.modulator->maxCurveShift() * eyeDistance + o.modulator->maxCurveScale() * (radius + (eyeMid - centre).norm());
		}
		anchors = anchorRing(extent, kAnchorMargin * faceSize + headRoom, model.width, model.height);
	}
}

// D48: the action-unit templates and the modulator's events and curves in them.
void FaceRig::loadActionUnits(const Face& face, const SynthOptions& o) {
	{
		// D48: the scheme's action-unit templates, when an emotion or an event needs them.
		const bool auEvents = o.modulator && (!o.modulator->auEvents().empty() || !o.modulator->curves().aus.empty());
		if (o.emotionSource != EmotionSource::Corpus || auEvents) {
			const FaceModel& model = face.model();
			const Scheme& scheme = model.scheme;
			auTemplates = face.auTemplates();
			if (!auTemplates && (auEvents || o.emotionSource == EmotionSource::ActionUnits))
				throw Error("no action-unit templates for scheme " + scheme.name + " (models/au-templates/" + scheme.name +
				            ".tsv; make them from a corpus with the emotions with 'talkhead corpus au-templates')");
			if (auTemplates) auFrame = eyeFrame(scheme, model.meanShape);
			if (auEvents)
				for (const AuEvent& e : o.modulator->auEvents()) {
					const int a = auTemplates->find(e.au);
					if (a < 0) throw Error("the action-unit templates of scheme " + scheme.name + " have no " + e.au);
					auEventIndex.push_back(a);
				}
			if (o.modulator)
				for (const ControlCurves::Au& c : o.modulator->curves().aus) {
					const int a = auTemplates->find(c.au);
					if (a < 0) throw Error("the action-unit templates of scheme " + scheme.name + " have no " + c.au);
					auCurveIndex.push_back(a);
				}
			if (auEvents && o.auAppearance) loadAuSkin(face, o);
		}
	}
}

// D61: the skin's maps of the AUs the events and curves name, mapped once into the face box.
void FaceRig::loadAuSkin(const Face& face, const SynthOptions& o) {
	std::vector<std::string> aus;
	auto add = [&](const std::string& au) {
		if (std::find(aus.begin(), aus.end(), au) == aus.end()) aus.push_back(au);
	};
	for (const AuEvent& e : o.modulator->auEvents()) add(e.au);
	for (const ControlCurves::Au& c : o.modulator->curves().aus) add(c.au);
	std::optional<MappedAuAppearance> skin = face.auSkin(aus, roiX0, roiY0, roiX1 - roiX0, roiY1 - roiY0, o.auOwnSkin);
	if (!skin) return;
	auSkin = std::make_unique<MappedAuAppearance>(std::move(*skin));
	for (const AuEvent& e : o.modulator->auEvents()) auEventSkin.push_back(auSkin->find(e.au));
	for (const ControlCurves::Au& c : o.modulator->curves().aus) auCurveSkin.push_back(auSkin->find(c.au));
}

// The meshes over the mean shape and the anchors, the baseface in YUV and the static background.
void FaceRig::makeMeshes(const FaceModel& model, const SynthOptions& o) {
	const int k = model.pointCount();
	anchorsOut = anchors;
	anchorsOut.col(0) *= scaleX;
	anchorsOut.col(1) *= scaleY;
	anchorsOutChroma = toChroma(anchorsOut);
	const int cw = (model.width + 1) / 2, ch = (model.height + 1) / 2;
	meanSource = withAnchors(model.meanShape, anchors, model.width, model.height);
	meanSourceChroma = withAnchors(toChroma(model.meanShape), toChroma(anchors), cw, ch);
	mesh = delaunayTriangulation(meanSource);
	movingMesh.vertexCount = mesh.vertexCount;
	for (const Triangle& t : mesh.triangles)
		if (t[0] < k || t[1] < k || t[2] < k) movingMesh.triangles.push_back(t);
	if (o.warpPath == WarpPath::Direct && o.resampling == Resampling::Sharp) prefilter = float(prefilterStrength(std::min(scaleX, scaleY)));
	makePrefilterMask(model, o);
	baseface = prefilteredForBilinear(model.baseface, prefilter, prefilterMask.empty() ? nullptr : &prefilterMask);
	if (o.warpPath == WarpPath::Direct && !model.baseface.empty()) {
		baseY.resize(std::size_t(model.width) * model.height);
		baseUV.resize(std::size_t(cw) * ch * 2);
		rgbToYuv420(baseface.data.data(), std::size_t(model.width) * 3, model.width, model.height, o.yuvRange, baseY.data(),
		            std::size_t(model.width), baseUV.data(), baseUV.data() + 1, std::size_t(cw) * 2, 2);
		// The background: the mean shape's frame, whose static triangles every frame shares.
		Points mean = model.meanShape;
		mean.col(0) *= scaleX;
		mean.col(1) *= scaleY;
		backgroundYuv.resize(width, height);
		PiecewiseAffineWarp luma(mesh, anchored(mean, false), width, height);
		luma.setSource(meanSource);
		std::uint8_t* y[1] = {backgroundYuv.y.data()};
		luma.applyPlanes(baseY.data(), model.width, model.height, std::size_t(model.width), 1, y, std::size_t(width));
		const int outCw = backgroundYuv.chromaWidth(), outCh = backgroundYuv.chromaHeight();
		PiecewiseAffineWarp chroma(mesh, anchored(toChroma(mean), true), outCw, outCh);
		chroma.setSource(meanSourceChroma);
		std::uint8_t* uv[2] = {backgroundYuv.u.data(), backgroundYuv.v.data()};
		chroma.applyPlanes(baseUV.data(), cw, ch, std::size_t(cw) * 2, 2, uv, std::size_t(outCw));
	}
}

// D84: enlarged or reduced, every pixel of the face and of the background is resampled at a phase that
// runs across it, so the prefilter applies everywhere. At the model's own size (within 2 px over the frame)
// the static background is copied and a face point moves only as far as the samples move it: a vertex
// that moves half a pixel or more (the most any sample's aligned point is from s̄'s, or any head motion)
// takes the whole prefilter, a still one none, the anchors and the frame border none, interpolated over
// the mesh between them.
void FaceRig::makePrefilterMask(const FaceModel& model, const SynthOptions& o) {
	prefilterMask.clear();
	if (prefilter == 0 || model.baseface.empty()) return;
	const double span = double(std::max(model.width, model.height));
	if (std::abs(scaleX - 1) * span >= 2 || std::abs(scaleY - 1) * span >= 2) return;
	const int k = model.pointCount();
	const bool headMoves = o.modulator && (o.modulator->maxAngle() > 0 || o.modulator->maxShift() > 0);
	Points value = Points::Zero(meanSource.rows(), 2);
	for (int i = 0; i < k; ++i) {
		double most = headMoves ? 1.0 : 0.0;
		for (const Points& s : model.alignedShapes) most = std::max(most, (s.row(i) - model.meanShape.row(i)).norm());
		value(i, 0) = std::min(1.0, most / 0.5);
	}
	// The mesh's affine map per triangle carries the vertex values: its "source x" at a pixel is their
	// barycentric mix.
	PiecewiseAffineWarp field(mesh, meanSource, model.width, model.height);
	field.setSource(value);
	prefilterMask.assign(std::size_t(model.width) * std::size_t(model.height), 0.f);
	field.forEachPixel([&](std::size_t p, float v, float) { prefilterMask[p] = std::clamp(v, 0.f, 1.f); });
}

// D42, D50: the closed lids, when the modulator blinks.
void FaceRig::makeClosedLids(const Face& face, const SynthOptions& o) {
	const FaceModel& model = face.model();
	if (o.modulator && !o.modulator->blinks().empty() && !model.baseface.empty()) {
		// D50: the corpus's closed-eyes image, in the mean frame, gives the shut lid where the model has one.
		const Image8& closed = face.closedEyes();
		const Image8 closedDrawn = prefilteredForBilinear(closed, prefilter, prefilterMask.empty() ? nullptr : &prefilterMask);  // sampled as the rest of the face is (D84)
		for (const EyeSpec& e : eyes) {
			if (closed.empty()) {
				eyePatches.push_back(closedLid(model, baseface, e, roiX0, roiY0, roiX1, roiY1, o.yuvRange, 0.7));
				continue;
			}
			// D86: the person's own lid comes down over the eye (eyeSlits), then their shut eye comes in.
			eyePatches.push_back(closedLidFrom(model, closedDrawn, e, roiX0, roiY0, roiX1, roiY1, o.yuvRange));
			const auto up = lidLine(model.meanShape, e, true), lo = lidLine(model.meanShape, e, false);
			EyeSlit s;
			const double xa = std::min(up.front()(0), up.back()(0)), xb = std::max(up.front()(0), up.back()(0));
			s.x0 = std::max(roiX0, int(std::ceil(xa)));
			for (int x = s.x0; x <= std::min(roiX1 - 1, int(std::floor(xb))); ++x) {
				const double yu = polylineY(up, x), yl = polylineY(lo, x);
				s.upper.push_back(float(std::isnan(yu) || std::isnan(yl) ? 0 : yu));
				s.lower.push_back(float(std::isnan(yu) || std::isnan(yl) ? 0 : std::max(yu, yl)));
			}
			eyeSlits.push_back(std::move(s));
		}
	}
}


Points FaceRig::anchored(const Points& face, bool chroma) const {
	return chroma ? withAnchors(face, anchorsOutChroma, (width + 1) / 2, (height + 1) / 2) : withAnchors(face, anchorsOut, width, height);
}

const Image8& FaceRig::backgroundRgb() const {
	std::call_once(backgroundRgbOnce_, [&] {
		Points mean = model_.meanShape;
		mean.col(0) *= scaleX;
		mean.col(1) *= scaleY;
		PiecewiseAffineWarp warp(mesh, anchored(mean, false), width, height);
		warp.setSource(meanSource);
		backgroundRgb_ = Image8(width, height, 3);
		warp.apply(baseface, backgroundRgb_);
	});
	return backgroundRgb_;
}

}  // namespace talkhead
