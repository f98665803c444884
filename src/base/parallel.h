// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
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

// parallelFor on threads that persist from call to call (for loops that run many times, e.g. once per
// batch of frames): no thread start-up, and thread-local scratch stays warm. The helpers are started by
// the constructor and inherit its thread's scheduling priority; the thread calling run() works too.
// run() is not reentrant and must be called from one thread at a time.
class WorkerPool {
public:
	explicit WorkerPool(unsigned threads) {
		const unsigned n = resolveThreads(threads);
		for (unsigned t = 1; t < n; ++t) helpers_.emplace_back([this] { helperLoop(); });
	}
	WorkerPool(const WorkerPool&) = delete;
	WorkerPool& operator=(const WorkerPool&) = delete;
	~WorkerPool() {
		{
			std::lock_guard<std::mutex> lock(mutex_);
			quit_ = true;
		}
		wake_.notify_all();
		for (auto& t : helpers_) t.join();
	}
	unsigned threads() const { return unsigned(helpers_.size()) + 1; }

	// body(i) for i in [0, count), indices handed out in order; the first exception is rethrown here.
	void run(std::size_t count, const std::function<void(std::size_t)>& body) {
		{
			std::lock_guard<std::mutex> lock(mutex_);
			body_ = &body;
			count_ = count;
			next_ = 0;
			failed_ = false;
			error_ = nullptr;
			busy_ = helpers_.size();
			++generation_;
		}
		wake_.notify_all();
		work();
		std::unique_lock<std::mutex> lock(mutex_);
		done_.wait(lock, [&] { return busy_ == 0; });
		body_ = nullptr;
		if (error_) std::rethrow_exception(error_);
	}

private:
	void work() {
		for (;;) {
			if (failed_.load()) return;
			const std::size_t i = next_.fetch_add(1);
			if (i >= count_) return;
			try {
				(*body_)(i);
			} catch (...) {
				std::lock_guard<std::mutex> lock(mutex_);
				if (!error_) error_ = std::current_exception();
				failed_ = true;
				return;
			}
		}
	}
	void helperLoop() {
		std::uint64_t seen = 0;
		for (;;) {
			{
				std::unique_lock<std::mutex> lock(mutex_);
				wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
				if (quit_) return;
				seen = generation_;
			}
			work();
			std::lock_guard<std::mutex> lock(mutex_);
			if (--busy_ == 0) done_.notify_all();
		}
	}
	std::vector<std::thread> helpers_;
	std::mutex mutex_;
	std::condition_variable wake_, done_;
	const std::function<void(std::size_t)>* body_ = nullptr;
	std::size_t count_ = 0, busy_ = 0;
	std::atomic<std::size_t> next_{0};
	std::atomic<bool> failed_{false};
	std::exception_ptr error_;
	std::uint64_t generation_ = 0;
	bool quit_ = false;
};

}  // namespace talkhead
