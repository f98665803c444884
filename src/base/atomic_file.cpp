// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/atomic_file.h"

#include <unistd.h>

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

void writeFileAtomically(const std::string& path, const std::string& bytes) {
	const std::string tmp = temporaryNameFor(path);
	{
		std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
		out.write(bytes.data(), std::streamsize(bytes.size()));
		out.flush();
		if (!out) {
			out.close();
			std::remove(tmp.c_str());
			releaseTemporary(tmp);
			throw Error(path, 0, "cannot write (missing folder, no permission or disk full)");
		}
	}
	std::error_code ec;
	fs::rename(tmp, path, ec);
	if (ec) std::remove(tmp.c_str());
	releaseTemporary(tmp);
	if (ec) throw Error(path, 0, "cannot write: " + ec.message());
}

}  // namespace talkhead
