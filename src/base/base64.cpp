// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/base64.h"

#include <openssl/evp.h>

#include <cctype>
#include <limits>

namespace talkhead {

std::optional<std::string> decodeBase64(std::string_view text) {
	std::string clean;
	clean.reserve(text.size());
	for (char c : text)
		if (!std::isspace(static_cast<unsigned char>(c))) clean.push_back(c);
	if (clean.size() % 4 != 0 || clean.size() > std::size_t(std::numeric_limits<int>::max())) return std::nullopt;
	if (clean.empty()) return std::string();
	std::string out(clean.size() / 4 * 3, '\0');
	const int n = EVP_DecodeBlock(reinterpret_cast<unsigned char*>(out.data()), reinterpret_cast<const unsigned char*>(clean.data()), int(clean.size()));
	if (n < 0) return std::nullopt;
	// EVP_DecodeBlock counts the padding's bytes: drop one per '='.
	std::size_t size = std::size_t(n);
	if (clean.back() == '=') --size;
	if (clean[clean.size() - 2] == '=') --size;
	out.resize(size);
	return out;
}

}  // namespace talkhead
