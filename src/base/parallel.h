// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace talkhead {

// Number of worker threads to use when the caller asks for `requested` (0 = all cores).
inline unsigned resolveThreads(unsigned requested) {
	if (requested > 0) return requested;
	unsigned n = std::thread::hardware_concurrency();
	return n == 0 ? 1 : n;
}

// Runs body(i) for i in [0, count) on `threads` threads, handing out indices in order. The first
// exception thrown by any body is rethrown here after all threads stop. Results must not depend on
// which thread ran an index (callers write into per-index slots), so output is deterministic.
inline void parallelFor(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& body) {
	threads = std::max(1u, std::min<unsigned>(resolveThreads(threads), static_cast<unsigned>(std::max<std::size_t>(count, 1))));
	if (threads == 1) {
		for (std::size_t i = 0; i < count; ++i) body(i);
		return;
	}
	std::atomic<std::size_t> next{0};
	std::atomic<bool> failed{false};
	std::exception_ptr error;
	std::mutex errorMutex;
	auto worker = [&] {
		for (;;) {
			if (failed.load()) return;
			std::size_t i = next.fetch_add(1);
			if (i >= count) return;
			try {
				body(i);
			} catch (...) {
				std::lock_guard<std::mutex> lock(errorMutex);
				if (!error) error = std::current_exception();
				failed = true;
				return;
			}
		}
	};
	std::vector<std::thread> pool;
	for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
	worker();
	for (auto& t : pool) t.join();
	if (error) std::rethrow_exception(error);
}

}  // namespace talkhead
