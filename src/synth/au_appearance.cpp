// SPDX-License-Identifier: GPL-3.0-or-later
#include "synth/au_appearance.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "base/atomic_file.h"
#include "base/data_dirs.h"
#include "base/error.h"
#include "base/text.h"
#include "phonetics/emotion.h"
#include "warp/piecewise_affine.h"
#include "geometry/eigen_products.h"

namespace talkhead {

Points appearanceAnchors(const Scheme& scheme, const Points& shape) {
	if (scheme.eyes.size() != 2 || scheme.brows.size() != 2)
		throw Error("scheme " + scheme.name + " has no two eyes and two brows: action-unit appearance needs them as anchors");
	Points a(kAppearanceAnchors, 2);
	int k = 0;
	for (const EyeSpec& e : scheme.eyes) {
		a.row(k++) = shape.row(e.corner0);
		a.row(k++) = shape.row(e.corner1);
	}
	for (const BrowSpec& b : scheme.brows) {
		a.row(k++) = shape.row(b.points.front());
		a.row(k++) = shape.row(b.points.back());
	}
	const EyeFrame f = eyeFrame(scheme, shape);
	Eigen::Index chin = 0;
	double lowest = -1e300;
	for (Eigen::Index i = 0; i < shape.rows(); ++i) {
		const double y = (shape.row(i) - f.origin).dot(f.y);
		if (y > lowest) lowest = y, chin = i;
	}
	a.row(k) = shape.row(chin);
	return a;
}

int AuAppearance::find(const std::string& au) const {
	for (std::size_t i = 0; i < names.size(); ++i)
		if (names[i] == au) return int(i);
	return -1;
}

int MappedAuAppearance::find(const std::string& au) const {
	for (std::size_t i = 0; i < names.size(); ++i)
		if (names[i] == au) return int(i);
	return -1;
}

namespace {

float luma(const std::uint8_t* p) { return 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2]; }

// The affine map (2×3, least squares) that takes the points `from` to `to`.
Eigen::Matrix<double, 2, 3> fitAffine(const Points& from, const Points& to) {
	Eigen::MatrixXd A(from.rows(), 3);
	A.col(0) = from.col(0);
	A.col(1) = from.col(1);
	A.col(2).setOnes();
	const Eigen::MatrixXd X = A.colPivHouseholderQr().solve(Eigen::MatrixXd(to));  // 3 × 2
	return X.transpose();
}

void blur(std::vector<float>& v, int w, int h, double sigma) {
	const int r = int(std::ceil(3 * sigma));
	std::vector<float> k(std::size_t(2 * r + 1));
	float sum = 0;
	for (int i = -r; i <= r; ++i) sum += k[std::size_t(i + r)] = float(std::exp(-0.5 * i * i / (sigma * sigma)));
	for (float& x : k) x /= sum;
	std::vector<float> t(v.size());
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x) {
			float s = 0;
			for (int i = -r; i <= r; ++i) s += k[std::size_t(i + r)] * v[std::size_t(y) * w + std::size_t(std::clamp(x + i, 0, w - 1))];
			t[std::size_t(y) * w + std::size_t(x)] = s;
		}
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x) {
			float s = 0;
			for (int i = -r; i <= r; ++i) s += k[std::size_t(i + r)] * t[std::size_t(std::clamp(y + i, 0, h - 1)) * w + std::size_t(x)];
			v[std::size_t(y) * w + std::size_t(x)] = s;
		}
}


using Poly = std::vector<Eigen::RowVector2d>;

Poly convexHull(Poly p) {
	std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a(0) < b(0) || (a(0) == b(0) && a(1) < b(1)); });
	if (p.size() < 3) return p;
	Poly h(2 * p.size());
	std::size_t k = 0;
	auto cross = [](const auto& o, const auto& a, const auto& b) { return (a(0) - o(0)) * (b(1) - o(1)) - (a(1) - o(1)) * (b(0) - o(0)); };
	for (std::size_t i = 0; i < p.size(); ++i) {
		while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
		h[k++] = p[i];
	}
	for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
		while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
		h[k++] = p[i];
	}
	h.resize(k - 1);
	return h;
}

double segmentDistance(const Eigen::RowVector2d& q, const Eigen::RowVector2d& a, const Eigen::RowVector2d& b) {
	const Eigen::RowVector2d ab = b - a;
	const double t = ab.squaredNorm() > 0 ? std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
	return (q - (a + t * ab)).norm();
}

// Distance to a closed polygon's outline, negative inside (even-odd).
double signedDistance(const Poly& poly, const Eigen::RowVector2d& q) {
	double d = 1e300;
	bool inside = false;
	for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
		d = std::min(d, segmentDistance(q, poly[j], poly[i]));
		if ((poly[i](1) > q(1)) != (poly[j](1) > q(1)) && q(0) < (poly[j](0) - poly[i](0)) * (q(1) - poly[i](1)) / (poly[j](1) - poly[i](1)) + poly[i](0))
			inside = !inside;
	}
	return inside ? -d : d;
}

double polylineDistance(const Poly& line, const Eigen::RowVector2d& q) {
	double d = 1e300;
	for (std::size_t i = 1; i < line.size(); ++i) d = std::min(d, segmentDistance(q, line[i - 1], line[i]));
	return d;
}

// Where a learned map may act, 0–1 over the grid (σ-feathered): the skin of the face and forehead, not
// the eyes, the brows' hair, the lips or the face's outline — there the warp's registration of a drawn
// face, not the skin, makes the difference (the maps show the hairline, the jaw line and the brows as
// edges otherwise).
std::vector<float> skinMask(const Scheme& scheme, const Points& shape, double gx0, double gy0, double scale, int gw, int gh) {
	const EyeFrame f = eyeFrame(scheme, shape);
	const double iod = f.iod * scale;  // grid pixels
	auto grid = [&](Eigen::Index i) { return Eigen::RowVector2d((shape(i, 0) - gx0) * scale, (shape(i, 1) - gy0) * scale); };
	// The face: its points from the brows down (a scheme may mark the hairline too), and the forehead to
	// 0.5 eye distances above the brows (0.7 takes in the drawn face's hairline).
	double browTop = 1e300;
	for (const BrowSpec& b : scheme.brows)
		for (int i : b.points) browTop = std::min(browTop, (shape.row(i) - f.origin).dot(f.y));
	Poly all;
	for (Eigen::Index i = 0; i < shape.rows(); ++i)
		if ((shape.row(i) - f.origin).dot(f.y) >= browTop - 1e-9) all.push_back(grid(i));
	const Eigen::RowVector2d up = -f.y * 0.5 * iod;  // the forehead, below the drawn face's hairline
	std::vector<Poly> brows;
	for (const BrowSpec& b : scheme.brows) {
		Poly line;
		for (int i : b.points) line.push_back(grid(i));
		for (const auto& q : line) all.push_back(q + up);
		brows.push_back(line);
	}
	const Poly face = convexHull(all);
	std::vector<Poly> holes;
	for (const EyeSpec& e : scheme.eyes) {
		Poly eye{grid(e.corner0)};
		for (int i : e.upper) eye.push_back(grid(i));
		eye.push_back(grid(e.corner1));
		for (auto it = e.lower.rbegin(); it != e.lower.rend(); ++it) eye.push_back(grid(*it));
		holes.push_back(eye);
	}
	for (const RegionSpec& r : scheme.regions)
		if (r.name == "lips") {
			Poly lips;
			for (std::size_t i = 0; i < r.boundary.size(); ++i)
				if (r.towards.empty() || r.towards[i] < 0) lips.push_back(grid(r.boundary[i]));
			holes.push_back(lips);
		}
	// The base of the nose (wings, nostril bases, subnasale), where the scheme names it: the drawn nostrils
	// rise with AU9 and AU10 and the warp's registration of them left dark dots above the upper lip, which
	// on a real face looked like a moustache's shadow (D73). The folds beside the wings stay.
	std::vector<Poly> noseBase;
	for (const auto& names : {std::vector<std::string>{"RN2", "RN3", "N3", "LN3", "LN2"}, std::vector<std::string>{"NS0", "NS1", "NS2", "NS3", "NS4"}}) {
		Poly line;
		for (const std::string& n : names)
			if (const int i = scheme.indexOf(n); i >= 0) line.push_back(grid(i));
		if (line.size() == names.size()) noseBase.push_back(line);
	}
	const double feather = 0.05 * iod;
	auto ramp = [&](double v) { return std::clamp(v / feather, 0.0, 1.0); };
	std::vector<float> m(std::size_t(gw) * std::size_t(gh));
	for (int y = 0; y < gh; ++y)
		for (int x = 0; x < gw; ++x) {
			const Eigen::RowVector2d q(x + 0.5, y + 0.5);
			double w = ramp(-signedDistance(face, q) - 0.08 * iod);
			for (const Poly& h : holes) w *= ramp(signedDistance(h, q) - 0.03 * iod);
			for (const Poly& b : brows) w *= ramp(polylineDistance(b, q) - 0.07 * iod);
			for (const Poly& b : noseBase) w *= ramp(polylineDistance(b, q) - 0.06 * iod);
			m[std::size_t(y) * gw + std::size_t(x)] = float(w);
		}
	return m;
}

}  // namespace

AuAppearance learnAuAppearance(const Scheme& scheme, const std::vector<AppearanceSample>& samples, const std::function<Image8(std::size_t)>& images,
                               const std::map<std::string, AuProfile>& profiles, int gridWidth) {
	// The neutral sample of each CDV; the reference: the neutral rest shape (sil, else the first neutral).
	std::map<std::string, std::size_t> neutralOf;
	for (std::size_t i = 0; i < samples.size(); ++i)
		if (samples[i].emotion == Emotion::neutralLabel() && !neutralOf.count(samples[i].cdv)) neutralOf[samples[i].cdv] = i;
	if (neutralOf.empty()) throw Error("the corpus has no neutral images: action-unit appearance is learned against them");
	const std::size_t ref = neutralOf.count("sil") ? neutralOf["sil"] : neutralOf.begin()->second;
	// The (emotion, CDV) pairs, the AUs their profiles use.
	std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (expressive sample, its CDV's neutral sample)
	std::vector<std::string> aus;
	for (std::size_t i = 0; i < samples.size(); ++i) {
		const auto p = profiles.find(samples[i].emotion);
		const auto n = neutralOf.find(samples[i].cdv);
		if (samples[i].emotion == Emotion::neutralLabel() || p == profiles.end() || n == neutralOf.end()) continue;
		pairs.emplace_back(i, n->second);
		for (const auto& [au, w] : p->second)
			if (w > 0 && std::find(aus.begin(), aus.end(), au) == aus.end()) aus.push_back(au);
	}
	if (pairs.size() < aus.size() || aus.empty()) throw Error("too few (emotion, CDV) images with a neutral of the same CDV to learn action-unit appearance");
	std::sort(aus.begin(), aus.end(), [](const std::string& a, const std::string& b) { return std::stoi(a.substr(2)) < std::stoi(b.substr(2)); });
	// The grid: the reference face's box (its points' bounds, 15 % larger), gridWidth wide.
	const Image8 refImage = images(ref);
	const int W = refImage.width, H = refImage.height;
	const Points& refShape = samples[ref].points;
	const double bx0 = refShape.col(0).minCoeff(), bx1 = refShape.col(0).maxCoeff(), by0 = refShape.col(1).minCoeff(), by1 = refShape.col(1).maxCoeff();
	const double mx = 0.15 * (bx1 - bx0), my = 0.15 * (by1 - by0);
	const double gx0 = bx0 - mx, gy0 = by0 - 2 * my;  // more room above: the forehead
	const double scale = double(gridWidth) / (bx1 - bx0 + 2 * mx);
	const int gw = gridWidth, gh = int(std::lround((by1 - by0 + 3 * my) * scale));
	const TriangleMesh mesh = delaunayTriangulation(withFrameBorder(refShape, W, H));
	PiecewiseAffineWarp toRef(mesh, withFrameBorder(refShape, W, H), W, H);
	auto warped = [&](std::size_t i) {
		PiecewiseAffineWarp w = toRef;
		w.setSource(withFrameBorder(samples[i].points, W, H));
		Image8 out(W, H, 3);
		const Image8 img = images(i);
		if (img.width != W || img.height != H) throw Error(samples[i].emotion + " " + samples[i].cdv + ": the corpus's images differ in size");
		w.apply(img, out);
		return out;
	};
	// The log luminance ratio of every pair on the grid (bilinear).
	const std::size_t P = std::size_t(gw) * std::size_t(gh);
	Eigen::MatrixXf Y(Eigen::Index(pairs.size()), Eigen::Index(P));
	std::map<std::size_t, Image8> neutralWarped;
	for (std::size_t k = 0; k < pairs.size(); ++k) {
		const Image8 e = warped(pairs[k].first);
		if (!neutralWarped.count(pairs[k].second)) neutralWarped[pairs[k].second] = warped(pairs[k].second);
		const Image8& n = neutralWarped[pairs[k].second];
		for (int gy = 0; gy < gh; ++gy)
			for (int gx = 0; gx < gw; ++gx) {
				const int x = std::clamp(int(std::lround(gx0 + (gx + 0.5) / scale - 0.5)), 0, W - 1);
				const int y = std::clamp(int(std::lround(gy0 + (gy + 0.5) / scale - 0.5)), 0, H - 1);
				const std::size_t at = (std::size_t(y) * W + std::size_t(x)) * 3;
				Y(Eigen::Index(k), Eigen::Index(std::size_t(gy) * gw + gx)) = std::log((luma(&e.data[at]) + 8.f) / (luma(&n.data[at]) + 8.f));
			}
	}
	pinEigenBlocking();  // products that round the same on every machine (D74)
	Eigen::MatrixXf X = Eigen::MatrixXf::Zero(Eigen::Index(pairs.size()), Eigen::Index(aus.size()));
	for (std::size_t k = 0; k < pairs.size(); ++k)
		for (const auto& [au, w] : profiles.at(samples[pairs[k].first].emotion))
			if (const auto it = std::find(aus.begin(), aus.end(), au); it != aus.end()) X(Eigen::Index(k), it - aus.begin()) = float(w);
	const float lambda = 0.05f * float(pairs.size()) / float(aus.size());
	const Eigen::MatrixXf XtX = X.transpose() * X + lambda * Eigen::MatrixXf::Identity(X.cols(), X.cols());
	const Eigen::MatrixXf B = XtX.ldlt().solve(X.transpose() * Y);  // AUs × pixels
	AuAppearance a;
	a.width = gw, a.height = gh, a.names = aus;
	a.anchors = appearanceAnchors(scheme, refShape);
	a.anchors.col(0) = (a.anchors.col(0).array() - gx0) * scale;
	a.anchors.col(1) = (a.anchors.col(1).array() - gy0) * scale;
	const std::vector<float> skin = skinMask(scheme, refShape, gx0, gy0, scale, gw, gh);
	for (std::size_t j = 0; j < aus.size(); ++j) {
		std::vector<float> m(P);
		for (std::size_t p = 0; p < P; ++p) m[p] = skin[p] * std::clamp(B(Eigen::Index(j), Eigen::Index(p)), -0.5f, 0.5f);
		blur(m, gw, gh, 1.5);
		a.logRatio.push_back(std::move(m));
	}
	a.source = std::to_string(pairs.size()) + " (emotion, CDV) images against their neutral";
	return a;
}

namespace {

constexpr char kMagic[8] = {'T', 'H', 'A', 'U', 'A', 'P', 'P', '1'};

}  // namespace

void saveAuAppearance(const AuAppearance& a, const std::string& path) {
	std::string s(kMagic, 8);
	auto put = [&](const void* p, std::size_t n) { s.append(static_cast<const char*>(p), n); };
	auto putInt = [&](std::int32_t v) { put(&v, 4); };
	auto putString = [&](const std::string& t) {
		putInt(std::int32_t(t.size()));
		put(t.data(), t.size());
	};
	putInt(a.width), putInt(a.height), putInt(std::int32_t(a.names.size()));
	for (int i = 0; i < kAppearanceAnchors; ++i)
		for (int c = 0; c < 2; ++c) {
			const float v = float(a.anchors(i, c));
			put(&v, 4);
		}
	putString(a.source);
	for (std::size_t j = 0; j < a.names.size(); ++j) {
		putString(a.names[j]);
		put(a.logRatio[j].data(), a.logRatio[j].size() * 4);
	}
	writeFileAtomically(path, s);
}

AuAppearance loadAuAppearance(const std::string& path, const std::vector<std::string>* only) {
	std::ifstream in(path, std::ios::binary);
	if (!in) throw Error(path, 0, "cannot open the action-unit appearance file");
	in.seekg(0, std::ios::end);
	const std::uint64_t size = std::uint64_t(std::max<std::streamoff>(0, in.tellg()));
	in.seekg(0);
	std::uint64_t at = 0;
	auto bad = [&](const std::string& what) { return Error(path, 0, "corrupt action-unit appearance file: " + what); };
	auto need = [&](std::uint64_t n) {
		if (size - at < n) throw bad("cut short");
		at += n;
	};
	auto get = [&](void* p, std::size_t n) {
		need(n);
		if (!in.read(static_cast<char*>(p), std::streamsize(n))) throw bad("cut short");
	};
	auto getInt = [&](std::int32_t lo, std::int32_t hi, const char* what) {
		std::int32_t v;
		get(&v, 4);
		if (v < lo || v > hi) throw bad(std::string(what) + " out of range");
		return v;
	};
	auto getString = [&](const char* what) {
		std::string t(std::size_t(getInt(0, 4096, what)), '\0');
		get(t.data(), t.size());
		return t;
	};
	char magic[8];
	if (size < 8) throw Error(path, 0, "not an action-unit appearance file (talkhead corpus au-appearance)");
	get(magic, 8);
	if (std::memcmp(magic, kMagic, 8) != 0) throw Error(path, 0, "not an action-unit appearance file (talkhead corpus au-appearance)");
	AuAppearance a;
	a.width = getInt(8, 4096, "width");
	a.height = getInt(8, 4096, "height");
	const int n = getInt(1, 64, "AU count");
	a.anchors.resize(kAppearanceAnchors, 2);
	for (int i = 0; i < kAppearanceAnchors; ++i)
		for (int c = 0; c < 2; ++c) {
			float v;
			get(&v, 4);
			if (!std::isfinite(v)) throw bad("an anchor is not a number");
			a.anchors(i, c) = v;
		}
	a.source = getString("source");
	const std::size_t P = std::size_t(a.width) * std::size_t(a.height);
	std::vector<std::string> seen;
	for (int j = 0; j < n; ++j) {
		const std::string name = getString("AU name");
		// Each AU once (fuzz finding: a file naming one twice gave two maps for it).
		if (std::find(seen.begin(), seen.end(), name) != seen.end()) throw bad("AU '" + safeQuote(name) + "' is given twice");
		seen.push_back(name);
		if (only && std::find(only->begin(), only->end(), name) == only->end()) {  // skipped, its size checked
			need(P * 4);
			in.seekg(std::streamoff(at));
			continue;
		}
		a.names.push_back(name);
		std::vector<float> m(P);
		get(m.data(), P * 4);
		for (float v : m)
			if (!(std::abs(v) < 10)) throw bad("a ratio of AU " + name + " is out of range");
		a.logRatio.push_back(std::move(m));
	}
	if (at != size) throw bad("trailing data");
	return a;
}

std::optional<AuAppearance> installedAuAppearance(const std::vector<std::string>& aus) {
	static std::mutex mutex;
	static std::optional<std::string> path;
	static bool looked = false;
	static AuAppearance cache;  // the AUs read so far
	static std::vector<std::string> absent;  // asked for, not in the file
	std::lock_guard<std::mutex> lock(mutex);
	if (!looked) path = findDataFile("models/au-appearance.bin"), looked = true;
	if (!path) return std::nullopt;
	std::vector<std::string> missing;
	for (const std::string& au : aus)
		if (cache.find(au) < 0 && std::find(absent.begin(), absent.end(), au) == absent.end() && std::find(missing.begin(), missing.end(), au) == missing.end())
			missing.push_back(au);
	if (!missing.empty() || cache.width == 0) {
		AuAppearance more = loadAuAppearance(*path, &missing);
		if (cache.width == 0) cache.width = more.width, cache.height = more.height, cache.anchors = more.anchors, cache.source = more.source;
		for (std::size_t j = 0; j < more.names.size(); ++j) {
			cache.names.push_back(more.names[j]);
			cache.logRatio.push_back(std::move(more.logRatio[j]));
		}
		for (const std::string& au : missing)
			if (cache.find(au) < 0) absent.push_back(au);
	}
	AuAppearance out;
	out.width = cache.width, out.height = cache.height, out.anchors = cache.anchors, out.source = cache.source;
	for (const std::string& au : aus)
		if (const int j = cache.find(au); j >= 0 && out.find(au) < 0) {
			out.names.push_back(au);
			out.logRatio.push_back(cache.logRatio[std::size_t(j)]);
		}
	return out;
}

MappedAuAppearance mapAuAppearance(const AuAppearance& a, const Scheme& scheme, const Points& shape, int x0, int y0, int width, int height,
                                   const std::vector<std::string>* only, const Image8* face) {
	MappedAuAppearance m;
	m.x0 = x0, m.y0 = y0, m.width = width, m.height = height;
	const Points anchors = appearanceAnchors(scheme, shape);
	const Eigen::Matrix<double, 2, 3> T = fitAffine(anchors, a.anchors);  // face pixels → grid
	double residual = 0;  // RMS, grid pixels: how far this face's proportions are from the learning face's
	for (Eigen::Index i = 0; i < anchors.rows(); ++i) {
		const Eigen::Vector2d g = T * Eigen::Vector3d(anchors(i, 0), anchors(i, 1), 1);
		residual += (g - a.anchors.row(i).transpose()).squaredNorm();
	}
	residual = std::sqrt(residual / double(anchors.rows()));
	// Between the eyes' centres (the first four anchors are the eyes' corners).
	auto eyeDistance = [](const Points& p) { return 0.5 * ((p.row(0) + p.row(1)) - (p.row(2) + p.row(3))).norm(); };
	const double gridIod = eyeDistance(a.anchors);
	std::vector<float> detail;  // D85: the face's own fine detail (log luminance less its blur), when it is another face
	double iod = 0;
	if (face && !face->empty() && residual > 0.05 * gridIod && width > 0 && height > 0) {
		iod = eyeDistance(anchors);
		detail.resize(std::size_t(width) * std::size_t(height));
		for (int y = 0; y < height; ++y)
			for (int x = 0; x < width; ++x) {
				const int fx = std::clamp(x0 + x, 0, face->width - 1), fy = std::clamp(y0 + y, 0, face->height - 1);
				detail[std::size_t(y) * std::size_t(width) + std::size_t(x)] = std::log(luma(face->row(fy) + 3 * fx) + 8.f);
			}
		std::vector<float> smooth = detail;
		blur(smooth, width, height, std::max(0.5, 0.04 * iod));
		for (std::size_t p = 0; p < detail.size(); ++p) detail[p] -= smooth[p];
		m.ownSkin = true;
	}
	const std::size_t P = std::size_t(width) * std::size_t(height);
	// Bilinear positions once for all AUs; outside the grid, no change.
	std::vector<std::int32_t> index(P, -1);
	std::vector<float> fx(P), fy(P);
	for (int y = 0; y < height; ++y)
		for (int x = 0; x < width; ++x) {
			const double gx = T(0, 0) * (x0 + x) + T(0, 1) * (y0 + y) + T(0, 2) - 0.5, gy = T(1, 0) * (x0 + x) + T(1, 1) * (y0 + y) + T(1, 2) - 0.5;
			if (!(gx >= 0 && gy >= 0 && gx < a.width - 1 && gy < a.height - 1)) continue;
			const std::size_t p = std::size_t(y) * width + std::size_t(x);
			const int ix = int(gx), iy = int(gy);
			index[p] = iy * a.width + ix;
			fx[p] = float(gx - ix), fy[p] = float(gy - iy);
		}
	for (std::size_t j = 0; j < a.names.size(); ++j) {
		if (only && std::find(only->begin(), only->end(), a.names[j]) == only->end()) continue;
		const std::vector<float>& src = a.logRatio[j];
		m.names.push_back(a.names[j]);
		std::vector<float> out(P, 0.f);
		for (std::size_t p = 0; p < P; ++p) {
			if (index[p] < 0) continue;
			const float* q = &src[std::size_t(index[p])];
			const float top = q[0] + fx[p] * (q[1] - q[0]), bottom = q[a.width] + fx[p] * (q[a.width + 1] - q[a.width]);
			out[p] = top + fy[p] * (bottom - top);
		}
		if (!detail.empty()) {  // D85: the broad shading, and the face's own detail deepened where the lines were
			std::vector<float> shading = out;
			blur(shading, width, height, 0.08 * iod);
			std::vector<float> strength(P);
			for (std::size_t p = 0; p < P; ++p) strength[p] = std::abs(out[p] - shading[p]);
			blur(strength, width, height, 0.08 * iod);
			for (std::size_t p = 0; p < P; ++p) {
				const float line = out[p] - shading[p];
				const float crease = line < 0 ? std::max(-0.3f, -line * line / 0.06f) : 0.f;  // the dark folds, narrowed; no pale ridges
				const float lines = std::min(1.f, strength[p] / 0.05f);
				// Where the lines are, no brightening either: a pale shading between dark folds is a band again.
				const float shade = shading[p] > 0 ? shading[p] * (1 - lines) : shading[p];
				// The skin's own fine lines deepened, by at most 4 % of its luminance: an eye's or a brow's edge
				// (a detail of 0.3) would otherwise come out drawn, as with eyeliner.
				out[p] = shade + crease + std::clamp(1.5f * lines * detail[p], -0.04f, 0.04f);
			}
		}
		m.logRatio.push_back(std::move(out));
	}
	return m;
}

std::vector<float> appearanceGain(const MappedAuAppearance& m, const std::vector<std::pair<std::string, double>>& weights) {
	std::vector<float> sum;
	for (const auto& [au, w] : weights) {
		const int j = m.find(au);
		if (j < 0 || w == 0) continue;
		if (sum.empty()) sum.assign(std::size_t(m.width) * std::size_t(m.height), 0.f);
		const std::vector<float>& r = m.logRatio[std::size_t(j)];
		for (std::size_t p = 0; p < sum.size(); ++p) sum[p] += float(w) * r[p];
	}
	for (float& v : sum) v = std::exp(v);
	return sum;
}

}  // namespace talkhead
