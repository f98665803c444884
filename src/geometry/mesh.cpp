// SPDX-License-Identifier: GPL-3.0-or-later
#include <algorithm>
#include <array>
#include <cmath>

#include "geometry/shape.h"

namespace talkhead {

Points withFrameBorder(const Points& points, int width, int height) {
	Points out(points.rows() + kFrameBorderPoints, 2);
	out.topRows(points.rows()) = points;
	const double x0 = -1, y0 = -1, x1 = width, y1 = height;
	const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
	const double border[kFrameBorderPoints][2] = {{x0, y0}, {xm, y0}, {x1, y0}, {x1, ym},
	                                              {x1, y1}, {xm, y1}, {x0, y1}, {x0, ym}};
	for (int i = 0; i < kFrameBorderPoints; ++i) {
		out(points.rows() + i, 0) = border[i][0];
		out(points.rows() + i, 1) = border[i][1];
	}
	return out;
}

std::vector<Span> rasterizeMesh(const Points& p, const TriangleMesh& mesh, int width, int height) {
	std::vector<Span> spans;
	rasterizeMesh(p, mesh, width, height, spans);
	return spans;
}

void rasterizeMesh(const Points& p, const TriangleMesh& mesh, int width, int height, std::vector<Span>& spans) {
	spans.clear();
	for (std::size_t ti = 0; ti < mesh.triangles.size(); ++ti) {
		const Triangle& t = mesh.triangles[ti];
		// Vertices in lexicographic (y, x) order, so that each edge runs from its smaller end and two
		// triangles sharing an edge compute bit-identical crossings: x = xa + (y − ya)·slope.
		std::array<std::array<double, 2>, 3> v;
		for (int e = 0; e < 3; ++e) v[std::size_t(e)] = {p(t[std::size_t(e)], 0), p(t[std::size_t(e)], 1)};
		auto before = [](const std::array<double, 2>& a, const std::array<double, 2>& b) { return a[1] < b[1] || (a[1] == b[1] && a[0] < b[0]); };
		if (before(v[1], v[0])) std::swap(v[0], v[1]);
		if (before(v[2], v[1])) std::swap(v[1], v[2]);
		if (before(v[1], v[0])) std::swap(v[0], v[1]);
		if (!(v[2][1] > v[0][1])) continue;
		auto slope = [](const std::array<double, 2>& a, const std::array<double, 2>& b) { return b[1] > a[1] ? (b[0] - a[0]) / (b[1] - a[1]) : 0.0; };
		const double sLong = slope(v[0], v[2]), sTop = slope(v[0], v[1]), sBottom = slope(v[1], v[2]);
		// Rows y with y0 ≤ y < y2; the short edge is v0→v1 while y < y1, then v1→v2.
		const int rowBegin = std::max(0, static_cast<int>(std::ceil(v[0][1])));
		const int rowEnd = std::min(height, static_cast<int>(std::ceil(v[2][1])));
		for (int y = rowBegin; y < rowEnd; ++y) {
			const double a = v[0][0] + (y - v[0][1]) * sLong;
			const double b = y < v[1][1] ? v[0][0] + (y - v[0][1]) * sTop : v[1][0] + (y - v[1][1]) * sBottom;
			const double xl = std::min(a, b), xr = std::max(a, b);
			const int x0 = std::max(0, static_cast<int>(std::ceil(xl)));  // pixels x with xl ≤ x < xr
			const int x1 = std::min(width, static_cast<int>(std::ceil(xr)));
			if (x0 < x1) spans.push_back(Span{y, x0, x1, static_cast<std::int32_t>(ti)});
		}
	}
}

}  // namespace talkhead
