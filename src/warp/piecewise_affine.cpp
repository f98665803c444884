// SPDX-License-Identifier: GPL-3.0-or-later
#include "warp/piecewise_affine.h"

#include <emmintrin.h>  // SSE2: part of the x86-64 baseline
#include <immintrin.h>  // AVX2 kernels, compiled with a target attribute and dispatched at run time

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <stdexcept>

namespace talkhead {

PiecewiseAffineWarp::PiecewiseAffineWarp(const TriangleMesh& mesh, const Points& destination, int width, int height)
    : mesh_(mesh), width_(width), height_(height) {
	setDestination(destination);
}

void PiecewiseAffineWarp::setDestination(const Points& destination) {
	if (destination.rows() != mesh_.vertexCount) throw std::logic_error("PiecewiseAffineWarp: vertex count differs");
	destination_ = destination;
	rasterizeMesh(destination, mesh_, width_, height_, spans_);
	inverseBasis_.resize(mesh_.triangles.size() * 6);
	for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
		const Triangle& tri = mesh_.triangles[t];
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
	affine_.assign(mesh_.triangles.size() * 6, 0.f);
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

void PiecewiseAffineWarp::clipSpans(int x0, int y0, int x1, int y1) {
	std::vector<Span> kept;
	for (Span s : spans_) {
		if (s.y < y0 || s.y >= y1) continue;
		s.x0 = std::max(s.x0, x0);
		s.x1 = std::min(s.x1, x1);
		if (s.x0 < s.x1) kept.push_back(s);
	}
	spans_.swap(kept);
}

std::vector<std::uint8_t> PiecewiseAffineWarp::coverage() const {
	std::vector<std::uint8_t> m(std::size_t(width_) * height_, 0);
	for (const Span& s : spans_)
		for (int x = s.x0; x < s.x1; ++x) m[std::size_t(s.y) * width_ + x] = 1;
	return m;
}

namespace {
// Round half away from zero, inline (std::llround is a libm call, and it ran per span).
inline std::int64_t roundToInt64(double v) { return std::int64_t(v < 0 ? v - 0.5 : v + 0.5); }

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

namespace {

// Bilinear sample at (x, y), clamped to the image: the slow path for spans that touch the border.
template <class In, class Out>
inline void sampleClamped(const In* sp, int sw, int sh, int ch, std::size_t stride, float x, float y, Out* o) {
	const float maxX = float(sw - 1), maxY = float(sh - 1);
	x = x < 0.f ? 0.f : (x > maxX ? maxX : x);
	y = y < 0.f ? 0.f : (y > maxY ? maxY : y);
	int ix = int(x), iy = int(y);
	float fx = x - float(ix), fy = y - float(iy);
	int dx = ix < sw - 1 ? ch : 0;
	std::size_t dy = iy < sh - 1 ? stride : 0;
	const In* p = sp + std::size_t(iy) * stride + std::size_t(ix) * ch;
	for (int c = 0; c < ch; ++c) {
		float top = float(p[c]) + fx * (float(p[c + dx]) - float(p[c]));
		float bottom = float(p[c + dy]) + fx * (float(p[c + dx + dy]) - float(p[c + dy]));
		o[c] = store<Out>(top + fy * (bottom - top));
	}
}

// A bilinear mix of values in [0, 255] stays in range: no clamping (and no branches) needed.
template <class T>
inline T storeInRange(float v);
template <>
inline float storeInRange<float>(float v) {
	return v;
}
template <>
inline std::uint8_t storeInRange<std::uint8_t>(float v) {
	return static_cast<std::uint8_t>(int(v + 0.5f));
}


// The run [fa, fb) of the span's pixels whose 2×2 source neighbourhood (plus the 4-byte loads) lies
// inside a sw × sh source under the affine map a; fa = fb = x1 when there is none.
// The run's positions are stepped in 32.32 fixed point from a double start, which can round to just below
// the float test's 0 (a row −1 read): the run keeps 1e-3 px from every edge, low as high.
inline void interiorRun(const float* a, const Span& s, int sw, int sh, int& fa, int& fb) {
	constexpr float lo = 1e-3f;
	const float limX = float(sw - 2) - 1e-3f, limY = float(sh - 1) - 1e-3f;
	const float rx = a[1] * float(s.y) + a[2], ry = a[4] * float(s.y) + a[5];
	fa = s.x0;
	fb = s.x1;
	// The usual case: both ends inside, hence (the map is affine along the run) every pixel between.
	const auto inside = [&](int x) {
		const float u = a[0] * float(x) + rx, v = a[3] * float(x) + ry;
		return u >= lo && u < limX && v >= lo && v < limY;
	};
	if (fb > fa && inside(fa) && inside(fb - 1)) return;
	auto limit = [&](float slope, float offset, float lim) {
		if (std::abs(slope) < 1e-9f) {
			if (!(offset >= lo && offset < lim)) fb = fa;
			return;
		}
		float t0 = (lo - offset) / slope, t1 = (lim - offset) / slope;
		if (slope < 0) std::swap(t0, t1);
		fa = std::max(fa, int(std::ceil(std::max(t0, -1e9f))) + 1);
		fb = std::min(fb, int(std::floor(std::min(t1, 1e9f))) - 1);
	};
	limit(a[0], rx, limX);
	limit(a[3], ry, limY);
	auto inBounds = [&](int x) {
		const float u = a[0] * float(x) + rx, v = a[3] * float(x) + ry;
		return u >= lo && u < limX && v >= lo && v < limY;
	};
	if (fb <= fa || !inBounds(fa) || !inBounds(fb - 1)) fa = fb = s.x1;
}

// One 8-bit RGB bilinear sample in SSE2 fixed point (32.32 position): 32-bit lanes r g b . scaled by 2¹⁴.
inline __m128i sampleRgb8(const std::uint8_t* sp, std::size_t stride, std::int64_t u, std::int64_t v) {
	const __m128i zero = _mm_setzero_si128();
	auto load32 = [](const std::uint8_t* p) {
		std::int32_t x;
		std::memcpy(&x, p, 4);
		return _mm_cvtsi32_si128(x);
	};
	const int ix = int(u >> 32), iy = int(v >> 32);
	const int wx = int(u >> 25) & 127, wy = int(v >> 25) & 127;
	const std::uint8_t* p = sp + std::size_t(iy) * stride + std::size_t(ix) * 3;
	const std::uint8_t* q = p + stride;
	const __m128i wxv = _mm_set1_epi32((wx << 16) | (128 - wx));
	const __m128i wyv = _mm_set1_epi32((wy << 16) | (128 - wy));
	__m128i top = _mm_madd_epi16(_mm_unpacklo_epi8(_mm_unpacklo_epi8(load32(p), load32(p + 3)), zero), wxv);
	__m128i bottom = _mm_madd_epi16(_mm_unpacklo_epi8(_mm_unpacklo_epi8(load32(q), load32(q + 3)), zero), wxv);
	__m128i tb = _mm_unpacklo_epi16(_mm_packs_epi32(top, top), _mm_packs_epi32(bottom, bottom));
	return _mm_madd_epi16(tb, wyv);
}


// Interior run for 8-bit RGB → 8-bit RGB in SSE2 fixed point: 7-bit bilinear weights (1/128 px),
// each pixel's three channels in one register. Callers guarantee that the 2×2 neighbourhood plus one
// byte (the 4-byte loads) lies inside the source for every x in [xa, xb).
inline void bilinearRunRgb8(const std::uint8_t* sp, std::size_t stride, const float* a, float rx, float ry, int xa, int xb,
                            std::uint8_t* o) {
	const __m128i zero = _mm_setzero_si128(), round = _mm_set1_epi32(1 << 13);
	// Source position in 32.32 fixed point, stepped along the run (drift < 1e-6 px over any run).
	constexpr double one = 4294967296.0;
	std::int64_t u = roundToInt64((double(a[0]) * xa + rx) * one), v = roundToInt64((double(a[3]) * xa + ry) * one);
	const std::int64_t du = roundToInt64(double(a[0]) * one), dv = roundToInt64(double(a[3]) * one);
	for (int x = xa; x < xb; ++x, o += 3, u += du, v += dv) {
		__m128i r = _mm_srai_epi32(_mm_add_epi32(sampleRgb8(sp, stride, u, v), round), 14);
		r = _mm_packus_epi16(_mm_packs_epi32(r, r), zero);
		const std::uint32_t rgb = std::uint32_t(_mm_cvtsi128_si32(r));
		o[0] = std::uint8_t(rgb);
		o[1] = std::uint8_t(rgb >> 8);
		o[2] = std::uint8_t(rgb >> 16);
	}
}
}  // namespace

void PiecewiseAffineWarp::dissolve(const Image8& a, const Points& sourceA, const Image8& b, const Points& sourceB, double w, Image8& dst) {
	if (dst.width != width_ || dst.height != height_ || a.channels != 3 || b.channels != 3 || dst.channels != 3)
		throw std::logic_error("PiecewiseAffineWarp::dissolve: sizes differ");
	setSource(sourceA);
	affineA_ = affine_;
	setSource(sourceB);
	const int wb = int(std::lround(std::clamp(w, 0.0, 1.0) * 256)), wa = 256 - wb;
	const std::size_t strideA = std::size_t(a.width) * 3, strideB = std::size_t(b.width) * 3;
	const __m128i weights = _mm_set1_epi32((wb << 16) | wa);
	const __m128i zero = _mm_setzero_si128(), round14 = _mm_set1_epi32(1 << 13), round8 = _mm_set1_epi32(128);
	constexpr double one = 4294967296.0;
	for (const Span& s : spans_) {
		const float* ma = &affineA_[std::size_t(s.tri) * 6];
		const float* mb = &affine_[std::size_t(s.tri) * 6];
		int aa, ab, ba, bb;
		interiorRun(ma, s, a.width, a.height, aa, ab);
		interiorRun(mb, s, b.width, b.height, ba, bb);
		int fa = std::max(aa, ba), fb = std::min(ab, bb);
		if (fb <= fa) fa = fb = s.x1;
		std::uint8_t* o = dst.data.data() + (std::size_t(s.y) * width_ + s.x0) * 3;
		auto slow = [&](int x) {
			std::uint8_t pa[3], pb[3];
			sampleClamped(a.data.data(), a.width, a.height, 3, strideA, ma[0] * float(x) + ma[1] * float(s.y) + ma[2], ma[3] * float(x) + ma[4] * float(s.y) + ma[5], pa);
			sampleClamped(b.data.data(), b.width, b.height, 3, strideB, mb[0] * float(x) + mb[1] * float(s.y) + mb[2], mb[3] * float(x) + mb[4] * float(s.y) + mb[5], pb);
			for (int c = 0; c < 3; ++c) o[c] = std::uint8_t((pa[c] * wa + pb[c] * wb + 128) >> 8);
			o += 3;
		};
		for (int x = s.x0; x < fa; ++x) slow(x);
		if (fb > fa) {
			const double rxa = double(ma[1]) * s.y + ma[2], rya = double(ma[4]) * s.y + ma[5];
			const double rxb = double(mb[1]) * s.y + mb[2], ryb = double(mb[4]) * s.y + mb[5];
			std::int64_t ua = roundToInt64((double(ma[0]) * fa + rxa) * one), va = roundToInt64((double(ma[3]) * fa + rya) * one);
			std::int64_t ub = roundToInt64((double(mb[0]) * fa + rxb) * one), vb = roundToInt64((double(mb[3]) * fa + ryb) * one);
			const std::int64_t dua = roundToInt64(double(ma[0]) * one), dva = roundToInt64(double(ma[3]) * one);
			const std::int64_t dub = roundToInt64(double(mb[0]) * one), dvb = roundToInt64(double(mb[3]) * one);
			for (int x = fa; x < fb; ++x, o += 3, ua += dua, va += dva, ub += dub, vb += dvb) {
				__m128i ra = _mm_srai_epi32(_mm_add_epi32(sampleRgb8(a.data.data(), strideA, ua, va), round14), 14);
				__m128i rb = _mm_srai_epi32(_mm_add_epi32(sampleRgb8(b.data.data(), strideB, ub, vb), round14), 14);
				__m128i ab16 = _mm_unpacklo_epi16(_mm_packs_epi32(ra, ra), _mm_packs_epi32(rb, rb));  // ra rb ga gb ba bb . .
				__m128i r = _mm_srai_epi32(_mm_add_epi32(_mm_madd_epi16(ab16, weights), round8), 8);
				r = _mm_packus_epi16(_mm_packs_epi32(r, r), zero);
				const std::uint32_t rgb = std::uint32_t(_mm_cvtsi128_si32(r));
				o[0] = std::uint8_t(rgb);
				o[1] = std::uint8_t(rgb >> 8);
				o[2] = std::uint8_t(rgb >> 16);
			}
		}
		for (int x = std::max(fa, fb); x < s.x1; ++x) slow(x);
	}
}

template <class In, class Out>
void PiecewiseAffineWarp::apply(const ImageT<In>& src, ImageT<Out>& dst) const {
	if (dst.width != width_ || dst.height != height_ || dst.channels != src.channels)
		throw std::logic_error("PiecewiseAffineWarp::apply: destination size differs");
	if (src.width < 1 || src.height < 1) throw std::logic_error("PiecewiseAffineWarp::apply: empty source");
	const int sw = src.width, sh = src.height, ch = src.channels;
	const In* sp = src.data.data();
	Out* dp = dst.data.data();
	const std::size_t stride = std::size_t(sw) * ch;
	for (const Span& s : spans_) {
		const float* a = &affine_[std::size_t(s.tri) * 6];
		const float rx = a[1] * float(s.y) + a[2], ry = a[4] * float(s.y) + a[5];
		Out* o = dp + (std::size_t(s.y) * width_ + s.x0) * ch;
		// The map is affine along the span: the run [fa, fb) needs no clamping; the ends use the clamped path.
		int fa, fb;
		interiorRun(a, s, sw, sh, fa, fb);
		for (int x = s.x0; x < fa; ++x, o += ch) sampleClamped(sp, sw, sh, ch, stride, a[0] * float(x) + rx, a[3] * float(x) + ry, o);
		if constexpr (std::is_same_v<In, std::uint8_t> && std::is_same_v<Out, std::uint8_t>) {
			if (ch == 3 && fb > fa) {
				bilinearRunRgb8(sp, stride, a, rx, ry, fa, fb, o);
				o += std::size_t(fb - fa) * 3;
			} else {
				for (int x = fa; x < fb; ++x, o += ch)
					sampleClamped(sp, sw, sh, ch, stride, a[0] * float(x) + rx, a[3] * float(x) + ry, o);
			}
		} else if (ch == 3) {
			for (int x = fa; x < fb; ++x, o += 3) {
				const float fxs = a[0] * float(x) + rx, fys = a[3] * float(x) + ry;
				const int ix = int(fxs), iy = int(fys);
				const float fx = fxs - float(ix), fy = fys - float(iy);
				const In* p = sp + std::size_t(iy) * stride + std::size_t(ix) * 3;
				const In* q = p + stride;
				for (int c = 0; c < 3; ++c) {
					const float top = float(p[c]) + fx * (float(p[c + 3]) - float(p[c]));
					const float bottom = float(q[c]) + fx * (float(q[c + 3]) - float(q[c]));
					o[c] = storeInRange<Out>(top + fy * (bottom - top));
				}
			}
		} else {
			for (int x = fa; x < fb; ++x, o += ch) sampleClamped(sp, sw, sh, ch, stride, a[0] * float(x) + rx, a[3] * float(x) + ry, o);
		}
		for (int x = std::max(fa, fb); x < s.x1; ++x, o += ch)
			sampleClamped(sp, sw, sh, ch, stride, a[0] * float(x) + rx, a[3] * float(x) + ry, o);
	}
}

namespace {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define TALKHEAD_AVX2 1
// The plane kernel's vector loop, eight pixels at a time over [x, fb): the scalar kernel's 32.32 fixed-point
// positions and 7-bit weights, so both give the same bytes (D74); returns fb. Compiled for AVX2 + FMA
// whatever the build's -march, and called only when the CPU has them (chosen at run time).
// The low n (≤ 8) bytes of v to o.
inline void storeUpTo8(std::uint8_t* o, __m128i v, int n) {
	if (n == 8) {
		_mm_storel_epi64(reinterpret_cast<__m128i*>(o), v);
	} else {
		alignas(16) std::uint8_t tmp[16];
		_mm_store_si128(reinterpret_cast<__m128i*>(tmp), v);
		std::memcpy(o, tmp, std::size_t(n));
	}
}

// The 32.32 fixed-point positions of eight pixels (two registers of four 64-bit lanes) split into their
// integer parts and 7-bit weights, exactly as the scalar kernel reads them (u >> 32, (u >> 25) & 127).
__attribute__((target("avx2,fma"), always_inline)) inline void splitFixed(__m256i lo, __m256i hi, __m256i& whole, __m256i& weight) {
	const __m256i odd = _mm256_setr_epi32(1, 3, 5, 7, 0, 2, 4, 6);  // high dwords low, low dwords high
	const __m256i pl = _mm256_permutevar8x32_epi32(lo, odd), ph = _mm256_permutevar8x32_epi32(hi, odd);
	whole = _mm256_permute2x128_si256(pl, ph, 0x20);
	weight = _mm256_srli_epi32(_mm256_permute2x128_si256(pl, ph, 0x31), 25);
}

__attribute__((target("avx2,fma"), always_inline)) inline int planeRunAvx2(const std::uint8_t* sp, int sw, std::size_t stride, int ch, const float* a, float rx, float ry,
                                                    int x, int fb, std::uint8_t* const* dst, std::size_t row) {
	const __m256i byte = _mm256_set1_epi32(0xFF), k128 = _mm256_set1_epi32(128);
	const __m256i strideV = _mm256_set1_epi32(int(stride));
	const __m256i round = _mm256_set1_epi32(1 << 13);
	const int* base = reinterpret_cast<const int*>(sp);
	const int* below = reinterpret_cast<const int*>(sp + stride);
	const bool window = sw >= 16 && stride >= 16;  // 16-byte row loads stay inside the source
	const __m256i one32 = _mm256_set1_epi32(1);
	// Gathered dwords → bytes 0 and 1 of each (the pixel and its right neighbour) packed low.
	const __m256i pairLow = _mm256_setr_epi8(0, 1, 4, 5, 8, 9, 12, 13, -1, -1, -1, -1, -1, -1, -1, -1, 0, 1, 4, 5, 8, 9, 12, 13, -1, -1, -1,
	                                         -1, -1, -1, -1, -1);
	const __m256i pack2 = _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7);
	// Positions in the scalar kernel's 32.32 fixed point, from the same start and step, so both kernels
	// sample the same pixels with the same weights: frames do not depend on the CPU (D74). Lane k of a
	// group holds uStart + k·du, stepped by 8·du per group (integer adds: exact).
	constexpr double one = 4294967296.0;
	const int x0 = x;
	const std::int64_t uStart = roundToInt64((double(a[0]) * x + rx) * one), vStart = roundToInt64((double(a[3]) * x + ry) * one);
	const std::int64_t du = roundToInt64(double(a[0]) * one), dv = roundToInt64(double(a[3]) * one);
	__m256i uLo = _mm256_setr_epi64x(uStart, uStart + du, uStart + 2 * du, uStart + 3 * du), uHi = _mm256_add_epi64(uLo, _mm256_set1_epi64x(4 * du));
	__m256i vLo = _mm256_setr_epi64x(vStart, vStart + dv, vStart + 2 * dv, vStart + 3 * dv), vHi = _mm256_add_epi64(vLo, _mm256_set1_epi64x(4 * dv));
	const __m256i du8 = _mm256_set1_epi64x(8 * du), dv8 = _mm256_set1_epi64x(8 * dv);
	// Whole groups of eight, then the span's last 1–7 pixels as one group whose lanes past the end repeat
	// the last pixel (so every sample stays inside the source) and are not stored.
	for (; x < fb; x += 8) {
		const int n = std::min(8, fb - x);
		__m256i iu, iv, wx, wy;
		if (n == 8) {
			splitFixed(uLo, uHi, iu, wx);
			splitFixed(vLo, vHi, iv, wy);
			uLo = _mm256_add_epi64(uLo, du8), uHi = _mm256_add_epi64(uHi, du8);
			vLo = _mm256_add_epi64(vLo, dv8), vHi = _mm256_add_epi64(vHi, dv8);
		} else {
			alignas(32) std::int64_t us[8], vs[8];
			for (int k = 0; k < 8; ++k) {
				const std::int64_t i = std::min(k, n - 1) + (x - x0);
				us[k] = uStart + i * du;
				vs[k] = vStart + i * dv;
			}
			splitFixed(_mm256_load_si256(reinterpret_cast<const __m256i*>(us)), _mm256_load_si256(reinterpret_cast<const __m256i*>(us + 4)), iu, wx);
			splitFixed(_mm256_load_si256(reinterpret_cast<const __m256i*>(vs)), _mm256_load_si256(reinterpret_cast<const __m256i*>(vs + 4)), iv, wy);
		}
		const __m256i lx = _mm256_sub_epi32(k128, wx), ly = _mm256_sub_epi32(k128, wy);
		if (ch == 1) {
			// The 2×2 neighbourhoods of the eight pixels: from one 16-byte window of two rows when
			// they share a row and span ≤ 15 bytes (a near-identity map, the usual case here), picked
			// with a byte shuffle; else gathered. Same integer arithmetic either way.
			__m256i top, bottom;
			const int iy0 = _mm256_cvtsi256_si32(iv), u0 = _mm256_cvtsi256_si32(iu), u7 = _mm256_extract_epi32(iu, 7);
			const int umin = std::min(u0, u7), umax = std::max(u0, u7);
			const __m256i wpair = _mm256_or_si256(_mm256_slli_epi32(wx, 16), lx);  // (128 − wx, wx) as int16 pairs
			if (window && umax - umin <= 14 && _mm256_movemask_epi8(_mm256_cmpeq_epi32(iv, _mm256_set1_epi32(iy0))) == -1) {
				const std::uint8_t* p = sp + std::size_t(iy0) * stride + std::size_t(umin);
				const __m128i row0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
				const __m128i row1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + stride));
				const __m256i idx = _mm256_sub_epi32(iu, _mm256_set1_epi32(umin));
				const __m256i pairs = _mm256_or_si256(idx, _mm256_slli_epi32(_mm256_add_epi32(idx, one32), 8));
				const __m128i m = _mm_packus_epi32(_mm256_castsi256_si128(pairs), _mm256_extracti128_si256(pairs, 1));
				top = _mm256_madd_epi16(_mm256_cvtepu8_epi16(_mm_shuffle_epi8(row0, m)), wpair);
				bottom = _mm256_madd_epi16(_mm256_cvtepu8_epi16(_mm_shuffle_epi8(row1, m)), wpair);
			} else {
				const __m256i off = _mm256_add_epi32(_mm256_mullo_epi32(iv, strideV), iu);
				const __m256i p = _mm256_i32gather_epi32(base, off, 1), q = _mm256_i32gather_epi32(below, off, 1);
				top = _mm256_madd_epi16(_mm256_cvtepu8_epi16(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
				                            _mm256_shuffle_epi8(p, pairLow), pack2))),
				                        wpair);
				bottom = _mm256_madd_epi16(_mm256_cvtepu8_epi16(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
				                               _mm256_shuffle_epi8(q, pairLow), pack2))),
				                           wpair);
			}
			const __m256i tb = _mm256_or_si256(top, _mm256_slli_epi32(bottom, 16));  // both < 2¹⁵
			const __m256i wv = _mm256_or_si256(_mm256_slli_epi32(wy, 16), ly);
			__m256i r = _mm256_srli_epi32(_mm256_add_epi32(_mm256_madd_epi16(tb, wv), round), 14);
			r = _mm256_packus_epi32(r, r);                       // 16-bit, per 128-bit lane
			r = _mm256_permute4x64_epi64(r, 0x08);               // lanes' low halves together
			r = _mm256_packus_epi16(r, r);
			storeUpTo8(dst[0] + row + std::size_t(x), _mm256_castsi256_si128(r), n);
		} else {
			// Each pixel's U V pairs at (iu, iv) and (iu + 1, iv), and the row below, as one dword per lane:
			// from two 16-byte windows per row (lanes 0–3 and 4–7, one per 128-bit half) when the eight
			// share a source row and each half spans ≤ 6 pairs (a near-identity map, the usual case), picked
			// with a byte shuffle; else gathered.
			__m256i p, q;
			const int iy0 = _mm256_cvtsi256_si32(iv);
			const int u0 = _mm256_cvtsi256_si32(iu), u3 = _mm256_extract_epi32(iu, 3), u4 = _mm256_extract_epi32(iu, 4),
			          u7 = _mm256_extract_epi32(iu, 7);
			const int loMin = std::min(u0, u3), hiMin = std::min(u4, u7);
			if (std::max(u0, u3) - loMin <= 6 && std::max(u4, u7) - hiMin <= 6 && std::max(loMin, hiMin) + 8 <= sw &&
			    _mm256_movemask_epi8(_mm256_cmpeq_epi32(iv, _mm256_set1_epi32(iy0))) == -1) {
				const std::uint8_t* r0 = sp + std::size_t(iy0) * stride;
				const __m256i top = _mm256_loadu2_m128i(reinterpret_cast<const __m128i*>(r0 + 2 * hiMin), reinterpret_cast<const __m128i*>(r0 + 2 * loMin));
				const __m256i bot = _mm256_loadu2_m128i(reinterpret_cast<const __m128i*>(r0 + stride + 2 * hiMin),
				                                        reinterpret_cast<const __m128i*>(r0 + stride + 2 * loMin));
				const __m256i d2 = _mm256_slli_epi32(_mm256_sub_epi32(iu, _mm256_setr_epi32(loMin, loMin, loMin, loMin, hiMin, hiMin, hiMin, hiMin)), 1);
				const __m256i m = _mm256_add_epi32(_mm256_mullo_epi32(d2, _mm256_set1_epi32(0x01010101)), _mm256_set1_epi32(0x03020100));
				p = _mm256_shuffle_epi8(top, m);
				q = _mm256_shuffle_epi8(bot, m);
			} else {
				const __m256i off = _mm256_add_epi32(_mm256_mullo_epi32(iv, strideV), _mm256_add_epi32(iu, iu));
				p = _mm256_i32gather_epi32(base, off, 1);
				q = _mm256_i32gather_epi32(below, off, 1);
			}
			__m256i res[2];
			for (int c = 0; c < 2; ++c) {
				const int sh0 = 8 * c, sh1 = 8 * c + 16;
				const __m256i p0 = _mm256_and_si256(_mm256_srl_epi32(p, _mm_cvtsi32_si128(sh0)), byte);
				const __m256i p1 = _mm256_and_si256(_mm256_srl_epi32(p, _mm_cvtsi32_si128(sh1)), byte);
				const __m256i q0 = _mm256_and_si256(_mm256_srl_epi32(q, _mm_cvtsi32_si128(sh0)), byte);
				const __m256i q1 = _mm256_and_si256(_mm256_srl_epi32(q, _mm_cvtsi32_si128(sh1)), byte);
				const __m256i top = _mm256_add_epi32(_mm256_mullo_epi32(p0, lx), _mm256_mullo_epi32(p1, wx));
				const __m256i bottom = _mm256_add_epi32(_mm256_mullo_epi32(q0, lx), _mm256_mullo_epi32(q1, wx));
				__m256i r = _mm256_srli_epi32(
				    _mm256_add_epi32(_mm256_add_epi32(_mm256_mullo_epi32(top, ly), _mm256_mullo_epi32(bottom, wy)), round), 14);
				r = _mm256_packus_epi32(r, r);
				r = _mm256_permute4x64_epi64(r, 0x08);
				res[c] = _mm256_packus_epi16(r, r);
			}
			storeUpTo8(dst[0] + row + std::size_t(x), _mm256_castsi256_si128(res[0]), n);
			storeUpTo8(dst[1] + row + std::size_t(x), _mm256_castsi256_si128(res[1]), n);
		}
	}
	return fb;
}

// The whole span list with the vector kernel: one call per warp, the kernel's constants set up once (the
// spans are short — ~27 luma pixels on average for a face — so per-span overhead matters). Pixels whose
// neighbourhood leaves the source take the clamped float path, as in the scalar kernel.
__attribute__((target("avx2,fma"))) void planeSpansAvx2(const std::vector<Span>& spans, const std::vector<float>& affine,
                                                        const std::uint8_t* sp, int sw, int sh, std::size_t stride, int ch,
                                                        std::uint8_t* const* dst, std::size_t dstStride) {
	for (const Span& s : spans) {
		const float* a = &affine[std::size_t(s.tri) * 6];
		const float rx = a[1] * float(s.y) + a[2], ry = a[4] * float(s.y) + a[5];
		const std::size_t row = std::size_t(s.y) * dstStride;
		int fa, fb;
		interiorRun(a, s, sw, ch == 1 ? sh - 1 : sh, fa, fb);
		auto slow = [&](int x) {
			std::uint8_t px[2];
			sampleClamped(sp, sw, sh, ch, stride, a[0] * float(x) + rx, a[3] * float(x) + ry, px);
			for (int c = 0; c < ch; ++c) dst[c][row + std::size_t(x)] = px[c];
		};
		int x = s.x0;
		for (; x < fa; ++x) slow(x);
		if (fb > fa) x = planeRunAvx2(sp, sw, stride, ch, a, rx, ry, fa, fb, dst, row);
		for (; x < s.x1; ++x) slow(x);
	}
}

// TALKHEAD_SCALAR_WARP (any value) forces the scalar kernel, so tests cover it on AVX2 machines too.
bool cpuHasAvx2() {
	static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && !std::getenv("TALKHEAD_SCALAR_WARP");
	return yes;
}
#endif
}  // namespace

void PiecewiseAffineWarp::applyPlanes(const std::uint8_t* sp, int sw, int sh, std::size_t stride, int ch, std::uint8_t* const* dst,
                                      std::size_t dstStride, bool scalar) const {
	if (ch != 1 && ch != 2) throw std::logic_error("PiecewiseAffineWarp::applyPlanes: 1 or 2 channels");
	if (sw < 1 || sh < 1) throw std::logic_error("PiecewiseAffineWarp::applyPlanes: empty source");
#ifdef TALKHEAD_AVX2
	if (!scalar && cpuHasAvx2()) {
		planeSpansAvx2(spans_, affine_, sp, sw, sh, stride, ch, dst, dstStride);
		return;
	}
#endif
	constexpr double one = 4294967296.0;
	for (const Span& s : spans_) {
		const float* a = &affine_[std::size_t(s.tri) * 6];
		const float rx = a[1] * float(s.y) + a[2], ry = a[4] * float(s.y) + a[5];
		const std::size_t row = std::size_t(s.y) * dstStride;
		int fa, fb;
		// One row short of the bottom: the vector kernel's 4-byte loads of the lower row then stay inside
		// the source (they read up to 2 bytes past the 2×2 neighbourhood).
		interiorRun(a, s, sw, ch == 1 ? sh - 1 : sh, fa, fb);
		auto slow = [&](int x) {
			std::uint8_t px[2];
			sampleClamped(sp, sw, sh, ch, stride, a[0] * float(x) + rx, a[3] * float(x) + ry, px);
			for (int c = 0; c < ch; ++c) dst[c][row + std::size_t(x)] = px[c];
		};
		for (int x = s.x0; x < fa; ++x) slow(x);
		if (fb > fa) {
			// 32.32 fixed-point positions stepped along the run, 7-bit weights (as bilinearRunRgb8).
			int x = fa;
			std::int64_t u = roundToInt64((double(a[0]) * x + rx) * one), v = roundToInt64((double(a[3]) * x + ry) * one);
			const std::int64_t du = roundToInt64(double(a[0]) * one), dv = roundToInt64(double(a[3]) * one);
			if (ch == 1) {
				std::uint8_t* o = dst[0] + row;
				for (; x < fb; ++x, u += du, v += dv) {
					const int wx = int(u >> 25) & 127, wy = int(v >> 25) & 127;
					const std::uint8_t* p = sp + std::size_t(v >> 32) * stride + std::size_t(u >> 32);
					const std::uint8_t* q = p + stride;
					const int top = p[0] * (128 - wx) + p[1] * wx, bottom = q[0] * (128 - wx) + q[1] * wx;
					o[x] = std::uint8_t((top * (128 - wy) + bottom * wy + (1 << 13)) >> 14);
				}
			} else {
				std::uint8_t* o0 = dst[0] + row;
				std::uint8_t* o1 = dst[1] + row;
				for (; x < fb; ++x, u += du, v += dv) {
					const int wx = int(u >> 25) & 127, wy = int(v >> 25) & 127;
					const std::uint8_t* p = sp + std::size_t(v >> 32) * stride + 2 * std::size_t(u >> 32);
					const std::uint8_t* q = p + stride;
					const int t0 = p[0] * (128 - wx) + p[2] * wx, b0 = q[0] * (128 - wx) + q[2] * wx;
					const int t1 = p[1] * (128 - wx) + p[3] * wx, b1 = q[1] * (128 - wx) + q[3] * wx;
					o0[x] = std::uint8_t((t0 * (128 - wy) + b0 * wy + (1 << 13)) >> 14);
					o1[x] = std::uint8_t((t1 * (128 - wy) + b1 * wy + (1 << 13)) >> 14);
				}
			}
		}
		for (int x = std::max(fa, fb); x < s.x1; ++x) slow(x);
	}
}

template void PiecewiseAffineWarp::apply(const ImageT<std::uint8_t>&, ImageT<std::uint8_t>&) const;
template void PiecewiseAffineWarp::apply(const ImageT<std::uint8_t>&, ImageT<float>&) const;
template void PiecewiseAffineWarp::apply(const ImageT<float>&, ImageT<float>&) const;
template void PiecewiseAffineWarp::apply(const ImageT<float>&, ImageT<std::uint8_t>&) const;

namespace {

// sin(x) by a Taylor series after reduction to [−π/2, π/2]: the same doubles on every machine (libm's sin
// may take another code path on another CPU).
double plainSin(double x) {
	const double pi = 3.14159265358979323846, twoPi = 2 * pi;
	x -= twoPi * double(std::llround(x / twoPi));
	if (x > pi / 2) x = pi - x;
	if (x < -pi / 2) x = -pi - x;
	const double x2 = x * x;
	double term = x, sum = x;
	for (int n = 1; n < 12; ++n) {
		term = -term * x2 / double((2 * n) * (2 * n + 1));
		sum += term;
	}
	return sum;
}

constexpr int kLanczosPhases = 1024;

// Per phase (a 1/1024 of a pixel): the six normalised weights of taps −2 … 3.
const std::vector<float>& lanczos3Table() {
	static const std::vector<float> table = [] {
		const double pi = 3.14159265358979323846;
		std::vector<float> t(std::size_t(kLanczosPhases) * 6);
		for (int p = 0; p < kLanczosPhases; ++p) {
			const double f = double(p) / kLanczosPhases;
			double w[6], sum = 0;
			for (int k = 0; k < 6; ++k) {
				const double d = f - double(k - 2);
				w[k] = std::abs(d) < 1e-12 ? 1.0 : (std::abs(d) >= 3 ? 0.0 : 3 * plainSin(pi * d) * plainSin(pi * d / 3) / (pi * pi * d * d));
				sum += w[k];
			}
			for (int k = 0; k < 6; ++k) t[std::size_t(p) * 6 + std::size_t(k)] = float(w[k] / sum);
		}
		return t;
	}();
	return table;
}

}  // namespace

void PiecewiseAffineWarp::applyLanczos3(const Image8& src, ImageT<float>& dst) const {
	if (dst.width != width_ || dst.height != height_ || dst.channels != 3 || src.channels != 3)
		throw std::logic_error("PiecewiseAffineWarp::applyLanczos3: RGB images of the warp's size");
	if (src.width < 1 || src.height < 1) throw std::logic_error("PiecewiseAffineWarp::applyLanczos3: empty source");
	const std::vector<float>& table = lanczos3Table();
	const int sw = src.width, sh = src.height;
	for (const Span& s : spans_) {
		const float* a = &affine_[std::size_t(s.tri) * 6];
		const float rx = a[1] * float(s.y) + a[2], ry = a[4] * float(s.y) + a[5];
		float* o = dst.data.data() + (std::size_t(s.y) * std::size_t(width_) + std::size_t(s.x0)) * 3;
		for (int x = s.x0; x < s.x1; ++x, o += 3) {
			const float fxs = a[0] * float(x) + rx, fys = a[3] * float(x) + ry;
			const float cx = std::clamp(fxs, 0.f, float(sw - 1)), cy = std::clamp(fys, 0.f, float(sh - 1));
			const int ix = int(cx), iy = int(cy);
			const int px = std::min(kLanczosPhases - 1, int((cx - float(ix)) * kLanczosPhases + 0.5f));
			const int py = std::min(kLanczosPhases - 1, int((cy - float(iy)) * kLanczosPhases + 0.5f));
			const float* wx = &table[std::size_t(px) * 6];
			const float* wy = &table[std::size_t(py) * 6];
			float acc[3] = {0, 0, 0};
			for (int j = 0; j < 6; ++j) {
				const std::uint8_t* row = src.row(std::clamp(iy + j - 2, 0, sh - 1));
				float r = 0, g = 0, b = 0;
				for (int k = 0; k < 6; ++k) {
					const std::uint8_t* p = row + 3 * std::clamp(ix + k - 2, 0, sw - 1);
					r += wx[k] * float(p[0]), g += wx[k] * float(p[1]), b += wx[k] * float(p[2]);
				}
				acc[0] += wy[j] * r, acc[1] += wy[j] * g, acc[2] += wy[j] * b;
			}
			for (int c = 0; c < 3; ++c) o[c] = std::clamp(acc[c], 0.f, 255.f);
		}
	}
}

}  // namespace talkhead
