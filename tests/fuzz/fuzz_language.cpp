// SPDX-License-Identifier: GPL-3.0-or-later
// A language's tables (src/phonetics/language.cpp, phonetics/<tag>/): the input is inventory.tsv, a
// form feed ('\f'), then symbols.tsv (the seeds are the shipped tables joined so, made by CMake); both
// are written to the process's folder and read by the Language constructor, and a few labels looked up.
#include <string>

#include "fuzz_support.h"
#include "phonetics/language.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string bytes(reinterpret_cast<const char*>(data), size);
	const std::size_t ff = bytes.find('\f');
	fuzz::writeInput(bytes.substr(0, ff), "inventory.tsv");
	fuzz::writeInput(ff == std::string::npos ? std::string() : bytes.substr(ff + 1), "symbols.tsv");
	fuzz::expectOnlyErrors([&] {
		const Language lang("xx", fuzz::tempDir());
		for (const char* label : {"a", "S", "tS", "ˈaː", "AH0", "t͡ʃ", "sil", "_"})
			for (Notation n : {Notation::Auto, Notation::Ipa, Notation::Arpabet, Notation::Xsampa}) {
				if (auto phones = lang.normalize(label, n))
					for (const std::string& p : *phones) lang.info(p);  // a phone the table gives is in its inventory
				lang.nearest(label, n);
			}
		lang.inventoryList();
	});
	return 0;
}
