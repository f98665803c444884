// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "base/error.h"
#include "geometry/scheme.h"
#include "geometry/shape.h"
#include "test_support.h"

using namespace talkhead;

namespace {
Points immMean() {
	const Corpus& c = test::immCorpus();
	std::vector<Points> shapes;
	for (const auto& e : c.entries) shapes.push_back(e.points);
	return generalizedProcrustes(shapes, loadScheme("imm-73").weights).mean;
}

std::vector<int> coverageCount(const std::vector<Span>& spans, int w, int h) {
	std::vector<int> count(std::size_t(w) * h, 0);
	for (const auto& s : spans)
		for (int x = s.x0; x < s.x1; ++x) ++count[std::size_t(s.y) * w + x];
	return count;
}
}  // namespace

TEST(Delaunay, squareWithCentreGivesFourTriangles) {
	Points p(5, 2);
	p << 0, 0, 10, 0, 10, 10, 0, 10, 5, 5;
	TriangleMesh m = delaunayTriangulation(p);
	ASSERT_EQ(m.triangles.size(), 4u);
	for (const auto& t : m.triangles) {
		EXPECT_NEAR(signedArea(p, t), 25.0, 1e-12);
		EXPECT_TRUE(t[0] == 4 || t[1] == 4 || t[2] == 4);
	}
}

TEST(Delaunay, collinearPointsAreRejected) {
	Points p(3, 2);
	p << 0, 0, 1, 1, 2, 2;
	EXPECT_THROW(delaunayTriangulation(p), Error);
}

TEST(Delaunay, immMeanMeshIsValidAndOriented) {
	SKIP_WITHOUT_IMM();
	Points mean = immMean();
	for (const Points& pts : {mean, withFrameBorder(mean, 800, 600)}) {
		TriangleMesh m = delaunayTriangulation(pts);
		// Euler: a triangulation of n points with h on the hull has 2n − 2 − h triangles.
		std::vector<cv::Point2f> cvPts;
		for (Eigen::Index i = 0; i < pts.rows(); ++i) cvPts.emplace_back(float(pts(i, 0)), float(pts(i, 1)));
		std::vector<cv::Point2f> hull;
		cv::convexHull(cvPts, hull);
		Eigen::Index onHull = 0;  // hull vertices plus points lying on hull edges
		for (const auto& q : cvPts) onHull += std::abs(cv::pointPolygonTest(hull, q, true)) < 1e-3;
		EXPECT_EQ(m.triangles.size(), std::size_t(2 * pts.rows() - 2 - onHull));
		for (const auto& t : m.triangles) EXPECT_GT(signedArea(pts, t), 1e-3) << "degenerate or flipped triangle";
	}
}

TEST(Raster, frameMeshPartitionsEveryPixelExactlyOnce) {
	SKIP_WITHOUT_IMM();
	Points pts = withFrameBorder(immMean(), 800, 600);
	TriangleMesh m = delaunayTriangulation(pts);
	auto count = coverageCount(rasterizeMesh(pts, m, 800, 600), 800, 600);
	for (std::size_t i = 0; i < count.size(); ++i) ASSERT_EQ(count[i], 1) << "pixel " << i % 800 << "," << i / 800;
}

TEST(Raster, faceMeshCoversItsHullWithoutOverlap) {
	SKIP_WITHOUT_IMM();
	Points mean = immMean();
	TriangleMesh m = delaunayTriangulation(mean);
	auto count = coverageCount(rasterizeMesh(mean, m, 800, 600), 800, 600);
	std::vector<cv::Point2f> cvPts;
	for (Eigen::Index i = 0; i < mean.rows(); ++i) cvPts.emplace_back(float(mean(i, 0)), float(mean(i, 1)));
	std::vector<cv::Point2f> hull;
	cv::convexHull(cvPts, hull);
	int inside = 0, missed = 0;
	for (int y = 0; y < 600; ++y)
		for (int x = 0; x < 800; ++x) {
			int c = count[std::size_t(y) * 800 + x];
			ASSERT_LE(c, 1);
			double d = cv::pointPolygonTest(hull, cv::Point2f(float(x), float(y)), true);
			if (d > 0.5) {  // strictly inside the hull (pixel centres on the hull edge may go either way)
				++inside;
				if (c != 1) ++missed;
			}
			if (d < -0.5) ASSERT_EQ(c, 0);
		}
	EXPECT_GT(inside, 30000);
	EXPECT_EQ(missed, 0);
}

TEST(Raster, sharedEdgesAreNeitherDoubledNorDropped) {
	// Two triangles sharing a steep diagonal edge with fractional coordinates.
	Points p(4, 2);
	p << 0.3, 0.2, 20.7, 1.1, 19.2, 30.9, 1.4, 29.6;
	TriangleMesh m;
	m.vertexCount = 4;
	m.triangles = {{0, 1, 2}, {0, 2, 3}};
	auto count = coverageCount(rasterizeMesh(p, m, 24, 32), 24, 32);
	std::vector<cv::Point2f> quad{{0.3f, 0.2f}, {20.7f, 1.1f}, {19.2f, 30.9f}, {1.4f, 29.6f}};
	for (int y = 0; y < 32; ++y)
		for (int x = 0; x < 24; ++x) {
			double d = cv::pointPolygonTest(quad, cv::Point2f(float(x), float(y)), true);
			int c = count[std::size_t(y) * 24 + x];
			ASSERT_LE(c, 1);
			if (d > 1e-3) {
				ASSERT_EQ(c, 1) << x << "," << y;
			}
		}
}

namespace {
// Distance from p to the segment ab.
double segmentDistance(double px, double py, double ax, double ay, double bx, double by) {
	const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
	const double t = len2 > 0 ? std::clamp(((px - ax) * dx + (py - ay) * dy) / len2, 0.0, 1.0) : 0.0;
	return std::hypot(px - ax - t * dx, py - ay - t * dy);
}
}  // namespace

TEST(AnchorRing, enclosesEveryShapeByTheMarginInsideTheFrame) {
	// Two shapes of a small "face" (a diamond and the same moved): the anchors lie at least the margin
	// outside the hull of all their points, inside the frame, no two closer than margin / 2.
	Points a(4, 2), b(4, 2);
	a << 100, 50, 150, 100, 100, 150, 50, 100;
	b = a.array() + 5.0;
	const double margin = 20;
	const Points ring = anchorRing({a, b}, margin, 400, 300);
	ASSERT_GE(ring.rows(), 4);
	for (Eigen::Index i = 0; i < ring.rows(); ++i) {
		EXPECT_GE(ring(i, 0), 0);
		EXPECT_LE(ring(i, 0), 399);
		EXPECT_GE(ring(i, 1), 0);
		EXPECT_LE(ring(i, 1), 299);
		for (const Points* s : {&a, &b})
			for (Eigen::Index j = 0; j < s->rows(); ++j)
				EXPECT_GE(std::hypot(ring(i, 0) - (*s)(j, 0), ring(i, 1) - (*s)(j, 1)), margin - 1e-9);
		for (Eigen::Index j = 0; j < i; ++j) EXPECT_GE((ring.row(i) - ring.row(j)).norm(), margin / 2);
	}
	// Every shape point is inside the anchors' polygon, at least the margin from each of its edges (the
	// anchors come out in hull order).
	for (const Points* s : {&a, &b})
		for (Eigen::Index j = 0; j < s->rows(); ++j) {
			std::vector<cv::Point2f> poly;
			for (Eigen::Index i = 0; i < ring.rows(); ++i) poly.emplace_back(float(ring(i, 0)), float(ring(i, 1)));
			EXPECT_GT(cv::pointPolygonTest(poly, cv::Point2f(float((*s)(j, 0)), float((*s)(j, 1))), false), 0);
			for (Eigen::Index i = 0; i < ring.rows(); ++i) {
				const Eigen::Index k = (i + 1) % ring.rows();
				EXPECT_GE(segmentDistance((*s)(j, 0), (*s)(j, 1), ring(i, 0), ring(i, 1), ring(k, 0), ring(k, 1)), margin - 1e-6);
			}
		}
	// Near the frame's edge the anchors are clamped into it.
	const Points edge = anchorRing({a.array() - 45.0}, margin, 400, 300);
	EXPECT_EQ(edge.col(0).minCoeff(), 0);
	EXPECT_EQ(edge.col(1).minCoeff(), 0);
	// No area, no anchors.
	Points line(3, 2);
	line << 0, 0, 1, 1, 2, 2;
	EXPECT_EQ(anchorRing({line}, margin, 400, 300).rows(), 0);
}
