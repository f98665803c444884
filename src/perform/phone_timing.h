// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

namespace talkhead {

// Where a speech's phone times came from. The learned mouth plans each differently: an alignment's times
// come ~20 ms late against the mouth (D104: the model's visual lead moves them), and recognised phones are
// planned with the model learned from recognised phones (D106: their errors are not an alignment's).
enum class PhoneTiming {
	Given,       // a timed transcript, espeak-ng's, a TTS engine's: taken as they are
	Aligned,     // talkhead's aligner: text (or cues) aligned to the audio
	Recognised,  // the phones recognised from the audio alone (issue 49)
};

}  // namespace talkhead
