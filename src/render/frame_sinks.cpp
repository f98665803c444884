// SPDX-License-Identifier: GPL-3.0-or-later
// The frame sinks: MP4, y4m, PNG frames, landmarks TSV and a callback. File outputs go to temporary names
// and appear under their own names only on commit; errors name the output, never its temporary.
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "base/atomic_file.h"
#include "base/interrupt.h"
#include "base/error.h"
#include "corpus/landmarks_tsv.h"
#include "media/image_io.h"
#include "media/video_writer.h"
#include "render/frame_sink.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {

// A file written under a temporary name: removed unless renamed to `path` by commit().
struct TempOutput {
	std::string path, temp;
	bool committed = false;
	explicit TempOutput(std::string p) : path(std::move(p)), temp(temporaryNameFor(path)) {}
	~TempOutput() {
		if (!committed) {
			std::error_code ec;
			fs::remove(temp, ec);
		}
		releaseTemporary(temp);
	}
	void commit() {
		std::error_code ec;
		fs::rename(temp, path, ec);
		if (ec) throw Error(path, 0, "cannot write: " + ec.message());
		committed = true;
	}
	// Runs f; an Error naming the temporary is re-thrown naming the output.
	template <class F>
	void guard(F&& f) {
		try {
			f();
		} catch (const Error& e) {
			const std::string m = e.what();
			if (m.rfind(temp + ": ", 0) == 0) throw Error(path + ": " + m.substr(temp.size() + 2));
			throw;
		}
	}
};

// MP4 or WebM (VideoOptions: the container, crf, preset, alpha).
class VideoSink final : public FrameSink {
public:
	VideoSink(const std::string& path, const VideoOptions& o, std::unique_ptr<AudioSource> audio) : out_(path), options_(o), audio_(std::move(audio)) {}
	bool needsAlpha() const override { return options_.alpha; }
	void begin(const StreamInfo& info) override {
		VideoOptions vo = options_;
		vo.width = info.width, vo.height = info.height, vo.rate = info.rate;
		out_.guard([&] { writer_ = std::make_unique<Mp4Writer>(out_.temp, vo, audio_.get()); });
	}
	void frame(const RenderedFrame& f) override {
		out_.guard([&] { writer_->write(*f.yuv); });
	}
	void finish() override {
		out_.guard([&] {
			writer_->finish();
			writer_.reset();
		});
	}
	void commit() override { out_.commit(); }

private:
	TempOutput out_;
	VideoOptions options_;
	std::unique_ptr<AudioSource> audio_;
	std::unique_ptr<Mp4Writer> writer_;
};

class Y4mSink final : public FrameSink {
public:
	explicit Y4mSink(const std::string& path) {
		if (path != "-") out_ = std::make_unique<TempOutput>(path);
	}
	~Y4mSink() override {
		if (file_ && file_ != stdout) std::fclose(file_);
	}
	void begin(const StreamInfo& info) override {
		VideoOptions vo;
		vo.width = info.width, vo.height = info.height, vo.rate = info.rate;
		if (out_) {
			file_ = std::fopen(out_->temp.c_str(), "wb");
			if (!file_) throw Error(out_->path, 0, std::string("cannot write: ") + std::strerror(errno));
		} else {
			file_ = stdout;
		}
		writer_ = std::make_unique<Y4mWriter>(file_, vo, out_ ? out_->path : "-");
	}
	void frame(const RenderedFrame& f) override { writer_->write(*f.yuv); }
	void finish() override {
		writer_.reset();
		if (file_ == stdout) {
			std::fflush(stdout);
		} else if (file_) {
			errno = 0;
			const bool bad = std::fclose(file_) != 0;
			file_ = nullptr;
			if (bad) throw Error(out_->path, 0, std::string("cannot write: ") + std::strerror(errno));
		}
	}
	void commit() override {
		if (out_) out_->commit();
	}

private:
	std::unique_ptr<TempOutput> out_;
	std::FILE* file_ = nullptr;
	std::unique_ptr<Y4mWriter> writer_;
};

bool isFrameFile(const std::string& name) {
	return name.size() == 16 && name.compare(0, 6, "frame_") == 0 && name.compare(12, 4, ".png") == 0 &&
	       std::all_of(name.begin() + 6, name.begin() + 12, [](char c) { return c >= '0' && c <= '9'; });
}

// All-or-nothing: the frames go to a staged folder that replaces `dir` on commit (base/atomic_file.h).
class PngFramesSink final : public FrameSink {
public:
	PngFramesSink(std::string dir, bool alpha) : dir_(std::move(dir)), alpha_(alpha) { checkReplaceableFolder(dir_, isFrameFile); }
	void begin(const StreamInfo&) override { staged_ = std::make_unique<StagedFolder>(dir_, isFrameFile); }
	bool needsRgb() const override { return true; }
	bool needsAlpha() const override { return alpha_; }
	bool anyThread() const override { return true; }
	void frame(const RenderedFrame& f) override {
		char name[64];  // PNG compression is the slow part: done by the drawing threads
		std::snprintf(name, sizeof name, "frame_%06lld.png", (long long)f.index);
		if (!alpha_) {
			staged_->writeFile(name, [&](const std::string& p) { writeImage(p, *f.rgb, 1); });
			return;
		}
		thread_local Image8 rgba;  // RGB and the matte interleaved (reused: no allocation per frame)
		const Image8& rgb = *f.rgb;
		const std::vector<std::uint8_t>& a = f.yuv->a;
		if (rgba.width != rgb.width || rgba.height != rgb.height || rgba.channels != 4) rgba = Image8(rgb.width, rgb.height, 4);
		const std::size_t n = std::size_t(rgb.width) * std::size_t(rgb.height);
		for (std::size_t i = 0; i < n; ++i) {
			std::uint8_t* q = &rgba.data[4 * i];
			const std::uint8_t* p = &rgb.data[3 * i];
			q[0] = p[0], q[1] = p[1], q[2] = p[2], q[3] = a[i];
		}
		staged_->writeFile(name, [&](const std::string& p) { writeImage(p, rgba, 1); });
	}
	void commit() override { staged_->commit(); }

private:
	std::string dir_;
	bool alpha_;
	std::unique_ptr<StagedFolder> staged_;
};

class LandmarksSink final : public FrameSink {
public:
	explicit LandmarksSink(const std::string& path) : out_(path) {}
	~LandmarksSink() override {
		if (file_) std::fclose(file_);
	}
	void begin(const StreamInfo& info) override {
		file_ = std::fopen(out_.temp.c_str(), "wb");
		if (!file_) fail();
		count_ = info.pointNames.size();
		const std::string header = landmarksTsvHeader(info.pointNames);
		put(header.data(), header.size());
	}
	void frame(const RenderedFrame& f) override {
		line_.clear();
		row_.frame = f.index, row_.time = f.time, row_.points = *f.points;  // status drawn, confidence 1
		appendLandmarksTsvRow(line_, row_, count_);
		put(line_.data(), line_.size());
	}
	void finish() override {
		std::FILE* f = file_;
		file_ = nullptr;
		errno = 0;
		if (std::fclose(f) != 0) fail();
	}
	void commit() override { out_.commit(); }

private:
	TempOutput out_;
	std::FILE* file_ = nullptr;
	std::string line_;
	LandmarkRow row_;
	std::size_t count_ = 0;
	void put(const char* p, std::size_t n) {
		errno = 0;
		if (std::fwrite(p, 1, n, file_) != n) fail();
	}
	[[noreturn]] void fail() const { throw Error(out_.path, 0, std::string("cannot write: ") + std::strerror(errno ? errno : EIO)); }
};

class CallbackSink final : public FrameSink {
public:
	explicit CallbackSink(std::function<void(const StreamInfo&, const RenderedFrame&)> fn) : fn_(std::move(fn)) {}
	void begin(const StreamInfo& info) override { info_ = info; }
	void frame(const RenderedFrame& f) override { fn_(info_, f); }

private:
	std::function<void(const StreamInfo&, const RenderedFrame&)> fn_;
	StreamInfo info_;
};

}  // namespace

std::unique_ptr<FrameSink> makeMp4Sink(const std::string& path, const Mp4Settings& settings, const AudioClip* audio) {
	return makeMp4Sink(path, settings, audio && audio->frameCount() > 0 ? clipSource(*audio) : nullptr);
}
std::unique_ptr<FrameSink> makeMp4Sink(const std::string& path, const Mp4Settings& settings, std::unique_ptr<AudioSource> audio) {
	VideoOptions o;
	o.crf = settings.crf, o.preset = settings.preset;
	return std::make_unique<VideoSink>(path, o, std::move(audio));
}
std::unique_ptr<FrameSink> makeWebmSink(const std::string& path, const WebmSettings& settings, std::unique_ptr<AudioSource> audio) {
	VideoOptions o;
	o.container = VideoContainer::WebM, o.crf = settings.crf, o.alpha = settings.alpha;
	return std::make_unique<VideoSink>(path, o, std::move(audio));
}
std::unique_ptr<FrameSink> makeY4mSink(const std::string& path) { return std::make_unique<Y4mSink>(path); }
std::unique_ptr<FrameSink> makePngFramesSink(const std::string& dir, bool alpha) { return std::make_unique<PngFramesSink>(dir, alpha); }
std::unique_ptr<FrameSink> makeLandmarksSink(const std::string& path) { return std::make_unique<LandmarksSink>(path); }
std::unique_ptr<FrameSink> makeCallbackSink(std::function<void(const StreamInfo&, const RenderedFrame&)> fn) {
	return std::make_unique<CallbackSink>(std::move(fn));
}

}  // namespace talkhead
