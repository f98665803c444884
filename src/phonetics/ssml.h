// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>
#include <vector>

#include "base/ticks.h"

namespace talkhead {

// The SSML subset `talkhead say` reads (issue 13 §4; decision D45):
//   <speak> … </speak>                          optional wrapper
//   <emotion name="joy" intensity="0.6"> … </emotion>   the emotion over the words inside (nestable)
//   <break time="300ms"/>  (or "1.5s")          a pause of exactly that length
//   <mark name="here"/>                         reported with the time of the word that follows
//   <blink/>                                    a blink at the word that follows
//   <brows up="0.8"/> or <brows down="0.5"/>    brows raised or frowning (0–1.5) for 0.8 s from the next word
// and the entities &amp; &lt; &gt; &quot; &apos;. Anything else is an error with its line and column.
struct SsmlText {
	struct Segment {
		std::string text;  // plain text, spoken in one go
		Ticks pauseAfter{0};
	};
	struct Event {
		enum class Kind { EmotionStart, EmotionEnd, Mark, Blink, Brows } kind;
		std::size_t segment = 0, offset = 0;  // where: the segment, and the byte offset in its text
		std::string name;                     // emotion label or mark name (as written)
		double intensity = 1;                 // emotion intensity; brows: the raise
		double frown = 0;                     // brows: the frown
		long line = 0, column = 0;            // in the input, for messages
	};
	std::vector<Segment> segments;  // at least one
	std::vector<Event> events;      // in text order
};

// Whether a text is meant as SSML: it holds one of the subset's tags (a plain "a < b" is not).
bool looksLikeSsml(const std::string& text);

// Parses the subset; throws Error("path:line: column C: …") on malformed or unsupported markup.
SsmlText parseSsml(const std::string& text, const std::string& path);

}  // namespace talkhead
