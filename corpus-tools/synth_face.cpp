// SPDX-License-Identifier: GPL-3.0-or-later
// The parametric face of the synthetic corpus. Geometry is defined in "face units" (f = 1/7.2 of the
// image height, origin between the eyes, x to the image right, y down); the subject's right (R) is on
// the image left (x < 0). Every feature point is computed from the parameters that draw the face.
#include "synth_face.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace talkhead {

namespace {

struct P {
	double x, y;
};
P operator+(P a, P b) { return {a.x + b.x, a.y + b.y}; }
P operator-(P a, P b) { return {a.x - b.x, a.y - b.y}; }
P operator*(P a, double s) { return {a.x * s, a.y * s}; }
P lerp(P a, P b, double t) { return a + (b - a) * t; }
P mirror(P a) { return {-a.x, a.y}; }
double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }

// Catmull-Rom through control points (open: end points repeated), `n` samples per segment.
std::vector<P> curve(const std::vector<P>& c, int n = 10) {
	std::vector<P> out;
	const int m = int(c.size());
	for (int i = 0; i + 1 < m; ++i) {
		P p0 = c[std::max(0, i - 1)], p1 = c[i], p2 = c[i + 1], p3 = c[std::min(m - 1, i + 2)];
		for (int s = 0; s < n; ++s) {
			double t = double(s) / n, t2 = t * t, t3 = t2 * t;
			out.push_back((p1 * 2 + (p2 - p0) * t + (p0 * 2 - p1 * 5 + p2 * 4 - p3) * t2 + (p1 * 3 - p0 - p2 * 3 + p3) * t3) * 0.5);
		}
	}
	out.push_back(c.back());
	return out;
}

std::vector<P> closedCurve(const std::vector<P>& c, int n = 10) {
	std::vector<P> out;
	const int m = int(c.size());
	for (int i = 0; i < m; ++i) {
		P p0 = c[(i + m - 1) % m], p1 = c[i], p2 = c[(i + 1) % m], p3 = c[(i + 2) % m];
		for (int s = 0; s < n; ++s) {
			double t = double(s) / n, t2 = t * t, t3 = t2 * t;
			out.push_back((p1 * 2 + (p2 - p0) * t + (p0 * 2 - p1 * 5 + p2 * 4 - p3) * t2 + (p1 * 3 - p0 - p2 * 3 + p3) * t3) * 0.5);
		}
	}
	return out;
}

std::vector<P> concat(std::vector<P> a, const std::vector<P>& b) {
	a.insert(a.end(), b.begin(), b.end());
	return a;
}
std::vector<P> reversed(std::vector<P> a) {
	std::reverse(a.begin(), a.end());
	return a;
}
std::vector<P> mirrored(const std::vector<P>& a) {
	std::vector<P> r;
	for (const P& p : a) r.push_back(mirror(p));
	return r;
}
std::vector<P> ellipse(P c, double rx, double ry, double angleRad = 0, int n = 48) {
	std::vector<P> r;
	for (int i = 0; i < n; ++i) {
		double t = 2 * M_PI * i / n, x = rx * std::cos(t), y = ry * std::sin(t);
		r.push_back({c.x + x * std::cos(angleRad) - y * std::sin(angleRad), c.y + x * std::sin(angleRad) + y * std::cos(angleRad)});
	}
	return r;
}
// A stroke along a polyline as a polygon of the given half-widths at its start and end.
std::vector<P> stroke(const std::vector<P>& line, double w0, double w1) {
	std::vector<P> left, right;
	const std::size_t n = line.size();
	for (std::size_t i = 0; i < n; ++i) {
		P d = line[std::min(n - 1, i + 1)] - line[i == 0 ? 0 : i - 1];
		double len = std::hypot(d.x, d.y);
		P nrm = len > 0 ? P{-d.y / len, d.x / len} : P{0, 0};
		double t = n > 1 ? double(i) / double(n - 1) : 0;
		double w = w0 + (w1 - w0) * t;
		w *= std::sin(std::clamp(t, 0.0, 1.0) * M_PI) * 0.6 + 0.4;
		left.push_back(line[i] + nrm * w);
		right.push_back(line[i] - nrm * w);
	}
	return concat(left, reversed(right));
}

using Color = cv::Vec3f;

// Paints antialiased, optionally blurred shapes onto a float RGB canvas, only within each shape's box.
class Painter {
public:
	Painter(cv::Mat& canvas, double ox, double oy, double f) : c_(canvas), ox_(ox), oy_(oy), f_(f) {}

	struct Mask {
		cv::Rect roi;
		cv::Mat m;  // CV_32F, 0..1, roi-sized
		bool empty() const { return m.empty(); }
	};

	cv::Point2d px(P p) const { return {ox_ + p.x * f_, oy_ + p.y * f_}; }

	Mask shape(const std::vector<std::vector<P>>& polys, double blur = 0) const {
		double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
		for (const auto& poly : polys)
			for (const P& p : poly) {
				cv::Point2d q = px(p);
				x0 = std::min(x0, q.x), y0 = std::min(y0, q.y), x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
			}
		const double sigma = blur * f_;
		const int margin = int(std::ceil(3 * sigma)) + 2;
		cv::Rect roi(int(std::floor(x0)) - margin, int(std::floor(y0)) - margin, int(std::ceil(x1 - x0)) + 2 * margin + 1,
		             int(std::ceil(y1 - y0)) + 2 * margin + 1);
		roi &= cv::Rect(0, 0, c_.cols, c_.rows);
		Mask mk;
		if (roi.width <= 0 || roi.height <= 0) return mk;
		cv::Mat m8 = cv::Mat::zeros(roi.size(), CV_8U);
		constexpr int shift = 4;
		std::vector<std::vector<cv::Point>> pts;
		for (const auto& poly : polys) {
			std::vector<cv::Point> v;
			for (const P& p : poly) {
				cv::Point2d q = px(p);
				v.emplace_back(int(std::lround((q.x - roi.x) * (1 << shift))), int(std::lround((q.y - roi.y) * (1 << shift))));
			}
			pts.push_back(v);
		}
		cv::fillPoly(m8, pts, cv::Scalar(255), cv::LINE_AA, shift);
		m8.convertTo(mk.m, CV_32F, 1.0 / 255.0);
		if (sigma > 0.3) cv::GaussianBlur(mk.m, mk.m, cv::Size(0, 0), sigma);
		mk.roi = roi;
		return mk;
	}
	Mask shape(const std::vector<P>& poly, double blur = 0) const { return shape(std::vector<std::vector<P>>{poly}, blur); }

	// Mask a restricted to mask b (b's coverage multiplies a).
	static Mask clip(const Mask& a, const Mask& b) {
		Mask r = a;
		if (a.empty()) return r;
		r.m = a.m.clone();
		cv::Rect both = a.roi & b.roi;
		cv::Mat keep = cv::Mat::zeros(a.roi.size(), CV_32F);
		if (!b.empty() && both.area() > 0)
			b.m(both - b.roi.tl()).copyTo(keep(both - a.roi.tl()));
		cv::multiply(r.m, keep, r.m);
		return r;
	}

	void fill(const Mask& mk, Color color, double opacity = 1) {
		if (mk.empty()) return;
		cv::Mat region = c_(mk.roi);
		for (int y = 0; y < region.rows; ++y) {
			Color* d = region.ptr<Color>(y);
			const float* a = mk.m.ptr<float>(y);
			for (int x = 0; x < region.cols; ++x) {
				float w = a[x] * float(opacity);
				if (w > 0) d[x] = d[x] * (1 - w) + color * w;
			}
		}
	}
	// Multiplies the canvas by (1 − amount·mask): amount > 0 darkens, < 0 brightens.
	void shade(const Mask& mk, double amount) {
		if (mk.empty()) return;
		cv::Mat region = c_(mk.roi);
		for (int y = 0; y < region.rows; ++y) {
			Color* d = region.ptr<Color>(y);
			const float* a = mk.m.ptr<float>(y);
			for (int x = 0; x < region.cols; ++x) d[x] *= float(1 - amount * a[x]);
		}
	}
	void fill(const std::vector<P>& poly, Color color, double opacity = 1, double blur = 0) { fill(shape(poly, blur), color, opacity); }
	void shade(const std::vector<P>& poly, double amount, double blur) { shade(shape(poly, blur), amount); }

	double f() const { return f_; }
	cv::Mat& canvas() { return c_; }

private:
	cv::Mat& c_;
	double ox_, oy_, f_;
};

const Color kSkin(228, 180, 152);
const Color kSkinShadow(196, 138, 112);
const Color kHair(58, 38, 28);
const Color kHairLight(96, 66, 46);
const Color kLipUpper(178, 86, 92);
const Color kLipLower(196, 100, 106);
const Color kCavity(62, 20, 26);
const Color kTeeth(236, 232, 222);
const Color kTongue(196, 92, 98);
const Color kSclera(240, 236, 230);
const Color kIris(92, 66, 42);
const Color kBrow(78, 52, 38);
const Color kLash(36, 24, 20);
const Color kShirt(58, 92, 142);

// Everything the drawing and the points need, in face units.
struct Geometry {
	// mouth
	P cornerR, cornerL, rm1, vmr, cum, vml, lm1, lm3, clm, rm3, rm4, cium, lm4, lm5, cilm, rm5;
	double teethUpperEdge, teethLowerEdge, mouthHalfWidth, drop, jawOpen;
	// jaw
	P cjaw, rjaw2, rjaw1, chinSideR;
	// eyes (right = image left; left eye mirrored with its own values)
	P reye1, reye2, reye3, reye4, reyeUpperOuter, reyeUpperInner, reyeLowerInner, reyeLowerOuter;
	double eyeOpen;
	// brows
	P reb1, reb2, reb3;
	// nose
	P n1, n2, n3, n4, rn1, rn2, rn3;
	// head, ears
	P hc, hr, rear1, rear2, rear3, rear4;
	double cheekRaise;
};

Geometry computeGeometry(const Articulation& a, const ActionUnits& u) {
	Geometry g;
	// Jaw: AU26 adds to the viseme's opening; rounding and pressing never open it.
	g.jawOpen = std::clamp(a.jaw + 0.5 * u.au26, 0.0, 1.2);
	const double closed = clamp01(a.closed), tuck = clamp01(a.tuck), round = clamp01(a.round);
	g.drop = g.jawOpen * 0.40;
	const double ym = 1.36;
	// Mouth width: spread widens, rounding narrows; a smile (AU12) and the lip stretcher (AU20) widen every viseme,
	// tightening and pressing narrow it.
	double hw = 0.46 * (1 + 0.16 * a.width - 0.30 * round) *
	            (1 + 0.26 * u.au12 + 0.30 * u.au20 - 0.08 * u.au23 - 0.05 * u.au24 + 0.03 * u.au15);
	g.mouthHalfWidth = hw;
	const double open = 1 - closed;  // a bilabial closure overrides every action unit that parts the lips
	// AU17 pushes the lower lip's middle up, so the corners sit lower relative to it.
	const double cornerY = ym + 0.28 * g.drop * open - 0.17 * u.au12 + 0.16 * u.au15 + 0.05 * u.au20 + 0.03 * u.au17 - 0.02 * u.au10;
	g.cornerR = {-hw, cornerY};
	g.cornerL = {hw, cornerY};
	// Upper teeth are fixed to the skull; lower teeth ride on the jaw.
	g.teethUpperEdge = ym + 0.045;
	// Inner upper lip: raised by upper-lip raise, by teeth display and a little by rounding of an open mouth;
	// AU10 raises it off the upper teeth, a broad smile (AU12 with the lips parted) a little.
	const double yiu0 = ym - 0.005 - 0.06 * clamp01(a.upper) - 0.035 * clamp01(a.teeth) - 0.02 * round * clamp01(a.jaw * 3) + 0.02 * u.au24;
	const double yiu = yiu0 - (0.08 * u.au10 + 0.03 * u.au12 * u.au25) * open;
	// Lip thickness: tightening, pressing and stretching thin the lips.
	const double thin = std::clamp(1 - 0.40 * u.au23 - 0.45 * u.au24 - 0.25 * u.au20 - 0.12 * u.au12, 0.3, 1.0);
	const double tu = 0.125 * (1 + 0.35 * round) * thin;
	// Inner lower lip: the jaw's drop unless the lips are pressed; AU25 parts the lips without the jaw, AU16
	// pulls the lower lip down off the lower teeth, AU17 pushes it up; tucked under the upper teeth for [f].
	double yil = yiu0 + (g.drop + 0.04 * clamp01(a.teeth) + 0.06 * u.au25 + 0.07 * u.au16 - 0.02 * u.au17) * open;
	yil = std::max(yil, yiu);
	// The lower incisors show a little above the lower lip once the mouth is open.
	g.teethLowerEdge = std::max(g.teethUpperEdge + 0.01, yil - 0.035 * clamp01(g.drop / 0.12) - 0.03 * u.au16 * open);
	yil = yil + (g.teethUpperEdge + 0.01 - yil) * tuck;
	const double tl = 0.18 * (1 + 0.25 * round - 0.30 * tuck) * thin;
	g.cium = {0, yiu};
	g.cilm = {0, yil};
	g.cum = {0, yiu - tu};
	const double bow = 0.11 * hw / 0.46;
	// The lip stretcher flattens the lips into a wide, straight-sided opening.
	const double side = 1 + 0.16 * u.au20;
	g.vmr = {-bow, yiu - tu - 0.022};
	g.vml = {bow, yiu - tu - 0.022};
	g.rm1 = {-0.58 * side * hw, (cornerY * 0.25 + (yiu - tu) * 0.75) + 0.005};
	g.lm1 = mirror(g.rm1);
	g.rm4 = {-0.50 * side * hw, cornerY * 0.18 + yiu * 0.82};
	g.lm4 = mirror(g.rm4);
	g.rm5 = {-0.50 * side * hw, cornerY * 0.18 + yil * 0.82};
	g.lm5 = mirror(g.rm5);
	const double lowerOuter = yil + tl - 0.06 * u.au17;
	g.clm = {0, lowerOuter};
	g.rm3 = {-0.56 * side * hw, cornerY * 0.22 + lowerOuter * 0.78};
	g.lm3 = mirror(g.rm3);

	// Jaw outline moves with the opening (more at the chin than at the angle).
	g.cjaw = {0, 2.15 + g.jawOpen * 0.44 - 0.05 * u.au17};
	g.chinSideR = {-0.58, 2.00 + g.jawOpen * 0.40};
	g.rjaw2 = {-1.06 + 0.04 * g.jawOpen, 1.42 + g.jawOpen * 0.26};
	g.rjaw1 = {-1.22, 0.95 + g.jawOpen * 0.05};

	// Eyes: lid opening from AU5 (raise), AU7 (tighten), AU6 and AU9 (the cheek pushes the lower lid up), AU4
	// (the lowered brow presses on the upper lid), AU43 (close).
	const double openL = std::clamp(1 - 0.45 * u.au6 - 0.40 * u.au7 + 0.10 * u.au5 - 0.2 * u.au43 - 0.25 * u.au9, 0.25, 1.3);
	// AU43 at 1: shut — the upper lid comes down onto the lower lid's line (the closed-eye image, D50).
	const double openU = u.au43 >= 1 ? -0.6 * openL + 0.01
	                                 : std::clamp(1 + 0.60 * u.au5 - 0.30 * u.au7 - 0.15 * u.au6 - 0.85 * u.au43 - 0.10 * u.au4 - 0.10 * u.au9, 0.08, 1.7);
	g.eyeOpen = openU;
	g.reye1 = {-0.88, 0.01};
	g.reye3 = {-0.36, 0.02};
	g.reye2 = {-0.61, -0.125 * openU};
	g.reye4 = {-0.62, 0.075 * openL};
	g.reyeUpperOuter = {-0.77, -0.10 * openU};
	g.reyeUpperInner = {-0.45, -0.085 * openU - 0.02 * u.au1 * u.au4};  // 1+4 lifts the lid's inner third
	g.reyeLowerInner = {-0.46, 0.06 * openL};
	g.reyeLowerOuter = {-0.78, 0.055 * openL};
	g.cheekRaise = u.au6;

	// Brows: AU1 lifts the inner end, AU2 the outer, AU4 lowers them and draws them together, AU9 pulls the
	// inner ends down. In 1+4 (sadness, fear) AU1 wins at the inner end and AU4 knits and lowers the rest,
	// which gives the oblique brow of sadness.
	// With AU1+2 (fear) AU4 also flattens the raised arch into the straight brow of fear. AU9 lowers the
	// whole brow rather than knitting it.
	const double knit = u.au4 * (1 - 0.6 * u.au1);
	const double flatten = u.au4 * std::min(u.au1, u.au2);
	g.reb1 = {-0.30 + 0.10 * u.au4 + 0.01 * u.au9, -0.40 - 0.26 * u.au1 + 0.19 * knit + 0.05 * u.au9};
	g.reb2 = {-0.63 + 0.05 * u.au4, -0.53 - 0.06 * u.au1 - 0.19 * u.au2 + 0.15 * u.au4 + 0.06 * u.au9 + 0.08 * flatten};
	g.reb3 = {-0.97 + 0.02 * u.au4, -0.44 - 0.22 * u.au2 + 0.06 * u.au4 + 0.05 * u.au9};

	// Nose: AU9 wrinkles it, lifting the wings and the base.
	g.n1 = {0, -0.10};
	g.n4 = {0, 0.36};
	g.rn1 = {-0.13, 0.36};
	g.n2 = {0, 0.80 - 0.03 * u.au9};
	g.rn2 = {-0.31 - 0.03 * u.au9 - 0.01 * u.au10, 0.84 - 0.09 * u.au9 - 0.03 * u.au10};
	g.rn3 = {-0.16, 0.955 - 0.07 * u.au9 - 0.02 * u.au10};
	g.n3 = {0, 0.965 - 0.07 * u.au9 - 0.02 * u.au10};

	g.hc = {0, -2.05};
	g.hr = {-1.02, -1.62};
	g.rear1 = {-1.43, -0.30};
	g.rear2 = {-1.57, 0.02};
	g.rear3 = {-1.50, 0.52};
	g.rear4 = {-1.38, 0.74};
	return g;
}

// The 56 points in ch-unicamp-56 order (models/schemes/ch-unicamp-56.scheme).
std::vector<P> featurePoints(const Geometry& g) {
	auto L = mirror;
	return {g.cornerR, g.cornerL, g.cum,  g.clm,      g.vmr,      g.vml,      g.rm1,     g.lm1,     g.rm3,     g.lm3,    // 10
	        g.reb1,    g.reb2,    g.reb3, L(g.reb1),  L(g.reb2),  L(g.reb3),  g.reye1,   g.reye3,   g.reye2,   g.reye4,  // 20
	        L(g.reye1), L(g.reye3), L(g.reye2), L(g.reye4), g.rn1, L(g.rn1), g.n1, g.n3, g.rn3, L(g.rn3),              // 30
	        g.rn2,     L(g.rn2),  g.n2,   g.n4,       g.hc,       g.hr,       L(g.hr),   g.cjaw,    g.rjaw2,   L(g.rjaw2),  // 40
	        g.rjaw1,   L(g.rjaw1), g.rear1, g.rear2,  g.rear3,    g.rear4,    L(g.rear1), L(g.rear2), L(g.rear3), L(g.rear4),  // 50
	        g.rm4,     g.rm5,     g.cium, g.cilm,     g.lm4,      g.lm5};
}

std::vector<P> faceOutline(const Geometry& g) {
	// Temple → cheek → jaw angle → jaw at mouth height → chin side → chin, mirrored; over the skull top.
	std::vector<P> right{{-1.30, -0.95}, {-1.36, -0.30}, {-1.34, 0.40}, g.rjaw1, g.rjaw2, g.chinSideR};
	std::vector<P> ctrl{{0, -2.0}, {-0.95, -1.75}};
	ctrl = concat(ctrl, right);
	ctrl.push_back(g.cjaw);
	auto left = mirrored(reversed(right));
	ctrl = concat(ctrl, left);
	ctrl.push_back({0.95, -1.75});
	return closedCurve(ctrl, 12);
}

cv::Matx23d poseMatrix(const HeadPose& pose, int width, int height) {
	const double angle = pose.angleDeg * M_PI / 180.0;
	const double ca = pose.scale * std::cos(angle), sa = pose.scale * std::sin(angle);
	const double cx = width / 2.0, cy = height / 2.0;
	return cv::Matx23d(ca, -sa, cx - ca * cx + sa * cy + pose.dx, sa, ca, cy - sa * cx - ca * cy + pose.dy);
}

Points placePoints(const Geometry& g, const cv::Matx23d& M, double ox, double oy, double f) {
	const std::vector<P> fp = featurePoints(g);
	Points out(Eigen::Index(fp.size()), 2);
	for (std::size_t i = 0; i < fp.size(); ++i) {
		const double x = ox + fp[i].x * f, y = oy + fp[i].y * f;
		out(Eigen::Index(i), 0) = M(0, 0) * x + M(0, 1) * y + M(0, 2);
		out(Eigen::Index(i), 1) = M(1, 0) * x + M(1, 1) * y + M(1, 2);
	}
	return out;
}

}  // namespace

Points FaceRenderer::points(const Articulation& a, const ActionUnits& u, const HeadPose& pose) const {
	return placePoints(computeGeometry(a, u), poseMatrix(pose, width_, height_), width_ / 2.0, 0.40 * height_, height_ / 7.2);
}

FaceRenderer::FaceRenderer(int width, int height) : width_(width), height_(height) {
	cv::Mat canvas(height, width, CV_32FC3);
	for (int y = 0; y < height; ++y) {
		const float t = float(y) / float(height);
		Color top(206, 212, 220), bottom(168, 178, 190);
		Color c = top * (1 - t) + bottom * t;
		Color* row = canvas.ptr<Color>(y);
		for (int x = 0; x < width; ++x) {
			const float v = std::abs(float(x) / float(width) - 0.5f) * 2.f;
			row[x] = c * (1.f - 0.10f * v * v);
		}
	}
	const double f = height / 7.2;
	Painter pa(canvas, width / 2.0, 0.40 * height, f);
	// Hair behind the head, falling to the shoulders.
	pa.fill(closedCurve({{0, -2.12}, {-1.2, -1.75}, {-1.62, -0.7}, {-1.72, 0.8}, {-1.80, 2.2}, {-1.95, 3.05}, {-1.2, 3.2}, {0, 2.6},
	                     {1.2, 3.2}, {1.95, 3.05}, {1.80, 2.2}, {1.72, 0.8}, {1.62, -0.7}, {1.2, -1.75}}, 10),
	        kHair, 1, 0.015);
	// Neck and its shadow under the jaw.
	std::vector<P> neck{{-0.66, 1.5}, {-0.70, 2.6}, {-0.78, 3.25}, {0.78, 3.25}, {0.70, 2.6}, {0.66, 1.5}};
	pa.fill(neck, kSkin * 0.93f, 1, 0.01);
	pa.shade(std::vector<P>{{-0.68, 1.8}, {0.68, 1.8}, {0.60, 2.75}, {-0.60, 2.75}}, 0.20, 0.18);
	// Shoulders and a round-necked top.
	pa.fill(closedCurve({{-3.6, 5.0}, {-3.3, 3.7}, {-2.4, 3.12}, {-0.95, 2.92}, {0, 3.30}, {0.95, 2.92}, {2.4, 3.12}, {3.3, 3.7}, {3.6, 5.0}}, 10),
	        kShirt, 1, 0.01);
	pa.shade(closedCurve({{-1.1, 2.95}, {0, 3.45}, {1.1, 2.95}, {0, 3.7}}, 8), 0.25, 0.08);
	canvas.convertTo(canvas, CV_32FC3);
	backdrop_ = Image(width, height, 3);
	std::memcpy(backdrop_.data.data(), canvas.ptr<float>(0), backdrop_.data.size() * sizeof(float));
}

SynthFace FaceRenderer::render(const Articulation& a, const ActionUnits& u, const HeadPose& pose) const {
	const Geometry g = computeGeometry(a, u);
	cv::Mat canvas(height_, width_, CV_32FC3);
	std::memcpy(canvas.ptr<float>(0), backdrop_.data.data(), backdrop_.data.size() * sizeof(float));
	const double f = height_ / 7.2, ox = width_ / 2.0, oy = 0.40 * height_;
	Painter pa(canvas, ox, oy, f);

	// Ears (behind the face outline), with an inner fold.
	for (int side : {-1, 1}) {
		auto sx = [&](P p) { return P{p.x * (side < 0 ? 1 : -1), p.y}; };
		std::vector<P> ear{sx(g.rear1), sx(g.rear2), sx(g.rear3), sx(g.rear4), sx({-1.30, 0.62}), sx({-1.28, -0.22})};
		pa.fill(closedCurve(ear, 10), kSkin * 0.97f, 1, 0.006);
		pa.shade(closedCurve({sx({-1.44, -0.18}), sx({-1.50, 0.10}), sx({-1.44, 0.42}), sx({-1.36, 0.30}), sx({-1.38, -0.05})}, 8), 0.22, 0.03);
	}
	// Face skin with soft edge shading (darker towards the outline) and light from the upper left.
	const std::vector<P> outline = faceOutline(g);
	Painter::Mask face = pa.shape(outline);
	pa.fill(face, kSkin);
	{
		cv::Mat inside8;
		face.m.convertTo(inside8, CV_8U, 255);
		cv::threshold(inside8, inside8, 127, 255, cv::THRESH_BINARY);
		cv::Mat dist;
		cv::distanceTransform(inside8, dist, cv::DIST_L2, 3, CV_32F);
		cv::Mat region = canvas(face.roi);
		const double cx = ox - face.roi.x, cy = oy - face.roi.y;
		for (int y = 0; y < region.rows; ++y) {
			Color* d = region.ptr<Color>(y);
			const float* dd = dist.ptr<float>(y);
			const float* m = face.m.ptr<float>(y);
			for (int x = 0; x < region.cols; ++x) {
				if (m[x] <= 0) continue;
				const double edge = std::exp(-dd[x] / (0.28 * f));
				const double light = 0.05 * ((x - cx) / (1.4 * f)) + 0.03 * ((y - cy) / (2.0 * f));
				d[x] *= float(1 - 0.20 * edge - light);
			}
		}
	}
	// Hair on top: covers the skull down to a hairline with a middle parting, and frames the temples.
	pa.fill(closedCurve({{0, -2.08}, {-1.05, -1.70}, {-1.45, -0.90}, {-1.44, -0.15}, {-1.33, -0.10}, {-1.25, -0.80}, {-0.95, -1.20},
	                     {-0.45, -1.34}, {0, -1.26}, {0.45, -1.34}, {0.95, -1.20}, {1.25, -0.80}, {1.33, -0.10}, {1.44, -0.15},
	                     {1.45, -0.90}, {1.05, -1.70}},
	                    12),
	        kHair, 1, 0.012);
	pa.fill(stroke(curve({{-0.10, -1.95}, {-0.55, -1.70}, {-0.95, -1.35}}), 0.03, 0.01), kHairLight, 0.5, 0.02);
	pa.fill(stroke(curve({{0.10, -1.95}, {0.55, -1.70}, {0.95, -1.35}}), 0.03, 0.01), kHairLight, 0.5, 0.02);

	// Cheeks: blush, lifted by AU6.
	for (double s : {-1.0, 1.0}) {
		pa.fill(ellipse({s * 0.78, 0.80 - 0.10 * g.cheekRaise}, 0.32, 0.22), Color(222, 138, 128), 0.22 + 0.10 * g.cheekRaise, 0.14);
		pa.shade(ellipse({s * 0.72, 0.55 - 0.10 * g.cheekRaise}, 0.22, 0.10), -0.05 - 0.05 * g.cheekRaise, 0.10);
	}
	// Eye sockets and lid creases.
	for (double s : {-1.0, 1.0}) {
		pa.shade(ellipse({s * 0.62, -0.14}, 0.36, 0.20), 0.10, 0.10);
		pa.shade(ellipse({s * 0.36, 0.08}, 0.08, 0.15), 0.08, 0.06);  // beside the nose bridge
	}
	// Nose: side shadows, tip highlight, wings, nostrils, shadow under the nose.
	pa.shade(stroke(curve({{-0.14, 0.05}, {-0.17, 0.45}, {-0.24, 0.78}}), 0.05, 0.06), 0.16, 0.05);
	pa.shade(stroke(curve({{0.14, 0.05}, {0.17, 0.45}, {0.24, 0.78}}), 0.05, 0.06), 0.10, 0.05);
	pa.shade(ellipse({g.n2.x + 0.01, g.n2.y - 0.06}, 0.09, 0.07), -0.10, 0.04);
	pa.shade(ellipse({0, g.n3.y + 0.05}, 0.22, 0.05), 0.10, 0.04);
	for (double s : {-1.0, 1.0}) {
		P wing{s * std::abs(g.rn2.x), g.rn2.y};
		pa.shade(ellipse({wing.x * 0.82, wing.y - 0.01}, 0.11, 0.09), -0.04, 0.03);  // rounded wing
		pa.shade(stroke(curve({{s * 0.22, g.rn2.y - 0.13}, {wing.x, wing.y - 0.03}, {s * 0.24, g.rn3.y + 0.01}}), 0.008, 0.010), 0.14, 0.016);
		pa.fill(ellipse({s * 0.115, g.rn3.y - 0.02}, 0.070, 0.032, s * 0.35), Color(70, 32, 30), 0.85, 0.012);
	}
	// Appearance changes a warp cannot make (FACS Investigator's Guide, Ekman, Friesen & Hager 2002): the
	// wrinkles, folds and bulges each action unit produces, drawn from the same parameters as the points.
	// Nasolabial folds: deeper with a smile (AU12) and, in their upper part beside the nose wing, with AU9 and AU10.
	for (double s : {-1.0, 1.0}) {
		P top{s * (std::abs(g.rn2.x) + 0.03), g.rn2.y + 0.06 - 0.04 * (u.au9 + u.au10)};
		P corner{s * (g.mouthHalfWidth + 0.10), g.cornerR.y + 0.08};
		pa.shade(stroke(curve({top, lerp(top, corner, 0.5) + P{s * 0.06, 0}, corner}), 0.012 + 0.01 * u.au12, 0.02),
		         0.10 + 0.26 * u.au12 + 0.10 * u.au20, 0.025);
		if (u.au9 + u.au10 > 0.05)  // the deepened upper fold and the raised infraorbital triangle above it
			pa.shade(stroke(curve({top + P{0, -0.03}, lerp(top, corner, 0.35) + P{s * 0.04, 0}}), 0.02, 0.01), 0.30 * std::min(1.0, u.au9 + u.au10), 0.02);
		// AU15: the corners pulled down fold the skin below them (the depressor's oblique furrow).
		if (u.au15 > 0.05)
			pa.shade(stroke(curve({corner + P{-s * 0.08, 0.0}, corner + P{-s * 0.02, 0.14}, corner + P{s * 0.02, 0.26}}), 0.015, 0.008), 0.28 * u.au15, 0.02);
		// AU12/AU20: the skin bunches just outside each corner (a dimple for the smile, a taut fold when stretched).
		if (u.au12 + u.au20 > 0.05)
			pa.shade(ellipse({s * (g.mouthHalfWidth + 0.06), g.cornerR.y + 0.01}, 0.03, 0.06), 0.20 * std::min(1.0, u.au12 + u.au20), 0.02);
	}
	// Chin: mentolabial shadow and chin highlight; AU17 pushes the chin boss up, deepens the furrow under the
	// lower lip and wrinkles the chin's skin.
	pa.shade(ellipse({0, g.clm.y + 0.13 - 0.03 * u.au17}, 0.22, 0.05), 0.08 + 0.22 * u.au17, 0.05);
	pa.shade(ellipse({0, g.cjaw.y - 0.22}, 0.25, 0.13), -0.05 - 0.06 * u.au17, 0.08);
	if (u.au17 > 0.05)
		for (const P& d : {P{-0.10, -0.27}, P{0.08, -0.30}, P{-0.02, -0.20}, P{0.13, -0.21}, P{-0.14, -0.17}, P{0.03, -0.13}})
			pa.shade(ellipse(P{0, g.cjaw.y} + d, 0.025, 0.018), 0.12 * u.au17, 0.015);
	// AU23/AU24: the pressed lips bulge the skin above and below them.
	if (u.au23 + u.au24 > 0.05) {
		const double press = std::min(1.0, u.au23 + u.au24);
		pa.shade(stroke(curve({g.rm1 + P{-0.02, -0.05}, g.cum + P{0, -0.06}, g.lm1 + P{0.02, -0.05}}), 0.02, 0.02), -0.06 * press, 0.03);
		pa.shade(stroke(curve({g.rm3 + P{0, 0.05}, g.clm + P{0, 0.05}, g.lm3 + P{0, 0.05}}), 0.02, 0.02), 0.10 * press, 0.03);
	}
	// Forehead: horizontal lines, in the middle for AU1 (inner brow raise), across for AU2.
	if (u.au1 > 0.05 || u.au2 > 0.05) {
		const double reach = 0.30 + 0.30 * std::min(1.0, u.au2 / std::max(0.05, u.au1));
		for (int i = 0; i < 3; ++i) {
			double y = -0.80 - 0.13 * i - 0.08 * u.au1;
			pa.shade(stroke(curve({{-reach, y + 0.04 * (1 - u.au2)}, {0, y - 0.02 * u.au1}, {reach, y + 0.04 * (1 - u.au2)}}), 0.009, 0.009),
			         0.16 * std::max(u.au1, u.au2), 0.012);
		}
	}
	// AU4: vertical furrows between the brows, and the lowered brows shade the eyes.
	if (u.au4 > 0.05) {
		for (double s : {-1.0, 1.0}) {
			pa.shade(stroke(curve({{s * 0.09, -0.48}, {s * 0.075, -0.33}, {s * 0.08, -0.20}}), 0.012, 0.008), 0.40 * u.au4, 0.012);
			pa.shade(stroke(curve({{s * 0.17, -0.40}, {s * 0.13, -0.28}}), 0.008, 0.006), 0.20 * u.au4 * (1 - u.au1), 0.012);
			pa.shade(ellipse({s * 0.60, -0.16}, 0.32, 0.12), 0.12 * u.au4, 0.08);
		}
	}
	// AU9: horizontal wrinkles across the root of the nose, between and below the brows.
	if (u.au9 > 0.05)
		for (int i = 0; i < 3; ++i) {
			const double y = -0.12 + 0.09 * i, w = 0.10 + 0.02 * i;
			pa.shade(stroke(curve({{-w, y + 0.02}, {0, y - 0.015}, {w, y + 0.02}}), 0.010, 0.010), 0.30 * u.au9, 0.010);
		}
	// AU6 (and AU9's cheek): crow's feet fanning from the outer eye corners, the lower lid bulge.
	for (double s : {-1.0, 1.0}) {
		const double cheek = std::min(1.0, u.au6 + 0.5 * u.au9);
		if (cheek > 0.05) {
			for (int i = -1; i <= 1; ++i)
				pa.shade(stroke(curve({{s * 0.94, 0.02 + 0.05 * i}, {s * 1.06, 0.02 + 0.09 * i}}), 0.008, 0.004), 0.22 * cheek, 0.010);
			pa.shade(stroke(curve({{s * 0.45, 0.16}, {s * 0.62, 0.19}, {s * 0.80, 0.15}}), 0.012, 0.012), 0.14 * cheek, 0.02);
		}
	}

	// Eyes.
	for (double s : {-1.0, 1.0}) {
		auto X = [&](P p) { return P{p.x * -s, p.y}; };  // s = −1: right eye as computed; s = +1: mirrored
		const std::vector<P> upper = curve({X(g.reye1), X(g.reyeUpperOuter), X(g.reye2), X(g.reyeUpperInner), X(g.reye3)}, 8);
		const std::vector<P> lower = curve({X(g.reye3), X(g.reyeLowerInner), X(g.reye4), X(g.reyeLowerOuter), X(g.reye1)}, 8);
		const std::vector<P> opening = concat(upper, lower);
		Painter::Mask sclera = pa.shape(opening);
		pa.fill(sclera, kSclera);
		const P irisC{X(g.reye2).x * 0.0 + X({-0.615, 0}).x, -0.005};
		pa.fill(Painter::clip(pa.shape(ellipse(irisC, 0.108, 0.108), 0.004), sclera), kIris);
		pa.fill(Painter::clip(pa.shape(ellipse(irisC, 0.108, 0.108), 0.0), sclera), Color(40, 28, 20), 0.0);
		pa.shade(Painter::clip(pa.shape(ellipse(irisC, 0.07, 0.07), 0.03), sclera), -0.25);
		pa.fill(Painter::clip(pa.shape(ellipse(irisC, 0.045, 0.045), 0.003), sclera), Color(14, 10, 10));
		pa.fill(Painter::clip(pa.shape(ellipse(irisC + P{-0.03, -0.035}, 0.018, 0.018), 0.003), sclera), Color(250, 250, 250), 0.9);
		// Shadow of the upper lid on the eyeball.
		pa.shade(Painter::clip(pa.shape(stroke(upper, 0.05, 0.05), 0.02), sclera), 0.25);
		// Lashes along the upper lid (heavier at the outer corner), a soft lower lid line, the crease.
		std::vector<P> lashLine = upper;
		pa.fill(stroke(lashLine, s < 0 ? 0.032 : 0.012, s < 0 ? 0.012 : 0.032), kLash, 1, 0.004);
		pa.fill(stroke(lower, 0.008, 0.008), Color(120, 80, 70), 0.5, 0.006);
		std::vector<P> crease;
		for (const P& p : curve({X(g.reye1) + P{0, -0.05}, X(g.reye2) + P{0, -0.10 - 0.05 * g.eyeOpen}, X(g.reye3) + P{0, -0.07}}, 8))
			crease.push_back(p);
		pa.shade(stroke(crease, 0.01, 0.01), 0.18, 0.015);
	}
	// Brows: a tapered shape whose upper edge passes through REB1–REB3.
	for (double s : {-1.0, 1.0}) {
		auto X = [&](P p) { return P{p.x * -s, p.y}; };
		std::vector<P> top = curve({X(g.reb1), X(g.reb2), X(g.reb3)}, 10);
		std::vector<P> bottom = curve({X(g.reb3) + P{0, 0.035}, X(g.reb2) + P{0, 0.085}, X(g.reb1) + P{X(g.reb1).x * 0.02, 0.105}}, 10);
		pa.fill(concat(top, bottom), kBrow, 0.95, 0.008);
	}

	// Mouth: cavity, teeth and tongue inside it, then the lips over their edges.
	const std::vector<P> innerUpper = curve({g.cornerR, g.rm4, g.cium, g.lm4, g.cornerL}, 10);
	const std::vector<P> innerLower = curve({g.cornerL, g.lm5, g.cilm, g.rm5, g.cornerR}, 10);
	Painter::Mask cavity = pa.shape(concat(innerUpper, innerLower));
	if (!cavity.empty() && g.cilm.y - g.cium.y > 0.004) {
		pa.fill(cavity, kCavity);
		const double tw = 0.36;
		// Tongue body low in the mouth; its tip rises to the upper teeth for [t d n l].
		pa.fill(Painter::clip(pa.shape(ellipse({0, g.teethLowerEdge + 0.02}, 0.62 * g.mouthHalfWidth, 0.085), 0.01), cavity), kTongue, 0.95);
		if (a.tongue > 0.05) {
			const double tipY = g.teethLowerEdge + (g.teethUpperEdge + 0.02 - g.teethLowerEdge) * clamp01(a.tongue);
			pa.fill(Painter::clip(pa.shape(closedCurve({{-0.17, g.teethLowerEdge + 0.06}, {-0.12, tipY + 0.03}, {0, tipY}, {0.12, tipY + 0.03},
			                                            {0.17, g.teethLowerEdge + 0.06}}, 8), 0.008), cavity),
			        kTongue * 1.03f, 0.95);
		}
		std::vector<P> upperTeeth{{-tw, g.teethUpperEdge - 0.25}, {tw, g.teethUpperEdge - 0.25}};
		for (const P& p : reversed(curve({{-tw, g.teethUpperEdge - 0.07}, {-0.2, g.teethUpperEdge - 0.012}, {0, g.teethUpperEdge},
		                                  {0.2, g.teethUpperEdge - 0.012}, {tw, g.teethUpperEdge - 0.07}}, 8)))
			upperTeeth.push_back(p);
		std::rotate(upperTeeth.begin(), upperTeeth.begin() + 1, upperTeeth.end());
		Painter::Mask ut = Painter::clip(pa.shape(upperTeeth, 0.004), cavity);
		pa.fill(ut, kTeeth);
		std::vector<P> lowerTeeth = curve({{-tw * 0.9, g.teethLowerEdge + 0.06}, {-0.2, g.teethLowerEdge + 0.01}, {0, g.teethLowerEdge},
		                                   {0.2, g.teethLowerEdge + 0.01}, {tw * 0.9, g.teethLowerEdge + 0.06}}, 8);
		lowerTeeth.push_back({tw * 0.9, g.teethLowerEdge + 0.3});
		lowerTeeth.push_back({-tw * 0.9, g.teethLowerEdge + 0.3});
		pa.fill(Painter::clip(pa.shape(lowerTeeth, 0.004), cavity), kTeeth * 0.93f);
		// Gaps between the front teeth, and the darker depth of the mouth at the corners.
		for (double x : {-0.21, -0.07, 0.07, 0.21})
			pa.shade(Painter::clip(pa.shape(stroke(std::vector<P>{{x, g.teethUpperEdge - 0.12}, {x * 0.97, g.teethUpperEdge}}, 0.005, 0.005), 0.003), ut), 0.18);
		pa.shade(Painter::clip(pa.shape(ellipse({-g.mouthHalfWidth * 0.8, (g.cium.y + g.cilm.y) / 2}, 0.14, 0.2), 0.05), cavity), 0.35);
		pa.shade(Painter::clip(pa.shape(ellipse({g.mouthHalfWidth * 0.8, (g.cium.y + g.cilm.y) / 2}, 0.14, 0.2), 0.05), cavity), 0.35);
	}
	const std::vector<P> outerUpper = curve({g.cornerR, g.rm1, g.vmr, g.cum, g.vml, g.lm1, g.cornerL}, 10);
	const std::vector<P> outerLower = curve({g.cornerL, g.lm3, g.clm, g.rm3, g.cornerR}, 10);
	pa.fill(concat(outerUpper, reversed(innerUpper)), kLipUpper, 1, 0.004);
	pa.fill(concat(reversed(innerLower), outerLower), kLipLower, 1, 0.004);
	pa.shade(ellipse({0.02, g.clm.y - 0.07}, 0.18, 0.035), -0.12, 0.03);  // lower-lip highlight
	if (a.tuck > 0.05) {
		// [f v]: the upper incisors rest on the tucked lower lip.
		const double bite = 0.07 * clamp01(a.tuck);
		Painter::Mask lowerLip = pa.shape(concat(reversed(innerLower), outerLower));
		std::vector<P> tips = curve({{-0.30, g.cilm.y - 0.05}, {-0.18, g.cilm.y + bite * 0.8}, {0, g.cilm.y + bite}, {0.18, g.cilm.y + bite * 0.8},
		                             {0.30, g.cilm.y - 0.05}}, 8);
		tips.push_back({0.30, g.cilm.y - 0.1});
		tips.push_back({-0.30, g.cilm.y - 0.1});
		pa.shade(lowerLip, 0.12 * clamp01(a.tuck));  // the lip rolled in and pressed
		pa.fill(Painter::clip(pa.shape(tips, 0.004), lowerLip), kTeeth * 0.97f);
	}
	pa.shade(stroke(concat(std::vector<P>{g.cornerR}, innerUpper), 0.008, 0.008), 0.35, 0.006);  // the lip line
	for (double s : {-1.0, 1.0})  // mouth corners
		pa.shade(ellipse({s * (g.mouthHalfWidth + 0.01), g.cornerR.y}, 0.035, 0.025), 0.25, 0.015);
	// Philtrum: two soft ridges from the nose to the cupid's bow.
	pa.shade(stroke(std::vector<P>{{-0.05, g.n3.y + 0.03}, {g.vmr.x * 0.8, g.vmr.y - 0.01}}, 0.012, 0.012), 0.06, 0.02);
	pa.shade(stroke(std::vector<P>{{0.05, g.n3.y + 0.03}, {g.vml.x * 0.8, g.vml.y - 0.01}}, 0.012, 0.012), 0.06, 0.02);

	// Head pose: one similarity about the image centre, applied to the pixels and the points alike.
	const cv::Matx23d M = poseMatrix(pose, width_, height_);
	cv::Mat warped;
	cv::warpAffine(canvas, warped, M, canvas.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
	SynthFace out;
	out.image = Image8(width_, height_, 3);
	cv::Mat out8(height_, width_, CV_8UC3, out.image.data.data());
	warped.convertTo(out8, CV_8UC3);  // saturating, rounds to nearest
	out.points = placePoints(g, M, ox, oy, f);
	return out;
}

}  // namespace talkhead
