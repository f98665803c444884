// SPDX-License-Identifier: GPL-3.0-or-later
#include "warp/piecewise_affine.h"

#include <cmath>
#include <stdexcept>

namespace talkhead {

PiecewiseAffineWarp::PiecewiseAffineWarp(const TriangleMesh& mesh, const Points& destination, int width, int height)
    : mesh_(mesh), destination_(destination), width_(width), height_(height) {
	if (destination.rows() != mesh.vertexCount) throw std::logic_error("PiecewiseAffineWarp: vertex count differs");
	spans_ = rasterizeMesh(destination, mesh, width, height);
	inverseBasis_.resize(mesh.triangles.size() * 6);
	for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
		const Triangle& tri = mesh.triangles[t];
		double x0 = destination(tri[0], 0), y0 = destination(tri[0], 1);
		double ax = destination(tri[1], 0) - x0, ay = destination(tri[1], 1) - y0;
		double bx = destination(tri[2], 0) - x0, by = destination(tri[2], 1) - y0;
		double det = ax * by - bx * ay;
		double* m = &inverseBasis_[t * 6];
		if (std::abs(det) < 1e-12) {  // degenerate: covers no pixel centre, any map will do
			m[0] = m[1] = m[2] = m[3] = 0;
		} else {
			m[0] = by / det;
			m[1] = -bx / det;
			m[2] = -ay / det;
			m[3] = ax / det;
		}
		m[4] = x0;
		m[5] = y0;
	}
	affine_.assign(mesh.triangles.size() * 6, 0.f);
}

void PiecewiseAffineWarp::setSource(const Points& source) {
	if (source.rows() != mesh_.vertexCount) throw std::logic_error("PiecewiseAffineWarp::setSource: vertex count differs");
	for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
		const Triangle& tri = mesh_.triangles[t];
		const double* m = &inverseBasis_[t * 6];
		double sx0 = source(tri[0], 0), sy0 = source(tri[0], 1);
		double ux = source(tri[1], 0) - sx0, uy = source(tri[1], 1) - sy0;
		double vx = source(tri[2], 0) - sx0, vy = source(tri[2], 1) - sy0;
		// Barycentric (l1, l2) = Minv · (p − d0); source = s0 + l1·u + l2·v.
		double l1x = m[0], l1y = m[1], l2x = m[2], l2y = m[3];
		double a0 = ux * l1x + vx * l2x, a1 = ux * l1y + vx * l2y;
		double a3 = uy * l1x + vy * l2x, a4 = uy * l1y + vy * l2y;
		double a2 = sx0 - a0 * m[4] - a1 * m[5], a5 = sy0 - a3 * m[4] - a4 * m[5];
		float* a = &affine_[t * 6];
		a[0] = float(a0);
		a[1] = float(a1);
		a[2] = float(a2);
		a[3] = float(a3);
		a[4] = float(a4);
		a[5] = float(a5);
	}
}

std::vector<std::uint8_t> PiecewiseAffineWarp::coverage() const {
	std::vector<std::uint8_t> m(std::size_t(width_) * height_, 0);
	for (const Span& s : spans_)
		for (int x = s.x0; x < s.x1; ++x) m[std::size_t(s.y) * width_ + x] = 1;
	return m;
}

namespace {
template <class T>
inline T store(float v);
template <>
inline float store<float>(float v) {
	return v;
}
template <>
inline std::uint8_t store<std::uint8_t>(float v) {
	v += 0.5f;
	return static_cast<std::uint8_t>(v <= 0.f ? 0.f : (v >= 255.f ? 255.f : v));
}
}  // namespace

template <class In, class Out>
void PiecewiseAffineWarp::apply(const ImageT<In>& src, ImageT<Out>& dst) const {
	if (dst.width != width_ || dst.height != height_ || dst.channels != src.channels)
		throw std::logic_error("PiecewiseAffineWarp::apply: destination size differs");
	if (src.width < 1 || src.height < 1) throw std::logic_error("PiecewiseAffineWarp::apply: empty source");
	const int sw = src.width, sh = src.height, ch = src.channels;
	const float maxX = float(sw - 1), maxY = float(sh - 1);
	const In* sp = src.data.data();
	Out* dp = dst.data.data();
	const std::size_t stride = std::size_t(sw) * ch;
	forEachPixel([&](std::size_t pixel, float x, float y) {
		x = x < 0.f ? 0.f : (x > maxX ? maxX : x);
		y = y < 0.f ? 0.f : (y > maxY ? maxY : y);
		int ix = int(x), iy = int(y);
		float fx = x - float(ix), fy = y - float(iy);
		int dx = ix < sw - 1 ? ch : 0;
		std::size_t dy = iy < sh - 1 ? stride : 0;
		const In* p = sp + std::size_t(iy) * stride + std::size_t(ix) * ch;
		Out* o = dp + pixel * ch;
		const float w00 = (1 - fx) * (1 - fy), w01 = fx * (1 - fy), w10 = (1 - fx) * fy, w11 = fx * fy;
		for (int c = 0; c < ch; ++c)
			o[c] = store<Out>(w00 * float(p[c]) + w01 * float(p[c + dx]) + w10 * float(p[c + dy]) + w11 * float(p[c + dx + dy]));
	});
}

template void PiecewiseAffineWarp::apply(const ImageT<std::uint8_t>&, ImageT<std::uint8_t>&) const;
template void PiecewiseAffineWarp::apply(const ImageT<std::uint8_t>&, ImageT<float>&) const;
template void PiecewiseAffineWarp::apply(const ImageT<float>&, ImageT<float>&) const;
template void PiecewiseAffineWarp::apply(const ImageT<float>&, ImageT<std::uint8_t>&) const;

}  // namespace talkhead
