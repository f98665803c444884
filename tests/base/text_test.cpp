// SPDX-License-Identifier: GPL-3.0-or-later
// Issue 15: messages are safe to print whatever the input held; text files in UTF-16 are read; JSON
// errors name line and column.
#include <gtest/gtest.h>

#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "base/ticks.h"

#include <cmath>

using namespace talkhead;

namespace {

bool validUtf8(const std::string& s) {
	for (std::size_t i = 0; i < s.size();) {
		const unsigned char c = static_cast<unsigned char>(s[i]);
		const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
		if (n == 0 || i + n > s.size()) return false;
		for (std::size_t k = 1; k < n; ++k)
			if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
		i += n;
	}
	return true;
}

std::string jsonError(const std::string& text) {
	try {
		parseJson(text, "x.json");
	} catch (const Error& e) {
		return e.what();
	}
	return "no error";
}

}  // namespace

TEST(Text, quotedEscapesControlsAndBadBytesAndCutsBetweenCharacters) {
	EXPECT_EQ(safeQuote("plain"), "plain");
	EXPECT_EQ(safeQuote("a\nb\tc\rd"), "a\\nb\\tc\\rd");
	EXPECT_EQ(safeQuote(std::string("a\0b", 3)), "a\\x00b");
	EXPECT_EQ(safeQuote("\x1b[31mred"), "\\x1b[31mred");
	EXPECT_EQ(safeQuote("caf\xc3\xa9"), "caf\xc3\xa9");                  // é kept
	EXPECT_EQ(safeQuote("\xd9 x"), "\\xd9 x");                             // a lone lead byte
	EXPECT_EQ(safeQuote("\xc0\xaf"), "\\xc0\\xaf");                        // overlong '/'
	EXPECT_EQ(safeQuote("\xed\xa0\x80"), "\\xed\\xa0\\x80");               // a surrogate
	EXPECT_EQ(safeQuote("\xc2\x85"), "\\u0085");                           // C1 NEL
	EXPECT_EQ(safeQuote("\xe0\xb4\x80"), "\xe0\xb4\x80");                  // U+0D00 is a character
	// Cut between characters: 'ééé' is 6 bytes; at most 5 gives 'éé…'.
	EXPECT_EQ(safeQuote("\xc3\xa9\xc3\xa9\xc3\xa9", 5), "\xc3\xa9\xc3\xa9…");
	const std::string big(200000, 'x');
	EXPECT_LE(safeQuote(big).size(), 60u + 3);
	// Whatever bytes come in, what goes out is one line of valid UTF-8.
	std::string all;
	for (int i = 0; i < 256; ++i) all += char(i);
	for (std::size_t max : {std::size_t(7), std::size_t(60), std::string::npos}) {
		const std::string q = safeQuote(all + all, max);
		EXPECT_TRUE(validUtf8(q)) << max;
		EXPECT_EQ(q.find('\n'), std::string::npos);
	}
}

TEST(Text, safeLineBoundsAMessageKeepingItsStartAndEnd) {
	const std::string m = "file.tsv:3: unknown phone '" + std::string(200000, 'a') + "\n\x01' (known: p, b)";
	const std::string s = safeLine(m);
	EXPECT_LE(s.size(), 1010u);
	EXPECT_EQ(s.rfind("file.tsv:3: unknown phone 'aaa", 0), 0u);
	EXPECT_NE(s.find(" … "), std::string::npos);
	EXPECT_TRUE(endsWith(s, "aaa\\n\\x01' (known: p, b)")) << s.substr(s.size() - 40);
	EXPECT_TRUE(validUtf8(s));
	EXPECT_EQ(safeLine("short"), "short");
}

TEST(Text, decodeTextReadsUtf16WithAndWithoutBom) {
	const std::string le("\xff\xfe" "a\0\xe9\0", 6), be("\xfe\xff\0a\0\xe9", 6);
	EXPECT_EQ(decodeText(le), "a\xc3\xa9");
	EXPECT_EQ(decodeText(be), "a\xc3\xa9");
	EXPECT_EQ(decodeText(std::string("n\0a\0m\0e\0,\0x\0", 12)), "name,x");  // no BOM
	EXPECT_EQ(decodeText("\xef\xbb\xbfname,x"), "name,x");
	EXPECT_EQ(decodeText("name,x"), "name,x");
	EXPECT_EQ(decodeText(std::string("\xff\xfe\x00\xd8", 4)), "\xef\xbf\xbd");  // a lone surrogate → U+FFFD
}

TEST(Json, valuesKeepOrderAndRepeatedNames) {
	const JsonValue v = parseJson("{\"b\": 1, \"a\": [true, null, \"\\u00e9\\ud83d\\ude00\"], \"b\": -2.5e1}", "x.json");
	ASSERT_EQ(v.kind, JsonValue::Kind::Object);
	ASSERT_EQ(v.object.size(), 3u);
	EXPECT_EQ(v.object[0].first, "b");
	EXPECT_EQ(v.object[2].second.number, -25);
	const JsonValue& a = *v.find("a");
	ASSERT_EQ(a.array.size(), 3u);
	EXPECT_TRUE(a.array[0].boolean);
	EXPECT_EQ(a.array[1].kind, JsonValue::Kind::Null);
	EXPECT_EQ(a.array[2].string, "\xc3\xa9\xf0\x9f\x98\x80");
	EXPECT_EQ(jsonQuote("a\"\\\n\x01\xc3\xa9"), "\"a\\\"\\\\\\n\\u0001\xc3\xa9\"");
	EXPECT_EQ(jsonQuote("\xff"), "\"\xef\xbf\xbd\"");  // invalid UTF-8 is replaced, not written raw
}

TEST(Json, errorsNameLineAndColumn) {
	EXPECT_EQ(jsonError("{\n  \"a\": tru\n}"), "x.json:2: malformed JSON: column 11: syntax error while parsing value - invalid literal; last read: '\"a\": tru<U+000A>'");
	EXPECT_EQ(jsonError("[1, 2"), "x.json:1: malformed JSON: column 6: syntax error while parsing array - unexpected end of input; expected ']'");
	EXPECT_NE(jsonError("[1] x").find("x.json:1: malformed JSON: column 5:"), std::string::npos) << jsonError("[1] x");
	EXPECT_NE(jsonError(std::string(100, '[') + std::string(100, ']')).find("nested too deeply"), std::string::npos);
	EXPECT_NE(jsonError("\"\xff\"").find("x.json:1: malformed JSON: column 2:"), std::string::npos) << jsonError("\"\xff\"");
	EXPECT_NE(jsonError("").find("x.json:1: malformed JSON"), std::string::npos);
	EXPECT_NE(jsonError("1e999").find("malformed JSON"), std::string::npos) << jsonError("1e999");
}

TEST(Ticks, conversionSaturatesInsteadOfOverflowing) {
	EXPECT_EQ(ticksFromSeconds(1.5).count(), 1058400000);
	EXPECT_EQ(ticksFromSeconds(1e20), ticksFromSeconds(1e9));
	EXPECT_EQ(ticksFromSeconds(-1e300), ticksFromSeconds(-1e9));
	EXPECT_GT(ticksFromSeconds(1e20).count(), 0);
	EXPECT_EQ(ticksFromSeconds(std::nan("")).count(), 0);
	EXPECT_EQ(ticksFromSeconds(HUGE_VAL), ticksFromSeconds(1e9));
}

// Issue 30: one-line JSON is written by JsonObject, in the order added, escaped, never invalid.
TEST(JsonObject, membersInOrderEscapedAndNeverInvalid) {
	const std::string j = JsonObject()
	                          .add("type", "mark")
	                          .add("name", "a \"quoted\"\nname")
	                          .add("frame", 12)
	                          .add("time", 1.23456, "%.3f")
	                          .add("ok", true)
	                          .add("nan", std::nan(""), "%.3f")
	                          .raw("list", "[1, 2]")
	                          .str();
	EXPECT_EQ(j, R"({"type": "mark", "name": "a \"quoted\"\nname", "frame": 12, "time": 1.235, "ok": true, "nan": null, "list": [1, 2]})");
	EXPECT_EQ(parseJson(j, "j").find("name")->string, "a \"quoted\"\nname");
	EXPECT_EQ(JsonObject().str(), "{}");
}

