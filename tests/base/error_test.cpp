// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "base/error.h"

using namespace talkhead;

namespace {
std::optional<std::string> asFlag(const std::string& f) { return "--" + f; }
std::optional<std::string> onlyLang(const std::string& f) { return f == "lang" ? std::optional<std::string>("the request's 'lang'") : std::nullopt; }
}  // namespace

TEST(WordFields, theCommandLineNamesItsFlagsAndAClientOnlyWhatItCanSet) {
	const std::string m = "3 tiers: choose with {{tier}} NAME (or {{level}} words); check {{lang}} and {{notation}}";
	EXPECT_EQ(wordFields(m, asFlag), "3 tiers: choose with --tier NAME (or --level words); check --lang and --notation");
	// A client cannot give a tier or a notation: those clauses go, its own member is named.
	EXPECT_EQ(wordFields("no table for 'xx' (languages: en-US; {{generic-visemes}} maps IPA); give {{lang}}", onlyLang),
	          "no table for 'xx' (languages: en-US); give the request's 'lang'");
	EXPECT_EQ(wordFields("unknown phone 'x' ({{unknown}} nearest picks the closest)", onlyLang), "unknown phone 'x'");
	// A message only about the field keeps its bare name; braces that are not a field stay as they are.
	EXPECT_EQ(wordFields("{{max-sessions}} must be at least 1", onlyLang), "max-sessions must be at least 1");
	EXPECT_EQ(wordFields(R"(send {"type": "auth"} first)", asFlag), R"(send {"type": "auth"} first)");
	EXPECT_EQ(wordFields("half {{open", asFlag), "half {{open");
	EXPECT_EQ(wordFields("unknown emotion '{{Joy Ful}}' ({{lang}})", onlyLang), "unknown emotion '{{Joy Ful}}' (the request's 'lang')");
	EXPECT_EQ(fieldRef("tier"), "{{tier}}");
}

TEST(FieldError, namesItsField) {
	try {
		throw FieldError("crf", "webm's quality runs from 0 to 63");
	} catch (const Error& e) {
		EXPECT_STREQ(e.what(), "webm's quality runs from 0 to 63");
		EXPECT_EQ(dynamic_cast<const FieldError&>(e).field(), "crf");
	}
}
