// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

namespace talkhead {

// Nothing left behind on a stop (issue 15): every temporary name (atomic_file.h's temporaryNameFor) is
// registered here, and SIGINT, SIGTERM and SIGHUP remove every registered temporary that still exists,
// print "talkhead: interrupted" and exit at once (130, 143, 129), whatever the process was doing; a
// second signal does the same. SIGINT and SIGHUP that were ignored when the process started (a background
// job, nohup) stay ignored. Temporary names are never final names, so removing one that was already
// renamed or deleted is harmless.
void installInterruptHandlers();

// Registers a temporary path (a file or an empty-after-use folder); released once renamed or removed.
void registerTemporary(const std::string& path);
void releaseTemporary(const std::string& path);
// A temporary folder whose contents (files, empty subfolders) are removed on a signal too; released
// with releaseTemporary.
void registerTemporaryFolder(const std::string& path);
// A child process working for this one (0: none): a signal is passed on to it before this process exits.
void setInterruptChild(int pid);

}  // namespace talkhead
