// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <vector>

#include "geometry/shape.h"
#include "image/image.h"

namespace talkhead {

// Piecewise-affine warp over a triangle mesh (Costa 2015 §4.1.2, §5.5). The destination shape is fixed
// at construction: its pixels are rasterised once into spans (triangle per run of pixels), so a warp is
// one pass over the destination pixels with no per-pixel triangle search. setSource() computes one
// affine map per triangle (destination pixel → source position); apply() samples the source
// bilinearly (edge-clamped) in float. Pixels outside the destination mesh are left untouched.
class PiecewiseAffineWarp {
public:
	PiecewiseAffineWarp() = default;
	PiecewiseAffineWarp(const TriangleMesh& mesh, const Points& destination, int width, int height);

	// A new destination shape: re-rasterises the mesh into the existing buffers (no allocation once they
	// are large enough). The source must be set again afterwards.
	void setDestination(const Points& destination);

	// Source shape (same vertex count as the mesh). Cheap: one 2×3 affine per triangle.
	void setSource(const Points& source);

	// Costa (2015) Eq. 5.4 in one pass: dst = (1 − w)·A warped from sourceA + w·B warped from sourceB, both
	// to this warp's destination shape (8-bit RGB; w quantised to 1/256). Sets the source (to sourceB).
	void dissolve(const Image8& a, const Points& sourceA, const Image8& b, const Points& sourceB, double w, Image8& dst);

	// 8-bit planes: the source has `channels` (1 or 2) interleaved channels (luma; or chroma as U V pairs),
	// sw × sh samples, srcStride bytes per row; channel c goes to its own destination plane dst[c]
	// (width × height, dstStride bytes per row). Same fixed-point bilinear kernel as the RGB warp. The AVX2
	// kernel (chosen at run time; TALKHEAD_SCALAR_WARP forces the scalar one) and the scalar kernel give the
	// same bytes (D74); `scalar` asks for the scalar one here (tests compare the two).
	void applyPlanes(const std::uint8_t* src, int sw, int sh, std::size_t srcStride, int channels, std::uint8_t* const* dst,
	                 std::size_t dstStride, bool scalar = false) const;

	// Restricts the warp to the destination pixels in [x0, x1) × [y0, y1); the others are left alone.
	void clipSpans(int x0, int y0, int x1, int y1);

	// dst must be width × height with src's channel count; src may have any size.
	template <class In, class Out>
	void apply(const ImageT<In>& src, ImageT<Out>& dst) const;
	// The same warp of an 8-bit RGB image through a Lanczos-3 kernel (6 × 6 taps at 1/1024 of a pixel,
	// weights summing to one, the source's edge repeated), clamped to [0, 255]: it keeps 0.95 of a face's
	// fine detail where bilinear keeps 0.65 (issue 47, D80). Scalar and deterministic (the kernel's table is
	// made with plain arithmetic, no libm); about 9× the bilinear warp's time: for a model's build, not frames.
	void applyLanczos3(const Image8& src, ImageT<float>& dst) const;

	const std::vector<Span>& spans() const { return spans_; }
	int width() const { return width_; }
	int height() const { return height_; }
	const TriangleMesh& mesh() const { return mesh_; }
	const Points& destination() const { return destination_; }
	// Row-major coverage mask of the destination frame (1 = inside the mesh).
	std::vector<std::uint8_t> coverage() const;

	// Calls f(pixelIndex, sx, sy) for each covered destination pixel, in span order (triangle by triangle).
	template <class F>
	void forEachPixel(F&& f) const {
		for (const Span& s : spans_) {
			const float* a = &affine_[std::size_t(s.tri) * 6];
			const std::size_t base = std::size_t(s.y) * width_;
			const float rx = a[1] * s.y + a[2], ry = a[4] * s.y + a[5];
			for (int x = s.x0; x < s.x1; ++x) f(base + x, a[0] * x + rx, a[3] * x + ry);
		}
	}

private:
	TriangleMesh mesh_;
	Points destination_;
	int width_ = 0, height_ = 0;
	std::vector<Span> spans_;
	std::vector<double> inverseBasis_;  // per triangle: inverse of [d1−d0, d2−d0] (4) and d0 (2)
	std::vector<float> affine_;         // per triangle: sx = a0·x + a1·y + a2, sy = a3·x + a4·y + a5
	std::vector<float> affineA_;        // dissolve(): the first source's maps
};

}  // namespace talkhead
