// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

#include "render/frame_sink.h"

namespace talkhead {

// Two videos of the same size, frame rate and length side by side in one H.264 MP4 (ITU-T P.910's
// simultaneous presentation; the thesis's Appendix C test): left | gap | right, the gap mid-grey. The
// inputs are read as YUV 4:2:0 (a y4m or lossless H.264 file is copied exactly, nothing re-sampled); the
// sound track (optional, `audioPath`, e.g. the left or right stimulus's WAV) is muxed as it is. Written
// through a temporary name. Throws Error naming the file that does not match or cannot be read.
struct SideBySideOptions {
	int gap = 16;           // pixels between the two (even)
	Mp4Settings mp4;
};
void writeSideBySide(const std::string& left, const std::string& right, const std::string& audioPath, const std::string& out,
                     const SideBySideOptions& options = {});

}  // namespace talkhead
