// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/frame_rate.h"

#include <cstdio>
#include <limits>
#include <numeric>

namespace talkhead {

std::int64_t FrameRate::frameCount(Ticks duration) const {
	const std::int64_t d = std::max<std::int64_t>(0, duration.count());
	const __int128 numer = __int128(kTicksPerSecond) * den;
	const __int128 n = (__int128(d) * num + numer / 2) / numer;
	if (n > std::numeric_limits<std::int64_t>::max()) return std::numeric_limits<std::int64_t>::max();
	return std::max<std::int64_t>(1, std::int64_t(n));
}

std::int64_t FrameRate::frameAt(Ticks t) const {
	const __int128 numer = __int128(kTicksPerSecond) * den;
	return std::int64_t(__int128(std::max<std::int64_t>(0, t.count())) * num / numer);
}

std::string FrameRate::str() const {
	return den == 1 ? std::to_string(num) : std::to_string(num) + "/" + std::to_string(den);
}

std::optional<FrameRate> FrameRate::parse(const std::string& text) {
	auto digits = [](const std::string& s) { return !s.empty() && s.size() <= 9 && s.find_first_not_of("0123456789") == std::string::npos; };
	long long num = 0, den = 1;
	if (auto slash = text.find('/'); slash != std::string::npos) {
		const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
		if (!digits(a) || !digits(b)) return std::nullopt;
		num = std::stoll(a), den = std::stoll(b);
	} else if (auto dot = text.find('.'); dot != std::string::npos) {
		std::string a = text.substr(0, dot), b = text.substr(dot + 1);
		if (!digits(a) || (!b.empty() && !digits(b)) || b.size() > 6) return std::nullopt;
		while (!b.empty() && b.back() == '0') b.pop_back();
		static const struct {
			const char* spelled;
			int num;
		} kNtsc[] = {{"23.976", 24000}, {"29.97", 30000}, {"47.952", 48000}, {"59.94", 60000}, {"119.88", 120000}};
		for (const auto& k : kNtsc)
			if (a + "." + b == k.spelled) return FrameRate{k.num, 1001};
		den = 1;
		for (std::size_t i = 0; i < b.size(); ++i) den *= 10;
		num = std::stoll(a) * den + (b.empty() ? 0 : std::stoll(b));
	} else {
		if (!digits(text)) return std::nullopt;
		num = std::stoll(text);
	}
	if (den < 1 || num < den || num > 240 * den) return std::nullopt;
	const long long g = std::gcd(num, den);
	num /= g, den /= g;
	if (num > 1000000 || den > 1000000) return std::nullopt;
	return FrameRate{int(num), int(den)};
}

}  // namespace talkhead
