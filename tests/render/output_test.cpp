// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <filesystem>

#include "base/error.h"
#include "render/output.h"

using namespace talkhead;

namespace {
std::string fieldOf(const std::function<void()>& f) {
	try {
		f();
	} catch (const FieldError& e) {
		return e.field();
	}
	return "";
}
}  // namespace

TEST(OutputFormats, oneRegistryByNameAndByExtension) {
	EXPECT_EQ(findOutputFormat("webm")->format, VideoFormat::Webm);
	EXPECT_EQ(findOutputFormat("mkv"), nullptr);
	EXPECT_EQ(outputFormatForPath("take.WEBM")->format, VideoFormat::Webm);
	EXPECT_EQ(outputFormatForPath("a/b.m4v")->format, VideoFormat::Mp4);
	EXPECT_EQ(outputFormatForPath("frames.y4m")->format, VideoFormat::Y4m);
	EXPECT_EQ(outputFormatForPath("/dev/null"), nullptr);
	EXPECT_EQ(outputFormatNames(), "mp4, webm or y4m");
	EXPECT_TRUE(outputFormat(VideoFormat::Mp4Stream).stream);
	// The format of a file: named, else by its extension, else MP4; a name against the extension is ambiguous.
	EXPECT_EQ(videoFormatFor("x.webm", ""), VideoFormat::Webm);
	EXPECT_EQ(videoFormatFor("-", "y4m"), VideoFormat::Y4m);
	EXPECT_EQ(videoFormatFor("out", ""), VideoFormat::Mp4);
	EXPECT_EQ(fieldOf([] { videoFormatFor("x.webm", "mp4"); }), "format");
	EXPECT_EQ(fieldOf([] { videoFormatFor("x", "mp4-stream"); }), "format");
	EXPECT_EQ(fieldOf([] { videoFormatFor("x", "gif"); }), "format");
}

TEST(OutputFormats, aSpecTheFormatCannotWriteNamesItsField) {
	OutputSpec s;
	s.path = "x.mp4";
	s.crf = 52;
	EXPECT_EQ(fieldOf([&] { makeVideoSink(s, nullptr); }), "crf");
	s.crf = -1, s.alpha = true;
	EXPECT_EQ(fieldOf([&] { makeVideoSink(s, nullptr); }), "background");
	s.alpha = false, s.path = "-";
	EXPECT_EQ(fieldOf([&] { makeVideoSink(s, nullptr); }), "output");
	s.format = VideoFormat::Webm, s.path = "x.webm", s.crf = 63, s.alpha = true;
	EXPECT_NE(makeVideoSink(s, nullptr), nullptr);  // VP9's scale, with alpha
	s.format = VideoFormat::Mp4Stream, s.crf = -1;
	EXPECT_EQ(fieldOf([&] { makeVideoSink(s, nullptr); }), "background");
	s.alpha = false;
	EXPECT_EQ(fieldOf([&] { makeVideoSink(s, nullptr); }), "output");  // a stream needs somewhere to write
}

TEST(OutputFormats, serveStreamIsAFrameSinkThatWritesAnInitSegmentAndFragments) {
	std::string bytes;
	OutputSpec s;
	s.format = VideoFormat::Mp4Stream;
	s.threads = 1;
	s.write = [&](const std::uint8_t* d, std::size_t n) {
		bytes.append(reinterpret_cast<const char*>(d), n);
		return true;
	};
	auto sink = makeVideoSink(s, nullptr);
	StreamInfo info;
	info.width = 64, info.height = 48, info.rate = FrameRate{25, 1};
	sink->begin(info);
	EXPECT_EQ(sink->codecs().rfind("avc1.", 0), 0u) << sink->codecs();
	ASSERT_GE(bytes.size(), 8u);
	EXPECT_EQ(bytes.substr(4, 4), "ftyp");  // the init segment, before any frame
	const std::size_t init = bytes.size();
	YuvImage frame;
	frame.resize(64, 48);
	Points points;
	for (int n = 0; n < 3; ++n) {
		RenderedFrame f;
		f.index = n, f.yuv = &frame, f.points = &points;
		sink->frame(f);
	}
	EXPECT_GT(bytes.size(), init);
	EXPECT_NE(bytes.find("moof", init), std::string::npos);  // fragments, as frames come
}
