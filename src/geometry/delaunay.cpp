// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL lives in this translation unit only (it costs ~10 s to compile).
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/convex_hull_2.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "base/error.h"
#include "geometry/shape.h"

namespace talkhead {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;
}  // namespace

double signedArea(const Points& p, const Triangle& t) {
	double x0 = p(t[0], 0), y0 = p(t[0], 1);
	return 0.5 * ((p(t[1], 0) - x0) * (p(t[2], 1) - y0) - (p(t[2], 0) - x0) * (p(t[1], 1) - y0));
}

TriangleMesh delaunayTriangulation(const Points& points) {
	if (points.rows() < 3) throw Error("cannot triangulate fewer than 3 points");
	std::vector<std::pair<Kernel::Point_2, int>> input;
	input.reserve(points.rows());
	for (Eigen::Index i = 0; i < points.rows(); ++i) {
		if (!std::isfinite(points(i, 0)) || !std::isfinite(points(i, 1)))
			throw Error("cannot triangulate: point " + std::to_string(i) + " is not finite");
		input.emplace_back(Kernel::Point_2(points(i, 0), points(i, 1)), static_cast<int>(i));
	}
	// Insert one by one in index order so that, of coincident points, the lowest index is kept
	// (range insertion spatially sorts and would make that choice arbitrary).
	Delaunay dt;
	for (const auto& [pt, idx] : input) {
		std::size_t before = dt.number_of_vertices();
		auto v = dt.insert(pt);
		if (dt.number_of_vertices() > before) v->info() = idx;
	}
	if (dt.dimension() < 2) throw Error("cannot triangulate: the points are collinear");
	TriangleMesh mesh;
	mesh.vertexCount = static_cast<int>(points.rows());
	for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
		Triangle t{f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()};
		if (signedArea(points, t) < 0) std::swap(t[1], t[2]);
		// Canonical order (rotation keeping orientation) so that the output does not depend on CGAL's
		// internal face order: smallest index first, then sort triangles.
		std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
		mesh.triangles.push_back(t);
	}
	std::sort(mesh.triangles.begin(), mesh.triangles.end());
	return mesh;
}

Points anchorRing(const std::vector<Points>& shapes, double margin, int width, int height) {
	std::vector<Kernel::Point_2> all, hull;
	for (const Points& s : shapes)
		for (Eigen::Index i = 0; i < s.rows(); ++i)
			if (std::isfinite(s(i, 0)) && std::isfinite(s(i, 1))) all.emplace_back(s(i, 0), s(i, 1));
	CGAL::convex_hull_2(all.begin(), all.end(), std::back_inserter(hull));
	const std::size_t n = hull.size();
	if (n < 3 || !(margin > 0)) return Points(0, 2);
	double cx = 0, cy = 0;
	for (const auto& p : hull) cx += p.x() / double(n), cy += p.y() / double(n);
	// Outward unit normal of edge i (hull[i] → hull[i + 1]): the perpendicular pointing away from the centre.
	auto normal = [&](std::size_t i) {
		const auto& a = hull[i];
		const auto& b = hull[(i + 1) % n];
		double nx = b.y() - a.y(), ny = a.x() - b.x();
		const double len = std::hypot(nx, ny);
		nx /= len, ny /= len;
		if (nx * (0.5 * (a.x() + b.x()) - cx) + ny * (0.5 * (a.y() + b.y()) - cy) < 0) nx = -nx, ny = -ny;
		return std::pair<double, double>{nx, ny};
	};
	std::vector<std::pair<double, double>> kept;
	for (std::size_t i = 0; i < n; ++i) {
		const auto [px, py] = normal((i + n - 1) % n);
		const auto [qx, qy] = normal(i);
		double dx = px + qx, dy = py + qy;
		const double len = std::hypot(dx, dy);
		if (len < 1e-9) dx = qx, dy = qy;
		else dx /= len, dy /= len;
		const double d = margin / std::max(0.5, dx * qx + dy * qy);
		const double x = std::clamp(hull[i].x() + d * dx, 0.0, double(width - 1));
		const double y = std::clamp(hull[i].y() + d * dy, 0.0, double(height - 1));
		if (std::none_of(kept.begin(), kept.end(), [&](const auto& k) { return std::hypot(k.first - x, k.second - y) < 0.5 * margin; }))
			kept.emplace_back(x, y);
	}
	Points ring(Eigen::Index(kept.size()), 2);
	for (std::size_t i = 0; i < kept.size(); ++i) ring(Eigen::Index(i), 0) = kept[i].first, ring(Eigen::Index(i), 1) = kept[i].second;
	return ring;
}

}  // namespace talkhead
