// SPDX-License-Identifier: GPL-3.0-or-later
// What every libFuzzer target shares (tests/fuzz/README.md): talkhead::Error is the expected answer to bad
// input; anything else that leaves a parser (another exception, a crash, a sanitizer report, a hang) is a
// finding. Readers that take a path get the input through a file of this process's own.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <typeinfo>

#include "base/error.h"

namespace talkhead::fuzz {

// A folder of this process's own (in /dev/shm when it can, for speed), removed at exit.
const std::string& tempDir();

// Writes the input to tempDir()/name (replacing what the last input left) and returns the path.
std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& name);
std::string writeInput(const std::string& bytes, const std::string& name);

// Runs `parse`: a talkhead::Error is the parser rejecting bad input (fine); any other exception is a
// finding, reported with its type and message before aborting (libFuzzer saves the input).
template <class F>
void expectOnlyErrors(F&& parse) {
	try {
		parse();
	} catch (const talkhead::Error&) {
	} catch (const std::exception& e) {
		std::fprintf(stderr, "\n==fuzz== uncaught %s (not talkhead::Error): %s\n", typeid(e).name(), e.what());
		std::abort();
	} catch (...) {
		std::fprintf(stderr, "\n==fuzz== uncaught exception of unknown type (not talkhead::Error)\n");
		std::abort();
	}
}

// A broken promise of the parser (its output violates what the header documents): a finding.
[[noreturn]] void violated(const char* what, const std::string& detail = "");
#define TALKHEAD_FUZZ_CHECK(cond, detail) \
	do { \
		if (!(cond)) ::talkhead::fuzz::violated(#cond, detail); \
	} while (0)

}  // namespace talkhead::fuzz
