// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL lives in this translation unit only (it costs ~10 s to compile).
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
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

}  // namespace talkhead
