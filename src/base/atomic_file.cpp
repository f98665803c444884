// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "base/error.h"
#include "base/interrupt.h"

namespace fs = std::filesystem;

namespace talkhead {

std::string temporaryNameFor(const std::string& path) {
	const fs::path t(path);
	const std::string name = (t.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" + t.filename().string())).string();
	registerTemporary(name);  // removed if a signal stops the process before it is renamed (interrupt.h)
	return name;
}

void writeFileAtomically(const std::string& path, const std::string& bytes) { writeFileAtomically(path, bytes.data(), bytes.size()); }

void writeFileAtomically(const std::string& path, const void* data, std::size_t size) {
	const std::string tmp = temporaryNameFor(path);
	// POSIX I/O, every call checked (a full disk shows at write() or at close()), errno in the message.
	auto fail = [&](int fd) {
		const int e = errno;
		if (fd >= 0) ::close(fd);
		std::remove(tmp.c_str());
		releaseTemporary(tmp);
		throw Error(path, 0, std::string("cannot write: ") + std::strerror(e));
	};
	const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
	if (fd < 0) fail(-1);
	const char* p = static_cast<const char*>(data);
	for (std::size_t left = size; left > 0;) {
		const ssize_t n = ::write(fd, p, left);
		if (n < 0 && errno == EINTR) continue;
		if (n <= 0) {
			if (n == 0) errno = ENOSPC;
			fail(fd);
		}
		p += n;
		left -= std::size_t(n);
	}
	if (::close(fd) != 0) fail(-1);
	std::error_code ec;
	fs::rename(tmp, path, ec);
	if (ec) std::remove(tmp.c_str());
	releaseTemporary(tmp);
	if (ec) throw Error(path, 0, "cannot write: " + ec.message());
}

namespace {
// Runs write(tmp); an Error naming `tmp` is re-thrown naming `shown`.
void renamedErrors(const std::string& tmp, const std::string& shown, const std::function<void(const std::string&)>& write) {
	try {
		write(tmp);
	} catch (const Error& e) {
		const std::string m = e.what(), prefix = tmp + ": ";
		if (m.rfind(prefix, 0) == 0) throw Error(shown, 0, m.substr(prefix.size()));
		throw;
	}
}
}  // namespace

StagedFile::StagedFile(std::string path) : path_(std::move(path)), temp_(temporaryNameFor(path_)) {}

StagedFile::~StagedFile() {
	if (!committed_) std::remove(temp_.c_str());
	releaseTemporary(temp_);
}

void StagedFile::write(const std::function<void(const std::string&)>& writer) { renamedErrors(temp_, path_, writer); }

void StagedFile::commit() {
	std::error_code ec;
	fs::rename(temp_, path_, ec);
	if (ec) throw Error(path_, 0, "cannot write: " + ec.message());
	committed_ = true;
}

void checkReplaceableFolder(const std::string& path, StagedFolder::Replaceable replaceable) {
	std::error_code ec;
	const auto st = fs::symlink_status(path, ec);
	if (ec || !fs::exists(st)) return;
	if (!fs::is_directory(st)) throw Error(path, 0, "exists and is not a folder");
	for (const auto& e : fs::directory_iterator(path, ec)) {
		const std::string name = e.path().filename().string();
		if (!e.is_regular_file() || !replaceable(name))
			throw Error(path, 0, "the folder holds other files ('" + name.substr(0, 60) + "'); name a new or empty folder, or one this command wrote before");
	}
	if (ec) throw Error(path, 0, "cannot read the folder: " + ec.message());
}

StagedFolder::StagedFolder(std::string path, Replaceable replaceable) : path_(std::move(path)), replaceable_(replaceable) {
	while (path_.size() > 1 && path_.back() == '/') path_.pop_back();
	checkReplaceableFolder(path_, replaceable_);
	const fs::path p(path_);
	const fs::path parent = p.parent_path().empty() ? fs::path(".") : p.parent_path();
	std::error_code ec;
	fs::create_directories(parent, ec);
	if (ec) throw Error(path_, 0, "cannot create folder: " + ec.message());
	temp_ = (parent / (".tmp-" + std::to_string(::getpid()) + "-" + p.filename().string())).string();
	registerTemporaryFolder(temp_);
	fs::remove_all(temp_, ec);
	if (!fs::create_directory(temp_, ec) || ec) {
		releaseTemporary(temp_);
		throw Error(path_, 0, "cannot create folder: " + (ec ? ec.message() : std::string("exists")));
	}
}

StagedFolder::~StagedFolder() {
	if (committed_) return;
	std::error_code ec;
	fs::remove_all(temp_, ec);
	releaseTemporary(temp_);
}

void StagedFolder::writeFile(const std::string& name, const std::function<void(const std::string&)>& write) const {
	renamedErrors((fs::path(temp_) / name).string(), (fs::path(path_) / name).string(), write);
}

void StagedFolder::commit() {
	checkReplaceableFolder(path_, replaceable_);
	std::error_code ec;
	// An empty folder is replaced by rename(2) itself; one with a previous output is moved aside first.
	std::string aside;
	if (fs::exists(path_, ec) && !fs::is_empty(path_, ec)) {
		aside = temp_ + ".old";
		registerTemporaryFolder(aside);
		fs::rename(path_, aside, ec);
		if (ec) {
			releaseTemporary(aside);
			throw Error(path_, 0, "cannot replace the folder: " + ec.message());
		}
	}
	fs::rename(temp_, path_, ec);
	if (ec) {
		if (!aside.empty()) {
			std::error_code back;
			fs::rename(aside, path_, back);  // put the previous output back
			releaseTemporary(aside);
		}
		throw Error(path_, 0, "cannot write the folder: " + ec.message());
	}
	committed_ = true;
	releaseTemporary(temp_);
	if (!aside.empty()) {
		fs::remove_all(aside, ec);
		releaseTemporary(aside);
	}
}

}  // namespace talkhead
