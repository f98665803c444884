// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "base/ticks.h"
#include "model/face_model.h"
#include "phonetics/transcript.h"
#include "render/live.h"

namespace talkhead {

// `talkhead serve` (issue 16, D54): live talking-head streams over HTTP + WebSocket (Boost.Beast). Each
// WebSocket connection to /live is one session: a LiveSession paced in real time, its frames and sound as
// fragmented MP4 (binary messages, for Media Source Extensions), its events and answers as JSON text
// messages; requests are JSON text messages (protocol: docs/serve-protocol.md).

// A client's request, parsed. Throws Error ("what is wrong") for anything malformed.
struct LiveRequest {
	enum class Kind { Say, Speak, Emotion, Stop } kind = Kind::Say;
	std::string id;                 // echoed in the events (optional)
	std::string text, lang, voice;  // say
	int rate = 0, pitch = -1;       // say: words per minute (80–450), pitch (0–100); 0 / −1 = the voice's
	std::optional<std::string> emotion;  // emotion, or say/speak: the emotion from this utterance on
	double intensity = 1;
	Ticks ramp{kTicksPerSecond * 3 / 10};
	std::string audio;              // speak: the sound's bytes (any format libav reads, or raw PCM:)
	int pcmRate = 0, pcmChannels = 1;  // speak: "encoding": "pcm_s16le" with "sample_rate" (and "channels")
	std::string transcript;         // speak: its timing, any transcript format talkhead reads, or
	std::optional<Transcript> timing;  // speak: Azure viseme events or ElevenLabs character timestamps
};
LiveRequest parseLiveRequest(const std::string& json);
// The utterance of a say (espeak-ng, in process) or speak (the sound decoded, the transcript read)
// request, at `sampleRate`. Throws Error.
Utterance prepareUtterance(const LiveRequest& request, const std::string& defaultLang, int sampleRate);
// Applies a request to the session at its next frame (say and speak: with their prepared utterance).
void applyLiveRequest(LiveSession& session, const LiveRequest& request, std::optional<Utterance> utterance);

struct ServeOptions {
	std::string host = "127.0.0.1";
	int port = 8765;
	int maxSessions = 4;
	bool demo = false;              // serve examples/live/index.html at /
	std::string demoPage;           // its path (found by the CLI)
	LiveOptions live;               // size, frame rate, emotion, blinks and head motion (seeded)
	std::string lang = "en-US";     // default language of say
	int crf = 23;                   // x264; 0 = lossless (tests: decoded frames equal the drawn ones)
	std::string preset = "veryfast";
	int encoderThreads = 1;         // per session
	std::size_t maxMessage = 32u << 20;  // bytes; larger requests get an error, the session goes on
	std::optional<std::string> recordDir;  // per session, the requests with the frame they took effect at
	std::function<void(const std::string&)> log;  // one line per event worth a log (stderr)
};

// Listens and serves until stop() is called from any thread (or a signal handler's flag: see the CLI).
class Server {
public:
	Server(const FaceModel& model, ServeOptions options);
	~Server();
	Server(const Server&) = delete;
	Server& operator=(const Server&) = delete;
	int port() const;  // the bound port (options.port 0: the one the system chose)
	void run();        // blocks
	void stop();
	struct Impl;

private:
	std::unique_ptr<Impl> impl_;
};

}  // namespace talkhead
