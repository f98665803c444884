// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to the media module: libav error handling.
#pragma once
extern "C" {
#include <libavutil/error.h>
}
#include <string>

#include "base/error.h"

namespace talkhead {

inline std::string avError(int code) {
	char buf[AV_ERROR_MAX_STRING_SIZE] = {};
	av_strerror(code, buf, sizeof buf);
	return buf;
}

// Throws Error("PATH: what: libav message") for a negative libav return code.
inline int checkAv(int ret, const std::string& path, const char* what) {
	if (ret < 0) throw Error(path, 0, std::string(what) + ": " + avError(ret));
	return ret;
}

}  // namespace talkhead
