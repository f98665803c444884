// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The video formats talkhead writes, in one registry (as OpenImageIO's table of format plugins): a format
// is found by its name or by an output's extension, and its entry makes the sink that writes it. render,
// say, live, serve's stream and stimulus sheets all make their video sinks here; a new output format is one
// entry in output.cpp (and its encoder in the libav plugin).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "media/audio.h"
#include "render/frame_sink.h"

namespace talkhead {

enum class VideoFormat {
	Mp4,        // H.264 + AAC, a file
	Webm,       // VP9 + Vorbis, a file; VP9's alpha plane can carry the face's matte
	Y4m,        // raw YUV4MPEG2 frames, a file or standard output
	Mp4Stream,  // H.264 + AAC as fragmented MP4 for Media Source Extensions, handed to a byte callback (serve)
};

// Where one video goes and how it is encoded. Each front end fills it from its own words (the CLI's flags,
// a request's members); makeVideoSink checks it and throws FieldError naming the field that is wrong.
struct OutputSpec {
	VideoFormat format = VideoFormat::Mp4;
	std::string path;  // a file ("-": standard output, where the format can write there); unused by streams
	std::function<bool(const std::uint8_t* data, std::size_t size)> write;  // a stream's bytes (false: its reader is gone)
	int crf = -1;                      // constant quality, the format's scale; -1: the format's default
	std::string preset = "veryfast";   // x264's preset (the H.264 formats)
	bool alpha = false;                // the face's matte as alpha (formats with alpha only)
	int threads = 0;                   // encoder threads (streams; 0: all cores)
};

struct OutputFormat {
	VideoFormat format;
	std::string name;                     // "mp4": the format field's value (the CLI's flag, a request's member)
	std::vector<std::string> extensions;  // lower case, with the dot: an output named so is in this format
	std::string description;              // for help texts and `talkhead formats`
	bool alpha = false;                   // can carry the face's matte
	bool audio = false;                   // muxes a sound track
	bool standardOutput = false;          // can write to "-"
	bool stream = false;                  // writes to OutputSpec::write, not to a file
	bool preset = false;                  // takes x264's preset
	int crfDefault = -1, crfMax = -1;     // the quality scale 0…crfMax and its default (-1: none)
	std::function<std::unique_ptr<FrameSink>(const OutputSpec&, std::unique_ptr<AudioSource>)> make;
};

// Every format, in the order help texts list them.
const std::vector<OutputFormat>& outputFormats();
const OutputFormat& outputFormat(VideoFormat format);
// By name ("webm"); nullptr when no format has it.
const OutputFormat* findOutputFormat(const std::string& name);
// By the extension of a file's name (case-insensitive: "take.WEBM"); nullptr when none claims it.
const OutputFormat* outputFormatForPath(const std::string& path);
// The file formats' names ("mp4, webm or y4m"), for messages.
std::string outputFormatNames(bool withStreams = false);

// The format a file output is written in: `named` when given (it must be a file format; a name that
// contradicts the path's extension is ambiguous), else the one the extension claims, else MP4. Throws
// FieldError("format", …) when unknown or ambiguous.
VideoFormat videoFormatFor(const std::string& path, const std::string& named);

// The sink that writes `spec` (the sound track, when the format has one, from `audio`). Throws FieldError
// naming the field ("crf", "background", "output", "preset") when the spec asks what the format cannot do.
std::unique_ptr<FrameSink> makeVideoSink(const OutputSpec& spec, std::unique_ptr<AudioSource> audio);

}  // namespace talkhead
