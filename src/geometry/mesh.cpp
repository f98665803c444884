// SPDX-License-Identifier: GPL-3.0-or-later
#include <algorithm>
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
		// Edges in canonical direction (from the lexicographically smaller (y, x) end) so that two
		// triangles sharing an edge compute bit-identical crossings.
		struct Edge {
			double xa, ya, xb, yb, slope;  // slope: dx/dy (the same for both triangles of an edge)
		};
		Edge edges[3];
		double ymin = 1e300, ymax = -1e300;
		for (int e = 0; e < 3; ++e) {
			int i = t[e], j = t[(e + 1) % 3];
			double xi = p(i, 0), yi = p(i, 1), xj = p(j, 0), yj = p(j, 1);
			if (yj < yi || (yj == yi && xj < xi)) {
				std::swap(xi, xj);
				std::swap(yi, yj);
			}
			edges[e] = {xi, yi, xj, yj, yj > yi ? (xj - xi) / (yj - yi) : 0.0};
			ymin = std::min(ymin, yi);
			ymax = std::max(ymax, yj);
		}
		if (!(ymax > ymin)) continue;
		int rowBegin = std::max(0, static_cast<int>(std::ceil(ymin)));
		int rowEnd = std::min(height, static_cast<int>(std::ceil(ymax)));  // rows y with ymin ≤ y < ymax
		for (int y = rowBegin; y < rowEnd; ++y) {
			double xs[2];
			int n = 0;
			for (const Edge& e : edges) {
				if (e.ya <= y && y < e.yb && n < 2) xs[n++] = e.xa + (y - e.ya) * e.slope;
			}
			if (n < 2) continue;
			double xl = std::min(xs[0], xs[1]), xr = std::max(xs[0], xs[1]);
			int x0 = std::max(0, static_cast<int>(std::ceil(xl)));  // pixels x with xl ≤ x < xr
			int x1 = std::min(width, static_cast<int>(std::ceil(xr)));
			if (x0 < x1) spans.push_back(Span{y, x0, x1, static_cast<std::int32_t>(ti)});
		}
	}
	// Row-major order (y, then x0; spans of a row never overlap): a counting sort by row, then insertion
	// by x0 within each row (a handful of spans). Scratch is per thread, so per-frame calls do not allocate.
	thread_local std::vector<std::int32_t> start;
	thread_local std::vector<Span> sorted;
	start.assign(std::size_t(std::max(height, 0)) + 1, 0);
	for (const Span& s : spans) ++start[std::size_t(s.y) + 1];
	for (std::size_t y = 1; y < start.size(); ++y) start[y] += start[y - 1];
	sorted.resize(spans.size());
	for (const Span& s : spans) sorted[std::size_t(start[std::size_t(s.y)]++)] = s;
	// start[y] is now the end of row y; insertion-sort each row by x0.
	std::size_t begin = 0;
	for (int y = 0; y < height; ++y) {
		const std::size_t end = std::size_t(start[std::size_t(y)]);
		for (std::size_t i = begin + 1; i < end; ++i) {
			const Span v = sorted[i];
			std::size_t j = i;
			for (; j > begin && sorted[j - 1].x0 > v.x0; --j) sorted[j] = sorted[j - 1];
			sorted[j] = v;
		}
		begin = end;
	}
	spans.swap(sorted);
}

}  // namespace talkhead
