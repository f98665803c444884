// SPDX-License-Identifier: GPL-3.0-or-later
// A live session's replan (render/live.h) after a long time: a continued ShapeModulator plan against a
// plan computed from the stream's start (what a replan cost before the continued plan computed its
// speaking activity only from the splice on). usage: bench_live_replan
#include <chrono>
#include <cstdio>

#include "synth/modulator.h"

using namespace talkhead;

int main() {
	ModulatorOptions o;
	std::printf("%-12s %14s %14s\n", "stream time", "from start", "continued");
	for (double at : {10.0, 3600.0, 8 * 3600.0}) {
		std::vector<Keypose> keys;
		for (int i = 0; i < 40; ++i) {
			Keypose k;
			k.time = ticksFromSeconds(at - 2 + 0.08 * i);
			k.cdv = i % 5 ? Cdv("a") : Cdv("sil");
			keys.push_back(k);
		}
		const Ticks from = ticksFromSeconds(at), horizon = ticksFromSeconds(at + 60);
		const ShapeModulator previous(o, Emotion(), ticksFromSeconds(60), keys);
		auto time = [](auto&& f) {
			const auto t0 = std::chrono::steady_clock::now();
			for (int r = 0; r < 5; ++r) f();
			return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / 5;
		};
		const double whole = time([&] { ShapeModulator m(o, Emotion(), horizon, keys); });
		const double continued = time([&] { ShapeModulator m(previous, from, o, Emotion(), horizon, keys); });
		std::printf("%9.0f s %11.2f ms %11.2f ms\n", at, whole, continued);
	}
}
