// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "base/frame_rate.h"
#include "base/ticks.h"
#include "geometry/shape.h"
#include "image/image.h"
#include "image/yuv.h"
#include "media/audio.h"

namespace talkhead {

// What every sink learns before the first frame.
struct StreamInfo {
	int width = 0, height = 0;             // output pixels (even)
	FrameRate rate;
	std::int64_t frames = 0;               // how many frames will come
	YuvRange range = YuvRange::Limited;    // of the YUV planes
	std::vector<std::string> pointNames;   // the model's feature points, in the order of RenderedFrame::points
	bool alpha = false;                    // the frames carry a matte (YuvImage::a): some sink needsAlpha()
};

// One finished frame. Valid only during the call.
struct RenderedFrame {
	std::int64_t index = 0;   // 0-based frame number
	Ticks time{0};            // its instant: rate.time(index)
	const YuvImage* yuv = nullptr;   // 4:2:0 planes in StreamInfo::range, and the matte (a) when StreamInfo::alpha
	const Image8* rgb = nullptr;     // 8-bit RGB, only when a sink asked for it (needsRgb)
	const Points* points = nullptr;  // feature points in output pixels (x, y), one row per point
};

// Where frames go. The renderer calls begin(), then frame() for every frame — in order on one writer
// thread, or, when anyThread(), from the drawing threads in any order — then finish() on every sink and,
// when all finished, commit() on every sink. A sink destroyed before commit() removes what it wrote, so a
// failed or interrupted render leaves no partial output.
class FrameSink {
public:
	virtual ~FrameSink() = default;
	virtual void begin(const StreamInfo& info) { (void)info; }
	virtual bool needsRgb() const { return false; }
	virtual bool needsAlpha() const { return false; }  // the face's matte with every frame (render/matte.h)
	virtual bool anyThread() const { return false; }
	virtual void frame(const RenderedFrame& f) = 0;
	virtual void finish() {}   // everything written, still under temporary names
	virtual void commit() {}   // outputs appear under their names
	// A stream's codecs (RFC 6381, "avc1.64001f,mp4a.40.2"), known after begin(); empty for files.
	virtual std::string codecs() const { return {}; }
};

// H.264 + AAC MP4 (libav, in process) written to a temporary name beside `path`, renamed on commit.
struct Mp4Settings {
	int crf = 20;                          // x264 constant rate factor, 0–51
	std::string preset = "veryfast";       // x264 preset
};
// `audio` (optional, must outlive the sink) becomes the AAC track.
std::unique_ptr<FrameSink> makeMp4Sink(const std::string& path, const Mp4Settings& settings, const AudioClip* audio);
// The same with the audio pulled from a source as the video advances (e.g. openAudioFile: an hour of
// audio costs no more memory than a second).
std::unique_ptr<FrameSink> makeMp4Sink(const std::string& path, const Mp4Settings& settings, std::unique_ptr<AudioSource> audio);
// VP9 + Vorbis WebM (libav, in process), temporary name renamed on commit: with `alpha`, VP9's alpha plane
// carries the face's matte (render/matte.h; WebM's alpha_mode: browsers, ffmpeg's libvpx-vp9 decoder).
struct WebmSettings {
	int crf = 32;        // libvpx-vp9 constant quality, 0–63 (lower: better, larger)
	bool alpha = false;  // transparent outside the face
};
std::unique_ptr<FrameSink> makeWebmSink(const std::string& path, const WebmSettings& settings, std::unique_ptr<AudioSource> audio);
// YUV4MPEG2 to a file (temporary name, renamed on commit) or, for "-", to standard output as frames come.
std::unique_ptr<FrameSink> makeY4mSink(const std::string& path);
// Every frame as DIR/frame_NNNNNN.png (RGB), compressed on the drawing threads. All or nothing: written
// into a temporary folder beside DIR that replaces it when the render completes (DIR may be new, empty or
// a previous run's frames; anything else in it is an Error before any work). A failed or interrupted
// render leaves DIR as it was. With `alpha`: RGBA, the face's matte as alpha (render/matte.h).
std::unique_ptr<FrameSink> makePngFramesSink(const std::string& dir, bool alpha = false);
// Feature points per frame: TSV `frame  time  status  confidence  <point>_x  <point>_y …`, the landmarks
// TSV of corpus/landmarks_tsv.h (status "drawn", confidence 1; time in seconds, 6 decimals; points in
// output pixels, 3 decimals), temporary name renamed on commit.
std::unique_ptr<FrameSink> makeLandmarksSink(const std::string& path);
// Calls `fn` for every frame, in order, on the writer thread.
std::unique_ptr<FrameSink> makeCallbackSink(std::function<void(const StreamInfo&, const RenderedFrame&)> fn);

}  // namespace talkhead
