// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/frame_rate.h"
#include "base/ticks.h"
#include "media/audio.h"
#include "phonetics/language.h"
#include "perform/utterance.h"
#include "render/frame_sink.h"
#include "render/player.h"
#include "render/render.h"
#include "synth/coarticulation.h"
#include "synth/synthesizer.h"

namespace talkhead {

// A live stream (issue 16, D54): one face, always on, whose timeline grows while it plays. Utterances are
// spliced in as they arrive, an emotion changes on the fly, a barge-in closes the mouth; between them the
// face idles (blinks, small head motion, the emotion). The session is driven frame by frame and is
// deterministic: the same commands before the same frames give byte-identical frames and the same sound,
// whatever the wall clock — `talkhead serve` paces it in real time, `talkhead live` replays a script
// offline. Not thread-safe: one thread calls everything.

struct LiveOptions {
	RenderOptions render;              // output size and fit, trajectory, dissolve (threads: unused)
	FrameRate rate{30, 1};
	Expression expression;             // at the start
	ModulatorOptions modulation;       // blinks and head motion, idle and speaking (seeded)
	int sampleRate = 22050;            // of the session's sound (espeak-ng's own rate: no resampling for say)
	double speechBrows = 1;            // brow raises with speech (D49), 0 = none
	PauseStyle pauses = PauseStyle::Natural;
};

// What happened at a frame, for the client.
struct LiveEvent {
	enum class Kind { UtteranceStarted, UtteranceEnded, Mark, Viseme, Stopped, Emotion } kind = Kind::Viseme;
	std::int64_t frame = 0;
	Ticks time{0};
	std::string id;    // the utterance's, or the stop's: JSON text (a quoted string or a number), "" for none
	std::string name;  // the mark, the viseme (CDV) or the emotion
	bool interrupted = false;  // UtteranceEnded by a stop
};
const char* liveEventName(LiveEvent::Kind kind);  // "utterance_started", "utterance_ended", "mark", …
// One event as JSON (docs/serve-protocol.md): {"type", "frame", "time", and "id", "viseme", "emotion",
// "name", "interrupted" as the kind has them}.
// `latencyMs`: an utterance_started event's latency from its request (serve).
std::string liveEventJson(const LiveEvent& e, std::optional<double> latencyMs = std::nullopt);

// An utterance planned for a session (LiveSession::plan): its keyposes from its start, in an expression,
// with their exemplars bound (D62), and its timed events — planned once, on any thread.
struct PlannedUtterance {
	Utterance utterance;
	bool planned = false;                // false: enqueue() plans it (an utterance given as it is)
	// From its start: its keys, speech brows (D49), the text's brows, blinks and marks (SSML).
	Timeline timeline;
	Expression expression;               // what the keys without an emotion of their own were given
	std::vector<std::uint8_t> stamped;   // per key: 1 its emotion, 2 its intensity came from `expression`
	PlannedUtterance() = default;
	explicit PlannedUtterance(Utterance u) : utterance(std::move(u)) {}
	Ticks duration() const { return utterance.duration(); }
};

class LiveSession {
public:
	// A session of `face` (its coarticulation model, D62: each phone keypose shows the face's exemplar
	// nearest the opening it predicts; none: the thesis's one sample per CDV).
	LiveSession(const Face& face, const LiveOptions& options);
	// A session of `model`, with a face of its own (no coarticulation model).
	LiveSession(const FaceModel& model, const LiveOptions& options);
	~LiveSession();
	LiveSession(const LiveSession&) = delete;
	LiveSession& operator=(const LiveSession&) = delete;

	const StreamInfo& info() const { return info_; }  // frames = 0: unbounded
	int sampleRate() const { return o_.sampleRate; }
	std::int64_t nextFrame() const { return next_; }
	Ticks nextTime() const { return o_.rate.time(next_); }
	const Expression& expression() const { return expression_; }

	// Plans `u` in `expression` (the planner render uses, perform/plan.h; then the exemplars of its
	// predicted mouths) and makes the keypose images it will need — the one call that may come from another
	// thread while frames are drawn (a server's speech thread), so that enqueue() then costs a frame nothing.
	PlannedUtterance plan(Utterance u, const Expression& expression) const;
	// Queues an utterance: it starts at the next frame, or when the speech queued before it ends (a part of
	// a streamed one, Utterance::opens/closes: right after the part before, when that has not ended). Returns
	// its start (stream time). Not planned yet: planned here, in the session's expression; planned in
	// another expression than the session's now: its keys take the session's (and their exemplars again).
	Ticks enqueue(PlannedUtterance u);
	Ticks enqueue(Utterance u) { return enqueue(PlannedUtterance(std::move(u))); }
	// The emotion from the next frame on, reached over `ramp` when idle (at the next keypose when
	// speaking).
	void setEmotion(const Expression& expression, Ticks ramp);
	// Barge-in: the speech under way and everything queued is dropped (the sound fades out over 10 ms) and
	// the mouth closes — at rest within 150 ms of the next frame.
	// `id` (JSON text, or "") goes on the `stopped` event; `unstarted`: ids of utterances the caller held
	// back and now drops (a server's prepared ones), each ended (interrupted) after the session's own.
	void stop(const std::string& id = {}, const std::vector<std::string>& unstarted = {});
	// Speech under way or queued at the next frame.
	bool speaking() const { return queueEnd_ > nextTime(); }
	// When the speech queued so far ends (stream time; at or before nextTime() when silent).
	Ticks queueEnd() const { return queueEnd_; }

	// Draws the next frame (YUV 4:2:0, limited range) and its feature points (output pixels); appends what
	// happened by this frame to `events`. `alpha`: the face's matte too, into the slot's yuv.a.
	const FrameSlot& drawNext(std::vector<LiveEvent>& events, bool alpha = false);
	// The same, copied out (tests).
	void drawNext(YuvImage& out, Points& points, std::vector<LiveEvent>& events);
	// The live frame player (talkhead live, serve's stream, serve's load measurement): draws the next frame
	// and hands it to `sink` (begun by the caller with info()), with the face's matte when the sink needs
	// alpha (render/matte.h, as render draws it); appends what happened by this frame to `events`.
	void play(FrameSink& sink, std::vector<LiveEvent>& events);

	// The session's sound (mono, sampleRate()): the utterances where they were placed, silence between. An
	// encoder pulls it as the frames advance; never ends. Reads must not run ahead of the frames drawn by
	// more than the encoder's block, or speech queued later would be missed (it is then dropped up to the
	// read position and the stream says so on stderr).
	AudioSource& audio();

	// The keyposes from the last drawn frame on (for tests and the debug view).
	const std::vector<Keypose>& keyposes() const { return timeline_.keys; }
	// The current plan of blinks and head motion.
	const ShapeModulator* modulator() const { return modulator_.get(); }

private:
	class Sound;
	struct Pending {  // an event at a stream time
		Ticks time{0};
		LiveEvent event;
	};
	LiveSession(std::unique_ptr<Face> own, const Face* face, const LiveOptions& options);
	std::unique_ptr<Face> ownFace_;    // made for a model alone (the FaceModel constructor)
	const Face& face_;
	LiveOptions o_;
	std::unique_ptr<FramePlayer> player_;  // the frame player render uses too
	StreamInfo info_;
	Synthesizer::Workspace ws_;
	FrameSlot slot_;                   // the frame drawn last
	std::int64_t next_ = 0;
	Expression expression_;
	Ticks queueEnd_{0};
	std::deque<Pending> pending_;
	std::string lastViseme_;
	ModulatorOptions modOptions_;  // the knobs
	Timeline timeline_;            // keys and what is asked for at stream times (brows, blinks, marks), spliced in as utterances come
	std::shared_ptr<const ShapeModulator> modulator_;
	Ticks horizon_{0};
	std::optional<std::string> open_;  // the id of a streamed utterance whose last part has not come
	std::unique_ptr<Sound> sound_;

	Ticks lastDrawn() const;  // the time of the last drawn frame (−1 tick when none)
	// The silence keypose at t in the session's emotion; with a coarticulation model that has a rest, drawn as a
	// plan's rest is (D107), so the idle face matches the pauses of what it says.
	Keypose rest(Ticks t) const;
	PlannedUtterance planned(Utterance u, const Expression& expression) const;  // plan() without the images
	void chooseExemplars(std::vector<Keypose>& keys, Emotion fallback) const;  // D62: again, for keys whose emotion changed
	void replan();
	void addPending(Ticks t, LiveEvent e);
};

}  // namespace talkhead
