// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <deque>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/ticks.h"
#include "synth/face.h"
#include "phonetics/espeak.h"
#include "phonetics/transcript.h"
#include "perform/stream.h"
#include "render/live.h"

namespace talkhead {

// `talkhead serve` (issue 16, D54): live talking-head streams over HTTP + WebSocket (Boost.Beast). Each
// WebSocket connection to /live is one session: a LiveSession paced in real time, its frames and sound as
// fragmented MP4 (binary messages, for Media Source Extensions), its events and answers as JSON text
// messages; requests are JSON text messages (protocol: docs/serve-protocol.md).

// A client's request, parsed. Throws Error ("what is wrong") for anything malformed.
struct LiveRequest {
	enum class Kind { Say, Speak, Emotion, Stop } kind = Kind::Say;
	std::string id;                 // as JSON text (a quoted string or an integer as written), echoed as is; "" when absent
	std::string text, lang, voice;  // say
	int rate = 0, pitch = -1;       // say: words per minute (80–450), pitch (0–100); 0 / −1 = the voice's
	std::optional<Expression> expression;  // emotion, or say/speak: the emotion from this utterance on
	Ticks ramp{kTicksPerSecond * 3 / 10};
	std::string audio;              // speak: the sound's bytes (any format libav reads, or raw PCM:)
	int pcmRate = 0, pcmChannels = 1;  // speak: "encoding": "pcm_s16le" with "sample_rate" (and "channels")
	std::string transcript;         // speak: its timing, any transcript format talkhead reads, or
	std::optional<Transcript> timing;  // speak: Azure viseme events or ElevenLabs character timestamps
	// speak, streamed (issue 49): `more` — more audio follows in speaks that name this one's id in
	// `continue` (`continues`: this is one of them; `id` is then the stream's); the last has no `more`.
	bool more = false, continues = false;
};
// At most kMaxRequestValues JSON values (issue 28 item 4: each costs ~100 bytes parsed).
constexpr std::size_t kMaxRequestValues = 500000;
LiveRequest parseLiveRequest(const std::string& json);
// A request's id, from the member's JSON text (jsonTopLevelMemberJson): that text when it is a string of at
// most 200 bytes or an integer within ±(2^53 − 1) written as digits (so that no two ids a client tells apart
// are echoed as one, in JavaScript too); throws Error otherwise.
std::string requestIdJson(const std::string& member);

// What a session record keeps of a request (`json` its text, `request` what was parsed from it): the members
// the parser reads for its type, nothing else (a request may carry megabytes of members it ignores).
std::string requestForRecord(const std::string& json, const LiveRequest& request);
// The utterance of a say (espeak-ng, in process) or speak (the sound decoded, the transcript read)
// request, at `sampleRate`, within `limits` (maxSeconds bounds speak's sound too). Throws Error, or
// SpeechCancelled.
// `recognize` false: a speak with no timing at all comes back with its sound and no phones (the caller
// recognises them in parts, perform/stream.h).
Utterance prepareUtterance(const LiveRequest& request, const std::string& defaultLang, int sampleRate, const SpeechLimits& limits = {}, bool recognize = true);
// Raw 16-bit little-endian PCM (a streamed speak's piece) as mono samples.
std::vector<float> pcmMono(const std::string& bytes, int channels);
// A speak whose phones come in parts (perform/stream.h): streamed (`more`, `continue`) or with no timing.
bool speaksInParts(const LiveRequest& request);
// Such a speak replayed offline (talkhead live): its parts into the session as they come, or with `held` into
// it (with the emotion the first part brings) for the script's part steps to release; `stream` holds the open
// stream between requests; `look` as the stream did after this piece (a recorded step's "look").
struct HeldPart {
	Utterance utterance;
	std::optional<Expression> expression;  // the emotion from this part on (the first part's request's)
	Ticks ramp{0};
};
void replaySpeakInParts(LiveSession& session, const LiveRequest& request, std::unique_ptr<SpeechStream>& stream, const std::string& defaultLang, bool look = true,
                        std::deque<HeldPart>* held = nullptr);
// Applies a request to the session at its next frame (say and speak: with their prepared utterance).
void applyLiveRequest(LiveSession& session, const LiveRequest& request, std::optional<PlannedUtterance> utterance);

// A recorded session (serve --record; talkhead live): one JSON object a line — {"frame": N, "request": {…}}
// steps (a streamed speak's piece after which the stream did not look for words: {"frame": N, "look": false,
// "request": {…}}; each part of a speak in parts taking effect: {"type": "part", "frame": N, "id": …}) (sorted by frame, the request's own text kept), an optional {"type": "end", "frame": N} (`end`, −1
// when absent) and {"type": "session", …} (informational). Throws Error naming the file and line.
struct SessionScript {
	struct Step {
		std::int64_t frame = 0;
		std::string json;  // the request as written
		long line = 0;
		bool look = true;  // a streamed speak's piece: whether the stream looked for words after it ("look": false)
		bool part = false;  // {"type": "part", "frame": N, "id": …}: the next part of a speak in parts takes effect
	};
	std::vector<Step> steps;
	bool hasParts = false;  // it has part steps (records before them: each part takes effect as its piece is replayed)
	std::int64_t end = -1;
};
SessionScript readSessionScript(const std::string& path);

// What one session may queue (issue 28 item 5); a request past a limit gets an error event naming it.
struct SessionLimits {
	int queuedRequests = 32;        // say and speak requests waiting, being prepared or queued to play
	double queuedSeconds = 900;     // speech queued ahead of the frames, the new utterance included
	double utteranceSeconds = 600;  // one say or speak
	double breakSeconds = 60;       // the SSML breaks of one say, together
};

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
	std::uint64_t recordMaxBytes = 64u << 20;  // one session's record at most: past it, its recording stops
	std::function<void(const std::string&)> log;  // one line per event worth a log (stderr); fields as {{field}}
	// How the server's operator reads a field in text the server answers over HTTP (a refused Host or
	// Origin, the demo page off): the CLI gives its flags; by default the field's name in quotes.
	std::function<std::optional<std::string>(const std::string&)> operatorField = [](const std::string& f) { return std::optional<std::string>("'" + f + "'"); };
	// Running it safely (issue 28, D58).
	std::vector<std::string> allowOrigins;  // pages allowed to open sessions besides the server's own and loopback ones
	std::vector<std::string> allowHosts;    // Host names besides the listen address and loopback names
	std::string token;                      // when set, every session and /metrics must give it (never logged)
	std::string tlsCert, tlsKey;            // PEM files: HTTPS and wss:// (both or neither)
	double idleSeconds = 300;               // a session with no request and nothing to say this long is closed; 0: never
	SessionLimits limits;
	double maxLoad = 0.9;                   // of the cores: a new session is refused when frames would be late; 0: off
	double drainSeconds = 5;                // at SIGTERM/SIGINT (handleSignals): speech under way finishes this long at most
	bool handleSignals = false;             // SIGTERM/SIGINT end the server gracefully (a second one at once)
};

// Listens and serves until stop() or shutdown() is called from any thread (or, with handleSignals, SIGTERM
// or SIGINT). Parsing, decoding and synthesis never run on the network thread: each session has its own
// threads (D54, D58). The network side (Boost.Beast, Asio, TLS) is the plugin libtalkhead-serve.so, loaded
// by the first Server (D68): the constructor throws Error when it cannot be loaded, as for the other plugins.
class Server {
public:
	Server(const Face& face, ServeOptions options);
	~Server();
	Server(const Server&) = delete;
	Server& operator=(const Server&) = delete;
	int port() const;  // the bound port (options.port 0: the one the system chose)
	void run();        // blocks until stopped
	void stop();       // at once: sessions end without notice
	void shutdown();   // gracefully: no new sessions; each is told, finishes its speech (drainSeconds), then closes

private:
	const struct ServeModule* module_;
	void* server_;
};

}  // namespace talkhead
