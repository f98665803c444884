// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz_support.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace talkhead::fuzz {

namespace {
struct TempDir {
	std::string path;
	TempDir() {
		std::error_code ec;
		const std::string base = fs::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : fs::temp_directory_path().string();
		std::string tmpl = base + "/talkhead-fuzz-XXXXXX";
		if (!::mkdtemp(tmpl.data())) {
			std::perror("talkhead fuzz: mkdtemp");
			std::abort();
		}
		path = tmpl;
	}
	~TempDir() {
		std::error_code ec;
		fs::remove_all(path, ec);
	}
};
}  // namespace

const std::string& tempDir() {
	static TempDir dir;
	return dir.path;
}

std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& name) {
	const std::string path = tempDir() + "/" + name;
	std::FILE* f = std::fopen(path.c_str(), "wb");
	if (!f || (size && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
		std::perror(("talkhead fuzz: cannot write " + path).c_str());
		std::abort();
	}
	return path;
}

std::string writeInput(const std::string& bytes, const std::string& name) {
	return writeInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), name);
}

void violated(const char* what, const std::string& detail) {
	std::fprintf(stderr, "\n==fuzz== broken promise: %s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
	std::abort();
}

}  // namespace talkhead::fuzz
