// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstddef>
#include <functional>
#include <string>

namespace talkhead {

// A temporary name in the same folder as `path` (".tmp-<pid>-<name>", so a rename is atomic and the
// extension stays last). Registered with interrupt.h: call releaseTemporary once it is renamed or removed.
std::string temporaryNameFor(const std::string& path);

// Writes the bytes to a temporary name and renames it into place: a failure leaves no partial file.
// Throws Error("PATH: cannot write: <reason>") — every write and the close checked, so a full disk is an
// error, never a short file.
void writeFileAtomically(const std::string& path, const std::string& bytes);
void writeFileAtomically(const std::string& path, const void* data, std::size_t size);

// A file written under a temporary name now and put in place later (a command's side outputs — speech,
// sidecars — appear only with its main output): write() runs the writer on the temporary path (an Error
// naming it is re-thrown naming `path`), commit() renames it into place; destroyed without commit(), the
// temporary is removed.
class StagedFile {
public:
	explicit StagedFile(std::string path);
	~StagedFile();
	StagedFile(const StagedFile&) = delete;
	StagedFile& operator=(const StagedFile&) = delete;
	void write(const std::function<void(const std::string&)>& writer);
	void commit();
	const std::string& path() const { return path_; }

private:
	std::string path_, temp_;
	bool committed_ = false;
};

// A folder written all-or-nothing (issue 15): files go into a temporary folder beside `path` (".tmp-<pid>-
// <name>", removed on a signal, interrupt.h), and commit() puts it in place of `path` — renamed when
// `path` does not exist or is empty; a previous output (every entry `replaceable`) is moved aside and
// removed. Destroyed without commit(), the temporary folder goes with everything in it. Flat folders only.
class StagedFolder {
public:
	using Replaceable = bool (*)(const std::string& name);
	// Throws Error naming `path` when it exists and is not a folder of replaceable entries (checked here,
	// before any work, and again at commit).
	StagedFolder(std::string path, Replaceable replaceable);
	~StagedFolder();
	StagedFolder(const StagedFolder&) = delete;
	StagedFolder& operator=(const StagedFolder&) = delete;
	const std::string& temp() const { return temp_; }  // write here
	const std::string& path() const { return path_; }
	// Runs write(the temporary path of file `name`); an Error naming that path is re-thrown naming
	// path()/name instead (messages name what the user asked for). Thread-safe.
	void writeFile(const std::string& name, const std::function<void(const std::string&)>& write) const;
	void commit();

private:
	std::string path_, temp_;
	Replaceable replaceable_;
	bool committed_ = false;
};
// The check alone (for commands that check every output before working).
void checkReplaceableFolder(const std::string& path, StagedFolder::Replaceable replaceable);

}  // namespace talkhead
