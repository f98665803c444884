// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

namespace talkhead {

// A shape: #points × 2 (x, y) in pixels, row-major so that data() is the thesis's interleaved shape
// vector s = [x1, y1, x2, y2, …] (Eq. 4.1). Pixel centres sit at integer coordinates.
using Points = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

// Similarity transform x' = a·x − b·y + tx, y' = b·x + a·y + ty (a = h·cosθ, b = h·sinθ).
struct Similarity {
	double a = 1, b = 0, tx = 0, ty = 0;
	double scale() const;
	double angle() const;  // radians
	Points apply(const Points& p) const;
	Similarity inverse() const;
	static Similarity fromScaleAngle(double scale, double angleRad, double tx, double ty);
};

// Weighted least-squares similarity that maps `from` onto `to`: minimises Σ w_k |T(from_k) − to_k|²
// (Cootes et al. 1995, Eq. 4.3 of Costa 2015, diagonal W with each point's weight on x and y).
// weights: one per point, ≥ 0, not all zero.
Similarity alignSimilarity(const Points& from, const Points& to, const Eigen::VectorXd& weights);

// Weighted sum of squared distances Σ w_k |p_k − q_k|².
double weightedDistance2(const Points& p, const Points& q, const Eigen::VectorXd& weights);

struct ProcrustesOptions {
	double tolerance = 1e-4;  // stop when Σ|mean_new − mean_old| over all 2k coordinates ≤ this (spec §4.2)
	int maxIterations = 100;
};

struct ProcrustesResult {
	std::vector<Points> aligned;          // every shape aligned to the final mean
	std::vector<Similarity> transforms;   // transforms[i] maps shapes[i] to aligned[i]
	Points mean;                          // normalised to the reference shape's pose
	std::size_t reference = 0;            // the "default normalizing shape": the weighted medoid
	int iterations = 0;
	bool converged = false;
	double lastChange = 0;                // Σ|Δ mean| at the last iteration
};

// Iterative generalised Procrustes alignment of spec §4.2 with a deterministic start (the medoid:
// the shape with the least summed aligned distance to all others). The mean is re-normalised to the
// reference every iteration, so it keeps that image's pixel frame.
ProcrustesResult generalizedProcrustes(const std::vector<Points>& shapes, const Eigen::VectorXd& weights,
                                       const ProcrustesOptions& options = {});

// Index of the shape nearest (Euclidean, unweighted) to `target`.
std::size_t nearestShape(const std::vector<Points>& shapes, const Points& target);

using Triangle = std::array<int, 3>;

// A triangle list over the points of a shape; the same topology serves every shape of the face.
struct TriangleMesh {
	int vertexCount = 0;
	std::vector<Triangle> triangles;  // each with signedArea > 0 (clockwise on screen, x right / y down)
};

// Delaunay triangulation (CGAL) of the points; vertices are the points' indices. Coincident points keep
// the lowest index. Triangles are oriented consistently (positive signed area in image coordinates,
// i.e. clockwise on screen).
TriangleMesh delaunayTriangulation(const Points& points);

// Signed area of triangle t of the mesh over the points (x right, y down).
double signedArea(const Points& points, const Triangle& t);

// The shape plus 8 frame-border points (4 corners and 4 edge midpoints) placed 1 px outside a
// width × height frame, so that a mesh over them covers every pixel centre.
Points withFrameBorder(const Points& points, int width, int height);
constexpr int kFrameBorderPoints = 8;

// Static anchor points around a face (decision D41). The convex hull of every point of `shapes`, each hull
// vertex moved outward by `margin` pixels (along the bisector of its two edges' outward normals, so both
// edges move by `margin`; at most 2·margin at a sharp corner), clamped into the frame [0, width − 1] ×
// [0, height − 1] and thinned so that no two anchors are closer than margin / 2. A warp mesh over shape +
// anchors + frame border keeps every triangle outside the anchors fixed: the background beyond them never
// moves. Empty when the points span no area.
Points anchorRing(const std::vector<Points>& shapes, double margin, int width, int height);

// A horizontal run of pixels [x0, x1) in row y that lies in triangle `tri`.
struct Span {
	std::int32_t y, x0, x1, tri;
};

// Rasterises the mesh at the given vertex positions into spans clipped to the frame. Pixel centres on
// shared edges belong to exactly one triangle (half-open rule on canonical edges), so a valid
// triangulation partitions the pixels it covers. Spans come triangle by triangle, each triangle's rows
// top to bottom (faster to warp than row-major order: each triangle's map and source stay in cache).
std::vector<Span> rasterizeMesh(const Points& points, const TriangleMesh& mesh, int width, int height);
// The same into an existing vector (its capacity is reused: no allocation per frame).
void rasterizeMesh(const Points& points, const TriangleMesh& mesh, int width, int height, std::vector<Span>& spans);

}  // namespace talkhead
