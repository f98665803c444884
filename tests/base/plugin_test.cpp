// SPDX-License-Identifier: GPL-3.0-or-later
// Issue 28, item 6: a plugin is never loaded while the process is out of file descriptors (one of
// libav's libraries, libgcrypt through libssh, aborts the process in its initialiser then); the error says
// so, and loading works again once descriptors are back.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <exception>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/plugin.h"

using namespace talkhead;

namespace {

std::string loadError(const char* name) {
	try {
		loadPlugin(name, "talkhead_none_module", 1);
	} catch (const Error& e) {
		return e.what();
	}
	return "(loaded)";
}

// Tries while the process is out of descriptors and keeps the exception to read later: UBSan's vptr check
// needs a free descriptor of its own (sanitizer_common tests memory with pipe()), so nothing polymorphic
// is touched until they are back.
std::exception_ptr tryLoad(const char* name) {
	try {
		loadPlugin(name, "talkhead_none_module", 1);
	} catch (...) {
		return std::current_exception();
	}
	return nullptr;
}

std::string messageOf(const std::exception_ptr& e) {
	if (!e) return "(loaded)";
	try {
		std::rethrow_exception(e);
	} catch (const Error& x) {
		return x.what();
	} catch (...) {
		return "(not an Error)";
	}
}

}  // namespace

TEST(Plugin, aMissingPluginNamesItselfAndTheVariable) {
	const std::string e = loadError("libtalkhead-none.so");
	EXPECT_NE(e.find("cannot load the plugin libtalkhead-none.so (not found"), std::string::npos) << e;
	EXPECT_NE(e.find("TALKHEAD_MODULE_DIR"), std::string::npos) << e;
}

TEST(Plugin, notLoadedOutOfFileDescriptors) {
	rlimit old{};
	ASSERT_EQ(::getrlimit(RLIMIT_NOFILE, &old), 0);
	// A low limit, then every descriptor under it taken.
	rlimit low = old;
	low.rlim_cur = 256;
	ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &low), 0);
	std::vector<int> held;
	for (int fd; (fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC)) >= 0;) held.push_back(fd);
	const std::exception_ptr outError = tryLoad("libtalkhead-none.so");
	// Descriptors back, but fewer than 16 free: still refused.
	for (std::size_t i = 0; i < 8 && i < held.size(); ++i) ::close(held[i]);
	const std::exception_ptr fewError = tryLoad("libtalkhead-none.so");
	for (std::size_t i = 8; i < held.size(); ++i) ::close(held[i]);
	const std::string out = messageOf(outError), few = messageOf(fewError);
	const std::string back = loadError("libtalkhead-none.so");
	ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &old), 0);
	EXPECT_GT(held.size(), 8u);
	EXPECT_NE(out.find("cannot load the plugin libtalkhead-none.so now: Too many open files (the process is out of file descriptors)"), std::string::npos) << out;
	EXPECT_NE(few.find("out of file descriptors"), std::string::npos) << few;
	EXPECT_NE(back.find("(not found"), std::string::npos) << back;
}
