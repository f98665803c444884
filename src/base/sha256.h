// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

namespace talkhead {

// SHA-256 of a file's bytes as 64 lowercase hex digits (OpenSSL's libcrypto); throws Error naming the
// file when it cannot be read.
std::string sha256File(const std::string& path);
// SHA-256 of a string.
std::string sha256(const std::string& bytes);

}  // namespace talkhead
