// SPDX-License-Identifier: GPL-3.0-or-later
// Every phone espeak-ng says for a language is in that language's tables (issue 28 item 9: say in en-US
// refused "science", "quiet", "diet": espeak-ng's aɪə was missing). The phones are enumerated from
// espeak-ng itself over a dictionary word list of the language (Debian's wamerican, wngerman, wfrench,
// wspanish, witalian, wbrazilian; every word).
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "phonetics/espeak.h"
#include "phonetics/language.h"

namespace talkhead {
namespace {

std::vector<std::string> wordList(const std::string& path, std::size_t most) {
	std::ifstream in(path);
	std::vector<std::string> all;
	for (std::string w; std::getline(in, w);)
		if (!w.empty() && w.find('\'') == std::string::npos) all.push_back(w);
	if (all.size() <= most) return all;
	std::vector<std::string> some;
	const std::size_t step = (all.size() + most - 1) / most;
	for (std::size_t i = 0; i < all.size(); i += step) some.push_back(all[i]);
	return some;
}

struct Case {
	const char* lang;
	const char* dict;
};

class EspeakPhones : public ::testing::TestWithParam<Case> {};

TEST_P(EspeakPhones, everyPhoneOfTheWordListIsKnown) {
	const Case c = GetParam();
	const std::string dict = std::string("/usr/share/dict/") + c.dict;
	if (!std::ifstream(dict)) GTEST_SKIP() << dict << " is not installed (scripts/setup-deps installs it)";
	const std::vector<std::string> words = wordList(dict, 400000);
	ASSERT_GT(words.size(), 10000u);
	const Language& lang = Language::get(c.lang);
	const std::map<std::string, std::string> phones = espeakPhonemeNames(words, espeakVoiceFor(c.lang));
	ASSERT_GT(phones.size(), 20u);
	std::string unknown;
	for (const auto& [p, word] : phones)  // read as say and word-level transcripts read them
		if (!lang.normalize(p, Notation::Espeak)) unknown += " '" + p + "' (" + word + ")";
	EXPECT_TRUE(unknown.empty()) << c.lang << ": espeak-ng phones the tables lack:" << unknown << " (of " << phones.size() << ")";
}

INSTANTIATE_TEST_SUITE_P(Languages, EspeakPhones,
                         ::testing::Values(Case{"en-US", "american-english"}, Case{"de", "ngerman"}, Case{"fr", "french"}, Case{"es", "spanish"},
                                           Case{"it", "italian"}, Case{"pt-BR", "brazilian"}),
                         [](const auto& info) {
	                         std::string n = info.param.lang;
	                         for (char& ch : n)
		                         if (ch == '-') ch = '_';
	                         return n;
                         });

// The words that were refused (item 9) become phones.
TEST(EspeakPhones, wordsWithTriphthongsSayInEnglish) {
	const Language& lang = Language::get("en-US");
	for (const char* w : {"science", "quiet", "diet", "client", "society", "violent", "fire", "our", "hour"}) {
		Transcript t;
		t.level = LabelLevel::Word;
		t.path = "words";
		t.intervals.push_back({Ticks(0), ticksFromSeconds(0.6), w, 1});
		EXPECT_NO_THROW(phoneSegments(t, lang)) << w;
	}
}

}  // namespace
}  // namespace talkhead
