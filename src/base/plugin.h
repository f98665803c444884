// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

namespace talkhead {

// Heavy libraries (OpenImageIO: ~260 shared libraries; libav: ~130) cost start-up time for every command,
// so the code that uses them is built as plugins (lib/talkhead/libtalkhead-*.so) and loaded on first use.
// Searched in order: $TALKHEAD_MODULE_DIR, <executable>/lib/talkhead (build tree), the installed tree
// relative to the executable, the configured install folder, and the build tree this was compiled in.
std::vector<std::string> pluginCandidates(const std::string& fileName);

// Loads the plugin (once per process, kept loaded) and returns what its extern "C" `entry` function
// returns. Throws Error naming the plugin and the folders searched when none loads, or when `abi` (the
// int at the start of the returned struct) differs from the one this build expects, or when fewer than 16
// file descriptors are free (libraries' initialisers may abort the process then; a later call may succeed).
const void* loadPlugin(const std::string& fileName, const char* entry, int abi);

// For a plugin's entry points: runs f and returns true, or returns false with `error` set to the message of
// the exception f threw, so that no exception crosses the plugin boundary.
template <class F>
bool guarded(std::string& error, F&& f) {
	try {
		f();
		return true;
	} catch (const std::exception& e) {
		error = e.what();
		return false;
	}
}

}  // namespace talkhead
