// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/corpus_filter.h"

#include <fnmatch.h>

#include <algorithm>
#include <filesystem>

#include "base/error.h"

namespace talkhead::cli {

Corpus loadFilteredCorpus(const std::string& path, const Args& args) {
	Corpus c = loadCorpus(path);
	auto include = args.get("--include");
	auto exclude = args.get("--exclude");
	if (!include && !exclude) return c;
	auto matches = [](const std::string& glob, const CorpusEntry& e) {
		return ::fnmatch(glob.c_str(), std::filesystem::path(e.imagePath).filename().c_str(), 0) == 0;
	};
	c.entries.erase(std::remove_if(c.entries.begin(), c.entries.end(),
	                               [&](const CorpusEntry& e) { return (include && !matches(*include, e)) || (exclude && matches(*exclude, e)); }),
	                c.entries.end());
	if (c.entries.empty()) throw Error(path, 0, "no image left after --include/--exclude");
	return c;
}

}  // namespace talkhead::cli
