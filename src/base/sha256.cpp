// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/sha256.h"

#include <openssl/evp.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "base/error.h"

namespace talkhead {

namespace {
struct Digest {
	EVP_MD_CTX* ctx = EVP_MD_CTX_new();
	Digest() {
		if (!ctx || EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr) != 1) throw Error("SHA-256: libcrypto cannot start a digest");
	}
	~Digest() { EVP_MD_CTX_free(ctx); }
	void update(const void* p, std::size_t n) {
		if (EVP_DigestUpdate(ctx, p, n) != 1) throw Error("SHA-256: libcrypto failed");
	}
	std::string hex() {
		unsigned char md[EVP_MAX_MD_SIZE];
		unsigned int n = 0;
		if (EVP_DigestFinal_ex(ctx, md, &n) != 1) throw Error("SHA-256: libcrypto failed");
		static const char* digits = "0123456789abcdef";
		std::string out;
		for (unsigned int i = 0; i < n; ++i) out += digits[md[i] >> 4], out += digits[md[i] & 15];
		return out;
	}
};
}  // namespace

std::string sha256(const std::string& bytes) {
	Digest d;
	d.update(bytes.data(), bytes.size());
	return d.hex();
}

std::string sha256File(const std::string& path) {
	std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
	if (!f) throw Error(path, 0, std::string("cannot open: ") + std::strerror(errno));
	Digest d;
	std::vector<char> buf(1 << 16);
	std::size_t n;
	while ((n = std::fread(buf.data(), 1, buf.size(), f.get())) > 0) d.update(buf.data(), n);
	if (std::ferror(f.get())) throw Error(path, 0, "read error");
	return d.hex();
}

}  // namespace talkhead
