// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>
#include <string_view>

namespace talkhead {

// Standard base64 (RFC 4648, with padding; whitespace ignored) to bytes, or nullopt when it is not base64.
// OpenSSL's decoder.
std::optional<std::string> decodeBase64(std::string_view text);

}  // namespace talkhead
