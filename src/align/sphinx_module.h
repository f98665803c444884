// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The pocketsphinx plugin (libtalkhead-sphinx.so): CMU PocketSphinx's phone-loop decoder (Debian
// libpocketsphinx3, acoustic model and phone language model from pocketsphinx-en-us). Loaded by the first
// command that recognises speech, so the others start without it. Built from the same tree, so C++ types
// cross the boundary; errors come back as strings.
#include <cstdint>
#include <string>
#include <vector>

namespace talkhead {

constexpr int kSphinxModuleAbi = 1;

// The decoder's settings (recognize.h chooses them).
struct SphinxConfig {
	std::string modelDir;    // holds en-us/ (the acoustic model) and en-us-phone.lm.bin
	double beam = 1e-20, phoneBeam = 1e-20;
	double languageWeight = 2.0;
};

// One recognised phone (ARPAbet, "SIL" for silence, "+NSN+"-style fillers for noises) over frames
// [start, end) of the utterance (100 frames per second).
struct SphinxPhone {
	int start = 0, end = 0;
	std::string phone;
};

struct SphinxModule {
	int abi;  // kSphinxModuleAbi
	// Loads the acoustic model and the phone language model; an opaque handle, or nullptr with `error` set.
	void* (*open)(const SphinxConfig& config, std::string& error);
	// Decodes one utterance of 16 kHz mono 16-bit samples.
	bool (*decode)(void* handle, const std::int16_t* samples, std::size_t count, std::vector<SphinxPhone>& phones, std::string& error);
	void (*close)(void* handle);
};

}  // namespace talkhead

extern "C" const void* talkhead_sphinx_module();
