// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead serve's requests (issue 16): parsing, and timing from Azure viseme events and ElevenLabs
// character timestamps.
#include <gtest/gtest.h>

#include <cmath>

#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "media/audio.h"
#include "perform/plan.h"
#include "phonetics/language.h"
#include "serve/access.h"
#include "serve/server.h"
#include "test_support.h"

using namespace talkhead;
using talkhead::test::errorOf;

TEST(LiveRequest, parsesEachTypeAndRefusesWhatIsWrong) {
	const LiveRequest say = parseLiveRequest(R"({"type": "say", "id": 7, "text": "Olá", "lang": "pt-BR", "emotion": "happy", "intensity": 0.5})");
	EXPECT_EQ(say.kind, LiveRequest::Kind::Say);
	EXPECT_EQ(say.id, "7");
	EXPECT_EQ(say.expression.value_or(Expression()).emotion().label(), "joy");  // an alias
	EXPECT_DOUBLE_EQ(say.expression->intensity(), 0.5);
	EXPECT_EQ(parseLiveRequest(R"({"type": "stop"})").kind, LiveRequest::Kind::Stop);
	const LiveRequest e = parseLiveRequest(R"({"type": "emotion", "emotion": "anger", "ramp": 1.5})");
	EXPECT_EQ(e.ramp, ticksFromSeconds(1.5));
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "emotion"})"); }).find("'emotion' is missing"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "emotion", "emotion": "grumpy"})"); }).find("unknown emotion 'grumpy'"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "say", "text": "x", "rate": 9000})"); }).find("'rate' must be from 80 to 450"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"([1, 2])"); }).find("a JSON object"), std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "!!!", "transcript": ""})"); }).find("not base64"), std::string::npos);
	// Issue 49: speak's timing is at most one member; with none the phones are recognised, with `text` aligned.
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "AAAA", "transcript": "x", "text": "y"})"); }).find("at most one of 'transcript', 'text'"),
	          std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "AAAA", "text": "  "})"); }).find("'text' is empty"), std::string::npos);
	const LiveRequest alone = parseLiveRequest(R"({"type": "speak", "audio": "AAAA"})");
	EXPECT_TRUE(alone.transcript.empty() && alone.text.empty() && !alone.timing);
	EXPECT_EQ(parseLiveRequest(R"({"type": "speak", "audio": "AAAA", "text": "bin blue"})").text, "bin blue");
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "AAAA", "visemes": [{"id": 22, "offset_ms": 0}]})"); }).find("id 22 is not 0-21"),
	          std::string::npos);
	EXPECT_NE(errorOf([] { parseLiveRequest(R"({"type": "speak", "audio": "AAAA", "visemes": [{"id": 1, "offset_ms": 90}, {"id": 2, "offset_ms": 10}]})"); })
	              .find("comes before"),
	          std::string::npos);
}

TEST(LiveRequest, azureVisemesAndElevenLabsCharactersBecomeTimings) {
	// Azure: offsets in ms, or the SDK's AudioOffset in 100 ns; each viseme lasts until the next.
	const LiveRequest az = parseLiveRequest(
	    R"({"type": "speak", "audio": "AAAA", "visemes": [{"id": 0, "offset_ms": 0}, {"VisemeId": 21, "AudioOffset": 500000}, {"id": 2, "offset_ms": 120}]})");
	ASSERT_TRUE(az.timing);
	EXPECT_EQ(az.timing->level, LabelLevel::Viseme);
	EXPECT_EQ(az.timing->visemeScheme, "azure");
	ASSERT_EQ(az.timing->intervals.size(), 3u);
	EXPECT_EQ(az.timing->intervals[1].label, "21");
	EXPECT_EQ(az.timing->intervals[1].start, ticksFromSeconds(0.05));
	EXPECT_EQ(az.timing->intervals[1].end, ticksFromSeconds(0.12));
	// Their CDVs through phonetics/viseme-input.tsv.
	Transcript t = *az.timing;
	t.intervals.back().end = ticksFromSeconds(0.3);
	const auto phones = phoneSegments(t, Language::get("en-US"));
	ASSERT_EQ(phones.size(), 3u);
	EXPECT_EQ(phones[0].cdv, "sil");
	EXPECT_EQ(phones[1].cdv, "p1");
	EXPECT_EQ(phones[2].cdv, "a");
	// ElevenLabs: characters grouped into words at spaces.
	const LiveRequest el = parseLiveRequest(
	    R"({"type": "speak", "audio": "AAAA", "alignment": {"characters": ["H", "i", " ", "y", "o", "u"],
	        "character_start_times_seconds": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6], "character_end_times_seconds": [0.2, 0.3, 0.4, 0.5, 0.6, 0.7]}})");
	ASSERT_TRUE(el.timing);
	EXPECT_EQ(el.timing->level, LabelLevel::Word);
	ASSERT_EQ(el.timing->intervals.size(), 2u);
	EXPECT_EQ(el.timing->intervals[0].label, "Hi");
	EXPECT_EQ(el.timing->intervals[0].start, ticksFromSeconds(0.1));
	EXPECT_EQ(el.timing->intervals[0].end, ticksFromSeconds(0.3));
	EXPECT_EQ(el.timing->intervals[1].label, "you");
	EXPECT_EQ(el.timing->intervals[1].start, ticksFromSeconds(0.4));
}

// Issue 28: who may connect (Host, Origin, token), each rule on its own.
TEST(ServeAccess, hostsOriginsAndTokens) {
	AccessPolicy loop;
	loop.listenHost = "127.0.0.1";
	EXPECT_FALSE(refusedHost(loop, "127.0.0.1:8765"));
	EXPECT_FALSE(refusedHost(loop, "localhost:8765"));
	EXPECT_FALSE(refusedHost(loop, "[::1]:8765"));
	EXPECT_FALSE(refusedHost(loop, "LOCALHOST."));
	EXPECT_TRUE(refusedHost(loop, "evil.example:8765"));    // DNS rebinding
	EXPECT_TRUE(refusedHost(loop, "192.0.2.7:8765"));       // not the listen address
	EXPECT_TRUE(refusedHost(loop, ""));
	AccessPolicy all = loop;
	all.listenHost = "0.0.0.0";
	EXPECT_FALSE(refusedHost(all, "192.0.2.7:8765"));       // any address of the machine
	EXPECT_TRUE(refusedHost(all, "talk.example.org"));      // names only when allowed
	all.allowHosts = {"talk.example.org"};
	EXPECT_FALSE(refusedHost(all, "Talk.Example.org:443"));
	AccessPolicy one = loop;
	one.listenHost = "192.0.2.7";
	EXPECT_FALSE(refusedHost(one, "192.0.2.7:8765"));
	EXPECT_TRUE(refusedHost(one, "192.0.2.8:8765"));

	EXPECT_FALSE(refusedOrigin(loop, "", "127.0.0.1:8765", false));  // not a browser
	EXPECT_FALSE(refusedOrigin(loop, "http://127.0.0.1:8765", "127.0.0.1:8765", false));
	EXPECT_FALSE(refusedOrigin(loop, "http://localhost:3000", "127.0.0.1:8765", false));  // a loopback page
	EXPECT_FALSE(refusedOrigin(loop, "https://app.localhost", "127.0.0.1:8765", false));
	EXPECT_TRUE(refusedOrigin(loop, "http://evil.example", "127.0.0.1:8765", false));
	EXPECT_TRUE(refusedOrigin(loop, "http://127.0.0.1.evil.example", "127.0.0.1:8765", false));
	EXPECT_TRUE(refusedOrigin(loop, "null", "127.0.0.1:8765", false));
	EXPECT_TRUE(refusedOrigin(loop, "file://", "127.0.0.1:8765", false));
	EXPECT_FALSE(refusedOrigin(all, "https://talk.example.org", "talk.example.org", true));  // its own origin over TLS
	EXPECT_TRUE(refusedOrigin(all, "http://talk.example.org", "talk.example.org", true));    // not its scheme
	AccessPolicy allowed = loop;
	allowed.allowOrigins = {"https://app.example.com"};
	EXPECT_FALSE(refusedOrigin(allowed, "https://app.example.com/", "127.0.0.1:8765", false));
	EXPECT_TRUE(refusedOrigin(allowed, "https://app.example.com.evil", "127.0.0.1:8765", false));
	allowed.allowOrigins = {"null"};
	EXPECT_FALSE(refusedOrigin(allowed, "null", "127.0.0.1:8765", false));

	EXPECT_EQ(bearerToken("Bearer abc.def").value_or(""), "abc.def");
	EXPECT_EQ(bearerToken("  bearer   xyz ").value_or(""), "xyz");
	EXPECT_FALSE(bearerToken("Basic dXNlcg=="));
	EXPECT_TRUE(sameToken("s3cret-s3cret-s3cret", "s3cret-s3cret-s3cret"));
	EXPECT_FALSE(sameToken("s3cret-s3cret-s3cret", "s3cret-s3cret-s3creT"));
	EXPECT_FALSE(sameToken("s3cret-s3cret-s3cret", "s3cret"));
	EXPECT_FALSE(sameToken("", ""));  // no token set: nothing matches it
}

// Issue 28 items 4 and 10: a request's size in values is bounded, and its id is read even from a text that
// cannot be parsed.
TEST(LiveRequest, boundedInValuesAndItsIdFoundInBrokenText) {
	std::string many = R"({"type": "say", "text": "hi", "junk": [)";
	for (std::size_t i = 0; i < kMaxRequestValues; ++i) many += i ? ",0" : "0";
	many += "]}";
	EXPECT_NE(errorOf([&] { parseLiveRequest(many); }).find("more values than a request may hold"), std::string::npos);
	EXPECT_EQ(jsonTopLevelMember(R"({"type": "say", "id": "a1", "text": )", "id").value_or(""), "a1");
	EXPECT_EQ(jsonTopLevelMember(R"({"id": 42, "type": "say")", "id").value_or(""), "42");
	EXPECT_EQ(jsonTopLevelMember(R"({"x": {"id": "inner"}, "id": "outer"})", "id").value_or(""), "outer");
	EXPECT_FALSE(jsonTopLevelMember(R"({"x": {"id": "inner"}})", "id"));
	EXPECT_FALSE(jsonTopLevelMember(R"({"id": {"a": 1}})", "id"));
	EXPECT_FALSE(jsonTopLevelMember("garbage", "id"));
}

// Issue 28 items 1 and 5: voices checked against espeak-ng's lists; synthesis bounded and cancellable.
TEST(LiveRequest, voicesAreCheckedAndSpeechIsBounded) {
	EXPECT_EQ(checkedEspeakVoice("en-us"), "en-us");
	EXPECT_EQ(checkedEspeakVoice("en-us+f3"), "en-us+f3");
	EXPECT_EQ(checkedEspeakVoice("en-us+3"), "en-us+m3");
	EXPECT_EQ(checkedEspeakVoice("pt-BR"), "pt-BR");
	for (const std::string bad : {"en-us+" + std::string(40, 'a'), std::string("en-us+../x"), std::string("nowhere"), std::string(200, 'e'), std::string("en us"),
	                              std::string("en-us+"), std::string("")})
		EXPECT_THROW(checkedEspeakVoice(bad), Error) << bad;
	const Language& en = Language::get("en-US");
	SpeechLimits l;
	l.maxBreakSeconds = 5;
	EXPECT_NE(errorOf([&] { speakText(R"(<speak>a <break time="3s"/> b <break time="3s"/> c</speak>)", en, "", 22050, 0, -1, l); }).find("breaks add up to 6.0 s"),
	          std::string::npos);
	l.maxBreakSeconds = 0;
	l.maxSeconds = 1;
	EXPECT_NE(errorOf([&] { speakText("This sentence takes quite a lot longer than one second to say out loud.", en, "", 22050, 0, -1, l); }).find("longer than 1 s"),
	          std::string::npos);
	EXPECT_NE(errorOf([&] { speakText(R"(<speak>Hello <break time="2s"/> there</speak>)", en, "", 22050, 0, -1, l); }).find("breaks add up to 2.0 s"),
	          std::string::npos);
	std::atomic<bool> cancel{true};
	l = {};
	l.cancel = &cancel;
	EXPECT_THROW(speakText("Cancelled before it says anything.", en, "", 22050, 0, -1, l), SpeechCancelled);
	l = {};
	l.maxSeconds = 10;
	const Utterance u = speakText("Short enough.", en, "", 22050, 0, -1, l);
	EXPECT_GT(u.audio.duration(), ticksFromSeconds(0.3));
}

// Issue 29: errors a WebSocket client gets never ask it for a command-line flag.
TEST(LiveRequest, speakErrorsSpeakToTheClientNotTheCommandLine) {
	LiveRequest r;
	r.kind = LiveRequest::Kind::Speak;
	r.audio = std::string(6400, '\0');  // 0.2 s of 16-kHz silence
	r.pcmRate = 16000;
	r.lang = "en-US";
	r.transcript = "0\t0.1\ta\n0.1\t0.2\tqq\n";
	const std::string e = errorOf([&] { prepareUtterance(r, "en-US", 22050); });
	EXPECT_NE(e.find("unknown en-US phone 'qq'"), std::string::npos) << e;
	EXPECT_EQ(e.find("--"), std::string::npos) << e;
	r.lang = "xx-YY";
	const std::string l = errorOf([&] { prepareUtterance(r, "en-US", 22050); });
	EXPECT_EQ(l.find("--"), std::string::npos) << l;
}

// Issue 49: a speak with its text gives the phones `render --audio A --text T` gives, within a frame; with
// no timing, the phones recognised from its audio (the shipped GRID clip's, as a WAV in memory).
TEST(LiveRequest, speakWithTextAlignsAndSpeakAloneRecognises) {
	const std::string clip = std::string(TALKHEAD_TEST_DATA_DIR) + "/../../models/faces/grid-s4/s4hq_pbbc4a.mpg";
	const std::string wavPath = test::tempDir("speak-text") + "/s.wav";
	writeWav(wavPath, decodeAudio(clip, 22050));
	const std::string text = "place blue by c four again";
	LiveRequest r;
	r.kind = LiveRequest::Kind::Speak;
	r.audio = readTextFile(wavPath);
	r.lang = "en-US";
	r.text = text;
	const Utterance u = prepareUtterance(r, "en-US", 48000);
	const TimedSpeech offline = speechFromText(text, wavPath, Language::get("en-US"));
	ASSERT_EQ(u.phones.size(), offline.phones.size());
	for (std::size_t k = 0; k < u.phones.size(); ++k) {
		EXPECT_EQ(u.phones[k].phone, offline.phones[k].phone) << k;
		EXPECT_LE(std::abs(toSeconds(u.phones[k].start - offline.phones[k].start)), 1.0 / 30) << k;
	}
	r.text.clear();
	const Utterance heard = prepareUtterance(r, "en-US", 48000);
	int spoken = 0;
	for (const PhoneSegment& p : heard.phones) spoken += p.cdv.label() != "sil";
	EXPECT_GE(spoken, 10);
	EXPECT_EQ(heard.phones.back().end, heard.audio.duration());
}
