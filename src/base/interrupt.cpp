// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/interrupt.h"

#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdint>

#include <atomic>
#include <csignal>
#include <cstring>
#include <sys/types.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>

namespace talkhead {

namespace {

// A fixed table the signal handler can walk without locks or allocation: a slot is free (0), being
// written (1) or holds a live path (2).
constexpr int kSlots = 512;
constexpr std::size_t kPathMax = 4096;
struct Slot {
	std::atomic<int> state{0};
	bool tree = false;  // a folder whose files are removed too
	char path[kPathMax];
};

// Removes what a folder holds (files, and folders up to `depth` levels down) with raw system calls only
// (async-signal-safe: no opendir, whose malloc could deadlock in a handler).
void emptyFolderAt(int dirfd, const char* path, int depth) {
	const int fd = ::openat(dirfd, path, O_RDONLY | O_DIRECTORY | O_CLOEXEC | O_NOFOLLOW);
	if (fd < 0) return;
	alignas(8) char buf[4096];
	for (int round = 0; round < 100000; ++round) {
		::lseek(fd, 0, SEEK_SET);
		const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
		if (n <= 0) break;
		bool removed = false;
		for (long at = 0; at < n;) {
			struct Entry {
				std::uint64_t ino;
				std::int64_t off;
				unsigned short reclen;
				unsigned char type;
				char name[1];
			};
			const Entry* e = reinterpret_cast<const Entry*>(buf + at);
			at += e->reclen;
			if (e->name[0] == '.' && (e->name[1] == 0 || (e->name[1] == '.' && e->name[2] == 0))) continue;
			if (::unlinkat(fd, e->name, 0) == 0) {
				removed = true;
				continue;
			}
			if (depth > 0) emptyFolderAt(fd, e->name, depth - 1);
			if (::unlinkat(fd, e->name, AT_REMOVEDIR) == 0) removed = true;
		}
		if (!removed) break;
	}
	::close(fd);
}
void emptyFolder(const char* path) { emptyFolderAt(AT_FDCWD, path, 3); }

Slot slots[kSlots];
std::atomic<pid_t> child{0};

void onSignal(int sig) {
	// The child process working for this one (batch) stops too, and removes its own temporaries.
	// Waited for up to 0.4 s, so that its files are gone before the folders they are in are removed.
	if (const pid_t c = child.load(std::memory_order_acquire); c > 0) {
		::kill(c, sig);
		const struct timespec tick {0, 10 * 1000 * 1000};
		for (int i = 0; i < 40 && ::waitpid(c, nullptr, WNOHANG) == 0; ++i) ::nanosleep(&tick, nullptr);
	}
	// Files first, then folders (emptied by then), whatever order they were registered in.
	for (Slot& s : slots)
		if (s.state.load(std::memory_order_acquire) == 2) {
			if (s.tree) emptyFolder(s.path);
			else ::unlink(s.path);  // async-signal-safe
		}
	for (Slot& s : slots)
		if (s.state.load(std::memory_order_acquire) == 2) ::rmdir(s.path);
	static const char message[] = "talkhead: interrupted\n";
	const ssize_t written = ::write(STDERR_FILENO, message, sizeof message - 1);
	(void)written;
	::_exit(128 + sig);
}

}  // namespace

void installInterruptHandlers() {
	struct sigaction sa {};
	sa.sa_handler = onSignal;
	sigemptyset(&sa.sa_mask);
	sa.sa_flags = 0;
	for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
		// A signal ignored when the process started stays ignored (a background job's SIGINT, nohup's SIGHUP).
		struct sigaction old {};
		if (sig != SIGTERM && sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
		sigaction(sig, &sa, nullptr);
	}
}

void registerSlot(const std::string& path, bool tree);

void setInterruptChild(int pid) { child.store(pid, std::memory_order_release); }

void registerTemporary(const std::string& path) { registerSlot(path, false); }
void registerTemporaryFolder(const std::string& path) { registerSlot(path, true); }

void registerSlot(const std::string& path, bool tree) {
	if (path.size() >= kPathMax) return;
	for (Slot& s : slots) {
		int expected = 0;
		if (s.state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) {
			s.tree = tree;
			std::memcpy(s.path, path.c_str(), path.size() + 1);
			s.state.store(2, std::memory_order_release);
			return;
		}
	}
	// Full (more than kSlots temporaries at once): this one is not cleaned on a signal.
}

void releaseTemporary(const std::string& path) {
	for (Slot& s : slots) {
		int expected = 2;
		if (s.state.load(std::memory_order_acquire) == 2 && std::strcmp(s.path, path.c_str()) == 0 &&
		    s.state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) {
			s.state.store(0, std::memory_order_release);
			return;
		}
	}
}

}  // namespace talkhead
