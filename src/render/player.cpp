// SPDX-License-Identifier: GPL-3.0-or-later
// The one frame player (render/player.h): keypose images, the synthesizer's frame, overlay, fit and matte.
#include "render/player.h"

#include <algorithm>
#include <cstdio>

#include "render/overlay.h"
#include "synth/modulator.h"

namespace talkhead {

namespace {

// Copies one plane of `inner` (iw × ih) into `out` (w × h) at (x, y), cropping what overflows and filling
// what is left by repeating the nearest edge pixel.
void placePlane(const std::uint8_t* inner, int iw, int ih, std::uint8_t* out, int w, int h, int x, int y) {
	for (int r = 0; r < h; ++r) {
		const int sr = std::clamp(r - y, 0, ih - 1);
		const std::uint8_t* src = inner + std::size_t(sr) * std::size_t(iw);
		std::uint8_t* dst = out + std::size_t(r) * std::size_t(w);
		const int c0 = std::clamp(x, 0, w), c1 = std::clamp(x + iw, 0, w);  // output columns that come from the inner frame
		if (c0 > 0) std::fill(dst, dst + c0, src[0]);
		if (c1 > c0) std::copy(src + (c0 - x), src + (c1 - x), dst + c0);
		if (c1 < w) std::fill(dst + std::max(c1, 0), dst + w, src[iw - 1]);
	}
}

void placeRgb(const Image8& inner, Image8& out, int w, int h, int x, int y) {
	if (out.width != w || out.height != h || out.channels != 3) out = Image8(w, h, 3);
	for (int r = 0; r < h; ++r) {
		const std::uint8_t* src = inner.row(std::clamp(r - y, 0, inner.height - 1));
		std::uint8_t* dst = out.row(r);
		for (int c = 0; c < w; ++c) {
			const int sc = std::clamp(c - x, 0, inner.width - 1);
			dst[3 * c] = src[3 * sc], dst[3 * c + 1] = src[3 * sc + 1], dst[3 * c + 2] = src[3 * sc + 2];
		}
	}
}

}  // namespace

void placeFitted(const YuvImage& inner, YuvImage& out, int w, int h, int x, int y) {
	out.resize(w, h);
	placePlane(inner.y.data(), inner.width, inner.height, out.y.data(), w, h, x, y);
	placePlane(inner.u.data(), inner.chromaWidth(), inner.chromaHeight(), out.u.data(), out.chromaWidth(), out.chromaHeight(), x / 2, y / 2);
	placePlane(inner.v.data(), inner.chromaWidth(), inner.chromaHeight(), out.v.data(), out.chromaWidth(), out.chromaHeight(), x / 2, y / 2);
}

FramePlayer::FramePlayer(const Face& face, const RenderOptions& options)
    : overlay_(options.debugOverlay), matte_(face.model().scheme, options.matte) {
	SynthOptions so = options.synth;
	so.yuvRange = YuvRange::Limited;  // what H.264 and y4m readers assume
	fit_ = fitOutput(face.model(), so, options.fit);
	synth_ = std::make_unique<Synthesizer>(face, so);
	width_ = fit_.place ? fit_.outWidth : synth_->width();
	height_ = fit_.place ? fit_.outHeight : synth_->height();
}

void FramePlayer::prepare(const std::vector<Keypose>& keys, Ticks from, Ticks to) {
	synth_->prepare(Synthesizer::keyposesBetween(keys, from, to, synth_->margin()));
}

void FramePlayer::draw(Ticks t, const std::vector<Keypose>& keys, Synthesizer::Workspace& ws, FrameSlot& slot, bool rgbFrames, bool alpha) const {
	const bool place = fit_.place;
	Image8& rgb = place ? slot.innerRgb : slot.rgb;
	YuvImage& yuv = place ? slot.innerYuv : slot.yuv;
	if (rgbFrames) {
		synth_->renderFrame(t, keys, ws, rgb, slot.points, slot.drawn);
		if (overlay_) drawDebugOverlay(rgb, slot.points, overlayLines(t, keys));
		rgbToYuv420(rgb, yuv, YuvRange::Limited);
	} else {
		synth_->renderFrameYuv(t, keys, ws, yuv, slot.points, slot.drawn);
		if (overlay_) drawDebugOverlay(yuv, slot.points, overlayLines(t, keys));
	}
	slot.drawn = !overlay_;  // the overlay writes over the static background
	if (place) {  // into the output frame: crop or pad, points moved with it
		placeFitted(yuv, slot.yuv, width_, height_, fit_.box.x, fit_.box.y);
		if (rgbFrames) placeRgb(rgb, slot.rgb, width_, height_, fit_.box.x, fit_.box.y);
		slot.points.col(0).array() += fit_.box.x;
		slot.points.col(1).array() += fit_.box.y;
	}
	if (alpha) matte_.draw(slot.points, width_, height_, slot.yuv.a);
}

std::vector<std::string> FramePlayer::overlayLines(Ticks tau, const std::vector<Keypose>& keys) const {
	const SynthOptions& so = synth_->options();
	std::vector<std::string> lines;
	char b[160];
	std::snprintf(b, sizeof b, "t %.3f s", toSeconds(tau));
	lines.emplace_back(b);
	std::size_t i = 0;
	while (i + 1 < keys.size() && keys[i + 1].time <= tau) ++i;
	auto label = [&](const Keypose& k) {
		const std::string& e = k.emotion.value_or(so.expression.emotion()).label();
		const double in = k.intensity.value_or(so.expression.intensity());
		char l[96];
		std::snprintf(l, sizeof l, "%s %s:%.2g @%.3f", k.cdv.label().c_str(), e.c_str(), in, toSeconds(k.time));
		return std::string(l);
	};
	if (i + 1 < keys.size() && tau > keys[i].time) {
		const double u = toSeconds(tau - keys[i].time) / toSeconds(keys[i + 1].time - keys[i].time);
		lines.push_back(label(keys[i]) + " -> " + label(keys[i + 1]));
		std::snprintf(b, sizeof b, "u %.2f", u);
		lines.emplace_back(b);
	} else {
		lines.push_back(label(keys[i]) + " (held)");
	}
	if (so.modulator) {
		const HeadMotion h = so.modulator->head(tau);
		std::snprintf(b, sizeof b, "lids %.2f  head %+.2f deg %+.3f %+.3f", so.modulator->eyeClosure(tau), (h.angle + h.roll) * 57.29578, h.dx, h.dy);
		lines.emplace_back(b);
	}
	return lines;
}

}  // namespace talkhead
