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
#include "synth/face_rig.h"
#include "synth/keypose_cache.h"
#include "warp/dissolve_detail.h"
#include "warp/piecewise_affine.h"

namespace talkhead {

namespace {
// CPU time of the calling thread (what the drawing costs, whatever else runs on the machine).
double threadCpuSeconds() {
	timespec t{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

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

Synthesizer::Synthesizer(const Face& face, const SynthOptions& o) : Synthesizer(nullptr, &face, o) {}
Synthesizer::Synthesizer(const FaceModel& model, const SynthOptions& o) : Synthesizer(std::make_unique<Face>(model), nullptr, o) {}
Synthesizer::Synthesizer(std::unique_ptr<Face> own, const Face* face, const SynthOptions& o)
    : ownFace_(std::move(own)),
      face_(face ? *face : *ownFace_),
      model_(face_.model()),
      o_(o),
      rig_(std::make_unique<FaceRig>(face_, o)),
      cache_(std::make_unique<KeyposeCache>(face_, o, *rig_)) {}

Synthesizer::~Synthesizer() = default;
Synthesizer::Workspace::Workspace() = default;
Synthesizer::Workspace::~Workspace() = default;
Synthesizer::Workspace::Workspace(Workspace&&) noexcept = default;
Synthesizer::Workspace& Synthesizer::Workspace::operator=(Workspace&&) noexcept = default;

int Synthesizer::width() const { return rig_->width; }
int Synthesizer::height() const { return rig_->height; }
const KeyposeImage& Synthesizer::keypose(Cdv cdv) { return cache_->keypose(cdv); }

KeyposeSource Synthesizer::keyposeSource(Cdv cdv, Emotion emotion) const {
	Keypose k{Ticks(0), cdv, 0, 0};
	k.context = {"", "", "", "", ""};
	k.emotion = emotion;
	return cache_->sourceOf(k);
}
std::vector<std::string> Synthesizer::substitutions() const { return cache_->substitutions(); }
void Synthesizer::prepare(const std::vector<Keypose>& keys) { cache_->prepare(keys); }
std::vector<std::string> Synthesizer::substitutionsFor(const std::vector<Keypose>& keys) const { return cache_->substitutionsFor(keys); }

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

void Synthesizer::addSkin(Between& f, int map, double weight, int side) {
	if (map < 0 || map >= Between::kMaxSkin || weight == 0) return;
	const auto m = std::size_t(map);
	(side < 0 ? f.left : side > 0 ? f.right : f.both)[m] += float(weight);
	if (std::find(f.skin.begin(), f.skin.begin() + f.skinCount, map) == f.skin.begin() + f.skinCount) f.skin[std::size_t(f.skinCount++)] = map;
}

void Synthesizer::applySkin(const Between& f, std::uint8_t* plane, std::size_t stride, int channels, int black) const {
	if (f.skinCount == 0 || !rig_->auSkin) return;
	const MappedAuAppearance& m = *rig_->auSkin;
	const EyeFrame& e = rig_->auFrame;
	for (int y = 0; y < m.height; ++y) {
		std::uint8_t* row = plane + std::size_t(m.y0 + y) * stride + std::size_t(m.x0) * std::size_t(channels);
		for (int x = 0; x < m.width; ++x) {
			// Which half (as applyActionUnits: within 5 % of the eye distance of the midline, half of each side).
			const double along = ((m.x0 + x - e.origin(0)) * e.x(0) + (m.y0 + y - e.origin(1)) * e.x(1)) / e.iod;
			const float l = along < -0.05 ? 1.f : (along > 0.05 ? 0.f : 0.5f);
			const std::size_t p = std::size_t(y) * std::size_t(m.width) + std::size_t(x);
			float sum = 0;
			for (int j = 0; j < f.skinCount; ++j) {
				const auto a = std::size_t(f.skin[std::size_t(j)]);
				const float r = m.logRatio[a][p];
				if (r != 0) sum += r * (f.both[a] + l * f.left[a] + (1 - l) * f.right[a]);
			}
			if (sum == 0) continue;
			const float g = std::exp(sum);
			for (int c = 0; c < channels; ++c) {
				std::uint8_t& v = row[std::size_t(x) * std::size_t(channels) + std::size_t(c)];
				const float out = float(black) + (float(v) - float(black)) * g + 0.5f;
				v = std::uint8_t(out <= 0.f ? 0.f : (out >= 255.f ? 255.f : out));
			}
		}
	}
}

namespace {

// Head motion (D42) about the face's centre, and a tracked head's (D55) about the point between the eyes.
void moveHead(Points& points, const HeadMotion& h, const FaceRig& rig) {
	if (h.angle != 0 || h.dx != 0 || h.dy != 0) {
		const double c = std::cos(h.angle), s = std::sin(h.angle);
		for (Eigen::Index i = 0; i < points.rows(); ++i) {
			const double x = points(i, 0) - rig.centre(0), y = points(i, 1) - rig.centre(1);
			points(i, 0) = rig.centre(0) + c * x - s * y + h.dx * rig.faceSize;
			points(i, 1) = rig.centre(1) + s * x + c * y + h.dy * rig.faceSize;
		}
	}
	if (h.roll != 0 || h.x != 0 || h.y != 0 || h.scale != 1) {
		const double c = std::cos(h.roll) * h.scale, s = std::sin(h.roll) * h.scale;
		for (Eigen::Index i = 0; i < points.rows(); ++i) {
			const double x = points(i, 0) - rig.eyeMid(0), y = points(i, 1) - rig.eyeMid(1);
			points(i, 0) = rig.eyeMid(0) + c * x - s * y + h.x * rig.eyeDistance;
			points(i, 1) = rig.eyeMid(1) + s * x + c * y + h.y * rig.eyeDistance;
		}
	}
}

}  // namespace

Synthesizer::Between Synthesizer::locate(Ticks tau, const std::vector<Keypose>& keys, Points& points) const {
	if (keys.empty()) throw std::logic_error("renderFrame: no keyposes");
	// The bracketing keyposes; before the first and after the last the face holds.
	std::size_t i = 0;
	while (i + 1 < keys.size() && keys[i + 1].time <= tau) ++i;
	Between f;
	f.src = &cache_->cached(keys[i]);
	const bool hold = tau <= keys.front().time || i + 1 >= keys.size();
	f.dst = hold ? f.src : &cache_->cached(keys[i + 1]);
	f.u = hold ? 0 : double((tau - keys[i].time).count()) / double((keys[i + 1].time - keys[i].time).count());
	f.w = o_.dissolve == Trajectory::Hermite ? f.u * f.u * (3 - 2 * f.u) : f.u;
	f.w256 = int(std::lround(std::clamp(f.w, 0.0, 1.0) * 256));
	if (o_.trajectory == Trajectory::Monotone && !hold) {
		const Points* before = i > 0 ? &cache_->cached(keys[i - 1]).shape : nullptr;
		const Points* after = i + 2 < keys.size() ? &cache_->cached(keys[i + 2]).shape : nullptr;
		auto seconds = [&](std::size_t j) { return toSeconds(keys[j].time); };
		points = monotoneTrajectory({before, &f.src->shape, &f.dst->shape, after},
		                            {before ? seconds(i - 1) : 0.0, seconds(i), seconds(i + 1), after ? seconds(i + 2) : 0.0}, f.u);
	} else {
		points = trajectory(f.src->shape, f.dst->shape, f.u, o_.trajectory);
	}
	if (rig_->stabilise) {  // D55: a tracked head: the pose is the driver's; the exemplars' own (up to ±1.7° on franck) is removed
		const Similarity t = alignSimilarity(points, model_.meanShape, rig_->stabiliseWeights);
		points = t.apply(points);
	}
	if (o_.modulator) {  // D42: lids, then the head, in model pixels
		f.closure = rig_->eyes.empty() ? 0.0 : o_.modulator->eyeClosure(tau);
		if (f.closure > 0) closeEyes(points, f.closure);
		// Brows (D46): raised 10 % of the eye distance, all along; a frown lowers them 6 % and draws the
		// inner ends 5 % toward the midline, fading to half the lowering and none of the pull at the outer end.
		const auto [raise, frown] = o_.modulator->brows(tau);
		if (raise > 0 || frown > 0)
			for (const BrowSpec& b : rig_->brows)
				for (std::size_t k = 0; k < b.points.size(); ++k) {
					const double inner = 1 - double(k) / double(b.points.size() - 1);
					const int i = b.points[k];
					const double toward = points(i, 0) < rig_->centre(0) ? 1.0 : -1.0;
					points(i, 1) += rig_->eyeDistance * (-0.10 * raise + 0.06 * frown * (0.5 + 0.5 * inner));
					points(i, 0) += rig_->eyeDistance * 0.05 * frown * inner * toward;
				}
		if (!rig_->auEventIndex.empty()) {  // D48: action units from a control track
			std::vector<AuWeight> w;
			const auto& all = o_.modulator->auEvents();
			for (const auto& [e, weight] : o_.modulator->actionUnits(tau)) {
				const std::size_t k = std::size_t(e - all.data());
				w.push_back({rig_->auEventIndex[k], weight, e->side});
				if (rig_->auSkin) addSkin(f, rig_->auEventSkin[k], weight, e->side);
			}
			applyActionUnits(points, *rig_->auTemplates, w, rig_->auFrame);
		}
		if (!rig_->auCurveIndex.empty()) {  // D55: action units from a tracked video
			std::vector<AuWeight> w;
			const auto& curves = o_.modulator->curves().aus;
			for (const auto& [k, weight] : o_.modulator->curveActionUnits(tau)) {
				w.push_back({rig_->auCurveIndex[k], weight, curves[k].side});
				if (rig_->auSkin) addSkin(f, rig_->auCurveSkin[k], weight, curves[k].side);
			}
			applyActionUnits(points, *rig_->auTemplates, w, rig_->auFrame);
		}
		moveHead(points, o_.modulator->head(tau), *rig_);
	}
	points.col(0) *= rig_->scaleX;
	points.col(1) *= rig_->scaleY;
	return f;
}

void Synthesizer::setModulator(std::shared_ptr<const ShapeModulator> m) {
	if (m) {
		if (!rig_->sizedForHead || m->maxAngle() > rig_->headAngle + 1e-12 || m->maxShift() > rig_->headShift + 1e-12)
			throw std::logic_error("Synthesizer::setModulator: the new plan moves the head further than the face box allows");
		if (!m->blinks().empty() && !rig_->sizedForBlinks) throw std::logic_error("Synthesizer::setModulator: blinks, but the synthesizer was made without");
		if (!m->auEvents().empty() || !m->curves().empty())
			throw std::logic_error("Synthesizer::setModulator: action-unit events and curves are fixed at construction");
	}
	o_.modulator = std::move(m);
}

void Synthesizer::closeEyes(Points& points, double closure) const {
	// Each upper-lid point comes down to 95 % of the way to the lower lid below it.
	for (const EyeSpec& e : rig_->eyes) {
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
	// D86: a face with its own shut eyes: the band between the open lids is redrawn from the rows the lowered
	// lid leaves visible; the frame's warp squeezes the band by k into the slit (closeEyes), so they come out
	// at their own size, under the person's own upper lid margin.
	const float k = float(1 - 0.95 * closure);
	auto lower = [](std::uint8_t* plane, std::size_t stride, std::size_t step, int channels, int rows, float yu, float yl, float k) {
		for (int y = std::max(0, int(std::ceil(yu))); y <= std::min(rows - 1, int(std::floor(yl))); ++y) {
			const float from = yl - (yl - float(y)) * k;  // ≥ y: read before it is written (top to bottom)
			const int r = std::min(rows - 1, int(from)), r1 = std::min(rows - 1, r + 1);
			const float f = from - float(r);
			for (int c = 0; c < channels; ++c) {
				const float a = plane[std::size_t(r) * stride + step * std::size_t(c)], b = plane[std::size_t(r1) * stride + step * std::size_t(c)];
				plane[std::size_t(y) * stride + step * std::size_t(c)] = std::uint8_t(a + f * (b - a) + 0.5f);
			}
		}
	};
	const int H = model_.height, ch = (H + 1) / 2;
	for (const FaceRig::EyeSlit& s : rig_->eyeSlits)
		for (std::size_t i = 0; i < s.upper.size(); ++i) {
			const float yu = s.upper[i], yl = s.lower[i];
			if (!(yl - yu >= 1)) continue;
			const std::size_t x = std::size_t(s.x0) + i;
			if (meanY) lower(meanY + x, std::size_t(W), 1, 1, H, yu, yl, k);
			if (meanRgb) lower(meanRgb + 3 * x, std::size_t(W) * 3, 1, 3, H, yu, yl, k);
			if (meanUV && (s.x0 + int(i)) % 2 == 0)  // the chroma sample of columns x, x + 1 (centred between them)
				lower(meanUV + x, std::size_t(cw) * 2, 1, 2, ch, (yu - 0.5f) / 2, (yl - 0.5f) / 2, k);
		}
	for (const ClosedLidPatch& p : rig_->eyePatches) {
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

void Synthesizer::restoreDetail(const Between& f, Workspace& ws, std::uint8_t* plane, std::size_t stride, int channels, float scale) const {
	if (f.src == f.dst || f.w256 <= 0 || f.w256 >= 256 || f.src->detail.empty() || f.dst->detail.empty()) return;
	const int rw = rig_->roiX1 - rig_->roiX0, rh = rig_->roiY1 - rig_->roiY0;
	if (!ws.detail) ws.detail = std::make_unique<DetailDissolve>();
	if (ws.detailA != f.src || ws.detailB != f.dst) {  // a new pair: made once, for the frames between them
		{
			std::lock_guard<std::mutex> lock(pairsMutex_);
			auto it = pairs_.find({f.src, f.dst});
			if (it == pairs_.end()) {
				if (pairs_.size() >= 4096) pairs_.clear();  // a long live session: start again (workspaces keep theirs alive)
				it = pairs_.emplace(std::make_pair(f.src, f.dst), std::make_shared<const DetailPair>(detailPair(f.src->detail.data(), f.src->detailEnergy,
				                                                                                               f.dst->detail.data(), f.dst->detailEnergy, rw, rh))).first;
			}
			ws.detailPair = it->second;
		}
		ws.detail->prepare(f.src->detail.data(), f.src->detailEnergy, f.dst->detail.data(), f.dst->detailEnergy, *ws.detailPair, rw, rh);
		ws.detailA = f.src, ws.detailB = f.dst;
	}
	if (ws.detail->y1() <= ws.detail->y0()) return;
	ws.detail->setWeight(f.w256 / 256.0);  // the blend's own weight
	for (int y = ws.detail->y0(); y < ws.detail->y1(); ++y)
		ws.detail->restoreRow(y, plane + std::size_t(rig_->roiY0 + y) * stride + std::size_t(rig_->roiX0) * std::size_t(channels), channels, scale);
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
	if (out.width != rig_->width || out.height != rig_->height || out.channels != 3) out = Image8(rig_->width, rig_->height, 3), outHoldsFrame = false;
	const double t0 = threadCpuSeconds();
	// The static background, then the moving triangles over it (D41).
	if (!outHoldsFrame) {
		const Image8& background = rig_->backgroundRgb();
		std::memcpy(out.data.data(), background.data.data(), out.data.size());
	}
	placeWarp(ws.warp, rig_->movingMesh, rig_->anchored(points, false), rig_->width, rig_->height);
	if (o_.warpPath == WarpPath::Keypose) {
		auto source = [&](const KeyposeImage* k) { return withAnchors(k->shape, rig_->anchors, model_.width, model_.height); };
		if (f.u <= 0) {
			ws.warp->setSource(source(f.src));
			ws.warp->apply(f.src->image, out);
		} else {  // F = K_f (1 − t) + K_b t, K_f = source warped S → P(t), K_b = target warped T → P(t), in one pass
			ws.warp->dissolve(f.src->image, source(f.src), f.dst->image, source(f.dst), f.w, out);
		}
		if (f.closure > 0 && !rig_->eyePatches.empty()) {
			// The shut lids live in the mean frame, which this order never builds: during a blink, the frame
			// goes back to the mean shape, gets its lids there, and is warped forward again (blink frames only).
			PiecewiseAffineWarp back(rig_->mesh, rig_->meanSource, model_.width, model_.height);
			back.setSource(rig_->anchored(points, false));
			if (ws.meanRgb.width != model_.width || ws.meanRgb.height != model_.height) ws.meanRgb = Image8(model_.width, model_.height, 3);
			back.apply(out, ws.meanRgb);  // the direct path's buffer, unused by this order
			drawClosedLids(nullptr, nullptr, ws.meanRgb.data.data(), f.closure);
			ws.warp->setSource(rig_->meanSource);
			ws.warp->apply(ws.meanRgb, out);
		}
		ws.warpSeconds += threadCpuSeconds() - t0;
		return;
	}
	// Direct: dissolve the two composited appearances in the mean-shape frame, then one warp s̄ → P(t).
	if (ws.meanRgb.empty()) ws.meanRgb = rig_->baseface;
	const int rw = rig_->roiX1 - rig_->roiX0;
	for (int y = rig_->roiY0; y < rig_->roiY1; ++y) {
		const std::size_t at = std::size_t(y - rig_->roiY0) * rw * 3;
		blendRow(f.src->rgb.data() + at, f.dst->rgb.data() + at, f.w256, ws.meanRgb.row(y) + std::size_t(rig_->roiX0) * 3, std::size_t(rw) * 3);
	}
	restoreDetail(f, ws, ws.meanRgb.data.data(), std::size_t(model_.width) * 3, 3, o_.yuvRange == YuvRange::Limited ? 255.f / 219.f : 1.f);
	applySkin(f, ws.meanRgb.data.data(), std::size_t(model_.width) * 3, 3, 0);
	if (f.closure > 0) drawClosedLids(nullptr, nullptr, ws.meanRgb.data.data(), f.closure);
	ws.warp->setSource(rig_->meanSource);
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
	if (out.width != rig_->width || out.height != rig_->height) outHoldsFrame = false;
	out.resize(rig_->width, rig_->height);
	const double t0 = threadCpuSeconds();
	const int W = model_.width, H = model_.height, cw = (W + 1) / 2, ch = (H + 1) / 2;
	const int outCw = out.chromaWidth(), outCh = out.chromaHeight();
	// The static background, then the moving triangles over it (D41).
	if (!outHoldsFrame) {
		std::memcpy(out.y.data(), rig_->backgroundYuv.y.data(), out.y.size());
		std::memcpy(out.u.data(), rig_->backgroundYuv.u.data(), out.u.size());
		std::memcpy(out.v.data(), rig_->backgroundYuv.v.data(), out.v.size());
	}
	placeWarp(ws.warp, rig_->movingMesh, rig_->anchored(points, false), rig_->width, rig_->height);
	placeWarp(ws.chromaWarp, rig_->movingMesh, rig_->anchored(toChroma(points), true), outCw, outCh);
	if (ws.meanY.empty()) {
		resizePrefaulted(ws.meanY, rig_->baseY.size());
		resizePrefaulted(ws.meanUV, rig_->baseUV.size());
		std::memcpy(ws.meanY.data(), rig_->baseY.data(), rig_->baseY.size());
		std::memcpy(ws.meanUV.data(), rig_->baseUV.data(), rig_->baseUV.size());
	}
	// Eq. 5.4 in the mean-shape frame (luma and chroma), then one warp of each plane s̄ → P(t).
	const int rw = rig_->roiX1 - rig_->roiX0, rcw = (rw + 1) / 2;
	for (int y = rig_->roiY0; y < rig_->roiY1; ++y) {
		const std::size_t at = std::size_t(y - rig_->roiY0) * rw;
		blendRow(f.src->y.data() + at, f.dst->y.data() + at, f.w256, ws.meanY.data() + std::size_t(y) * W + rig_->roiX0, std::size_t(rw));
	}
	for (int y = rig_->roiY0 / 2; y < (rig_->roiY1 + 1) / 2; ++y) {
		const std::size_t at = std::size_t(y - rig_->roiY0 / 2) * rcw * 2;
		blendRow(f.src->uv.data() + at, f.dst->uv.data() + at, f.w256, ws.meanUV.data() + (std::size_t(y) * cw + std::size_t(rig_->roiX0 / 2)) * 2,
		         std::size_t(rcw) * 2);
	}
	restoreDetail(f, ws, ws.meanY.data(), std::size_t(W), 1, 1.f);
	applySkin(f, ws.meanY.data(), std::size_t(W), 1, o_.yuvRange == YuvRange::Limited ? 16 : 0);
	if (f.closure > 0) drawClosedLids(ws.meanY.data(), ws.meanUV.data(), nullptr, f.closure);
	ws.warp->setSource(rig_->meanSource);
	std::uint8_t* luma[1] = {out.y.data()};
	ws.warp->applyPlanes(ws.meanY.data(), W, H, std::size_t(W), 1, luma, std::size_t(rig_->width));
	ws.chromaWarp->setSource(rig_->meanSourceChroma);
	std::uint8_t* chroma[2] = {out.u.data(), out.v.data()};
	ws.chromaWarp->applyPlanes(ws.meanUV.data(), cw, ch, std::size_t(cw) * 2, 2, chroma, std::size_t(outCw));
	ws.warpSeconds += threadCpuSeconds() - t0;
}

}  // namespace talkhead
