// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

namespace talkhead {

// A temporary name in the same folder as `path` (".tmp-<pid>-<name>", so a rename is atomic and the
// extension stays last). Registered with interrupt.h: call releaseTemporary once it is renamed or removed.
std::string temporaryNameFor(const std::string& path);

// Writes the bytes to a temporary name and renames it into place: a failure leaves no partial file.
// Throws Error("PATH: cannot write …").
void writeFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace talkhead
