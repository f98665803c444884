// SPDX-License-Identifier: GPL-3.0-or-later
// The registry of video formats (render/output.h): each entry's checks and the sink it makes.
#include "render/output.h"

#include <filesystem>

#include "base/error.h"
#include "base/text.h"
#include "media/video_writer.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {

// serve's stream: fragmented MP4 handed to a byte callback as it is made (media/video_writer.h). The init
// segment is written by begin(); nothing is renamed, nothing is removed (a stream cut is a stream cut).
class StreamSink final : public FrameSink {
public:
	StreamSink(const OutputSpec& spec, std::unique_ptr<AudioSource> audio) : spec_(spec), audio_(std::move(audio)) {}
	void begin(const StreamInfo& info) override {
		VideoOptions vo;
		vo.width = info.width, vo.height = info.height, vo.rate = info.rate;
		vo.crf = spec_.crf, vo.preset = spec_.preset, vo.threads = spec_.threads;
		writer_ = std::make_unique<Mp4LiveWriter>(spec_.write, vo, audio_.get());
	}
	std::string codecs() const override { return writer_ ? writer_->codecs() : std::string(); }
	void frame(const RenderedFrame& f) override { writer_->write(*f.yuv); }
	void finish() override { writer_->finish(); }

private:
	OutputSpec spec_;
	std::unique_ptr<AudioSource> audio_;  // declared before the writer: outlives it
	std::unique_ptr<Mp4LiveWriter> writer_;
};

std::vector<OutputFormat> makeRegistry() {
	std::vector<OutputFormat> r;
	OutputFormat mp4{VideoFormat::Mp4, "mp4", {".mp4", ".m4v", ".mov"}, "H.264 + AAC"};
	mp4.audio = true, mp4.preset = true, mp4.crfDefault = 20, mp4.crfMax = 51;
	mp4.make = [](const OutputSpec& s, std::unique_ptr<AudioSource> audio) {
		return makeMp4Sink(s.path, Mp4Settings{s.crf, s.preset}, std::move(audio));
	};
	r.push_back(std::move(mp4));
	OutputFormat webm{VideoFormat::Webm, "webm", {".webm"}, "VP9 + Vorbis, with the face's matte as alpha when asked"};
	webm.alpha = true, webm.audio = true, webm.crfDefault = 32, webm.crfMax = 63;
	webm.make = [](const OutputSpec& s, std::unique_ptr<AudioSource> audio) {
		return makeWebmSink(s.path, WebmSettings{s.crf, s.alpha}, std::move(audio));
	};
	r.push_back(std::move(webm));
	OutputFormat y4m{VideoFormat::Y4m, "y4m", {".y4m"}, "raw YUV4MPEG2 frames, no sound (e.g. -o - | ffplay -)"};
	y4m.standardOutput = true;
	y4m.make = [](const OutputSpec& s, std::unique_ptr<AudioSource>) { return makeY4mSink(s.path); };
	r.push_back(std::move(y4m));
	OutputFormat stream{VideoFormat::Mp4Stream, "mp4-stream", {}, "H.264 + AAC as fragmented MP4 for Media Source Extensions (serve)"};
	stream.audio = true, stream.stream = true, stream.preset = true, stream.crfDefault = 23, stream.crfMax = 51;
	stream.make = [](const OutputSpec& s, std::unique_ptr<AudioSource> audio) -> std::unique_ptr<FrameSink> {
		return std::make_unique<StreamSink>(s, std::move(audio));
	};
	r.push_back(std::move(stream));
	return r;
}

}  // namespace

const std::vector<OutputFormat>& outputFormats() {
	static const std::vector<OutputFormat> registry = makeRegistry();
	return registry;
}

const OutputFormat& outputFormat(VideoFormat format) {
	for (const OutputFormat& f : outputFormats())
		if (f.format == format) return f;
	throw std::logic_error("outputFormat: a format without an entry");
}

const OutputFormat* findOutputFormat(const std::string& name) {
	for (const OutputFormat& f : outputFormats())
		if (f.name == name) return &f;
	return nullptr;
}

const OutputFormat* outputFormatForPath(const std::string& path) {
	const std::string extension = toLower(fs::path(path).extension().string());
	if (extension.empty()) return nullptr;
	for (const OutputFormat& f : outputFormats())
		for (const std::string& e : f.extensions)
			if (e == extension) return &f;
	return nullptr;
}

std::string outputFormatNames(bool withStreams) {
	std::vector<std::string> names;
	for (const OutputFormat& f : outputFormats())
		if (withStreams || !f.stream) names.push_back(f.name);
	std::string s;
	for (std::size_t i = 0; i < names.size(); ++i) s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
	return s;
}

VideoFormat videoFormatFor(const std::string& path, const std::string& named) {
	const OutputFormat* byPath = outputFormatForPath(path);
	if (named.empty()) return byPath ? byPath->format : VideoFormat::Mp4;
	const OutputFormat* f = findOutputFormat(named);
	if (!f || f->stream) throw FieldError("format", "'" + named + "' is not a format written to files (" + outputFormatNames() + ")");
	if (byPath && byPath != f) throw FieldError("format", named + ", but the output " + path + " names another container: ambiguous");
	return f->format;
}

std::unique_ptr<FrameSink> makeVideoSink(const OutputSpec& spec, std::unique_ptr<AudioSource> audio) {
	const OutputFormat& f = outputFormat(spec.format);
	OutputSpec s = spec;
	if (s.crf < 0) s.crf = f.crfDefault;
	else if (f.crfMax < 0) throw FieldError("crf", f.name + " has no quality setting");
	else if (s.crf > f.crfMax) throw FieldError("crf", f.name + "'s quality runs from 0 to " + std::to_string(f.crfMax));
	if (s.alpha && !f.alpha) throw FieldError("background", f.name + " has no alpha channel");
	if (f.stream ? !s.write : s.path.empty()) throw FieldError("output", f.stream ? "a stream needs somewhere to write" : "no output named");
	if (!f.stream && s.path == "-" && !f.standardOutput) throw FieldError("output", f.name + " cannot be written to standard output");
	return f.make(s, f.audio ? std::move(audio) : nullptr);
}

}  // namespace talkhead
