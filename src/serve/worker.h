// SPDX-License-Identifier: GPL-3.0-or-later
// One session's work in `talkhead serve` (internal to the serve module): its threads, its queues and what
// the server reads of it (metrics, admission).
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "perform/stream.h"
#include "serve/server.h"

namespace talkhead {

using ServeClock = std::chrono::steady_clock;

// What the server counts, for /metrics (all sessions, since the start).
struct ServeCounters {
	std::atomic<std::int64_t> sessionsOpened{0}, refusedFull{0}, refusedLoad{0}, refusedAuth{0}, refusedOrigin{0}, refusedHost{0},
	    refusedShutdown{0}, refusedUnauthenticated{0}, closedUnauthenticated{0}, closedIdle{0}, requests{0}, requestErrors{0}, frames{0}, lateFrames{0}, acceptErrors{0};
	// Request → first frame of its utterance (seconds), a Prometheus histogram.
	static constexpr double kBuckets[] = {0.025, 0.05, 0.1, 0.2, 0.5, 1, 2, 5};
	std::mutex latencyMutex;
	std::int64_t latencyCounts[std::size(kBuckets) + 1] = {};
	double latencySum = 0;
	void latency(double seconds);
};

// One session's gauges, written by its threads, read by the server.
struct SessionStats {
	std::atomic<double> load{0};               // cores it takes: CPU time of its threads per second, smoothed
	std::atomic<std::int64_t> cpuNs{0};        // CPU time its threads have taken (each adds its own)
	std::atomic<std::int64_t> lastLateNs{-1};  // steady clock of its last late frame, −1: none
	std::atomic<int> queuedRequests{0};        // say/speak waiting, being prepared or queued to play
	std::atomic<double> queuedSeconds{0};      // speech ahead of the frames
	std::chrono::steady_clock::time_point opened;  // when its frames may start (set before its threads start)
};

// A late frame within the last few seconds.
bool lateRecently(const SessionStats& s);
// The cores one speaking session takes at these options (drawing, encoding, its speech), measured by doing
// it for a second of stream on this thread: what admission counts a session at before its own load is
// known (issue 45 item 3).
double measureSessionLoad(const Face& face, const ServeOptions& options);

// A session's worker as the network side (server.cpp, the plugin libtalkhead-serve.so, D68) sees it: called
// through its vtable, so the plugin holds no second copy of the library (one espeak-ng lock, one plugin
// loader, one language cache) — the workers are made by the serve module (ServeHost, serve_module.h).
class SessionWorker {
public:
	using Send = std::function<bool(bool binary, std::string data)>;  // false: the client is gone or too slow
	enum class End { Failed, Idle, Shutdown };
	using Close = std::function<void(End)>;
	virtual ~SessionWorker() = default;  // stops the threads (synthesis under way is cancelled first)
	// A request's text, from the network thread: only queued (parsed on the session's intake thread).
	// `oversize`: larger than the server takes, `text` then holds its beginning (for its id).
	virtual void request(std::string text, bool oversize) = 0;
	// The client is gone: synthesis under way stops now (before the destructor runs, elsewhere).
	virtual void cancel() = 0;
	// The server is going: no new requests; what is queued to play is played until `deadline`.
	virtual void shutdown(ServeClock::time_point deadline) = 0;
};

class LiveWorker final : public SessionWorker {
public:
	LiveWorker(const Face& face, const ServeOptions& o, int id, Send send, Close close, std::shared_ptr<SessionStats> stats, ServeCounters& counters);
	~LiveWorker() override;
	LiveWorker(const LiveWorker&) = delete;
	LiveWorker& operator=(const LiveWorker&) = delete;

	void request(std::string text, bool oversize) override;
	void cancel() override;
	void shutdown(ServeClock::time_point deadline) override;

private:
	struct Inbound {
		std::string text;
		bool oversize = false;
		ServeClock::time_point received;
	};
	struct Command {
		LiveRequest request;
		std::optional<PlannedUtterance> utterance;  // planned on the speech thread (LiveSession::plan)
		std::string json;  // for the record
		std::uint64_t generation = 0;
		ServeClock::time_point received;
		std::vector<std::string> dropped;  // a stop: the ids of the say/speak it dropped before they were prepared
		// A streamed speak's pieces that gave no part of their own (for the record), each with whether the stream
		// looked for words after it (`look`: not when the next piece had come already).
		std::vector<std::pair<std::string, bool>> alsoRecorded;
		// A part of a speak in parts (perform/stream.h): recorded as a "part" step at the frame it took effect, so
		// that `talkhead live` holds the parts a piece gave until their frames, as the stream did.
		bool part = false;
	};
	const Face& face_;
	const ServeOptions& o_;
	int id_;
	Send send_;
	Close close_;
	std::shared_ptr<SessionStats> stats_;
	ServeCounters& counters_;

	std::mutex m_;  // guards everything below up to the threads
	std::condition_variable inboxCv_, speechCv_, frameCv_;
	bool quit_ = false;
	bool closing_ = false;                          // shutdown: no new requests
	ServeClock::time_point deadline_{};             // shutdown: the end of the drain
	std::deque<Inbound> inbox_;
	std::size_t inboxBytes_ = 0;
	std::uint64_t generation_ = 0;                  // a stop starts a new one: older commands are dropped
	std::deque<Command> speechQueue_, frameQueue_;
	bool preparing_ = false;
	std::string preparingId_;                       // the id of the say/speak being prepared
	std::vector<std::string> orphans_;              // ids of say/speak the shutdown dropped: ended at the next frame
	int handed_ = 0;                                // say/speak prepared, not yet taken by the frame thread
	double handedSeconds_ = 0;
	Expression expression_;                         // the session's, for warming (the frame thread's copy)
	std::atomic<bool> cancel_{false};               // the synthesis under way stops
	std::atomic<std::int64_t> lastRequestNs_;

	// A streamed speak (issue 49), the speech thread's: the stream, the generation it began in, when its first
	// piece came, its channels, and the record lines of pieces not yet in a part.
	std::unique_ptr<SpeechStream> stream_;
	std::uint64_t streamGeneration_ = 0;
	ServeClock::time_point streamReceived_{};
	int streamChannels_ = 1;
	std::vector<std::pair<std::string, bool>> streamRecord_;
	std::string stoppedStream_;                     // the id of the stream a stop ended (its pieces in flight are dropped)
	// …and what the intake thread needs to know of it (under m_): its id while open, whether a part went to the frames.
	std::string streamId_;
	bool streamHanded_ = false;

	std::ofstream record_;
	std::uint64_t recorded_ = 0;                    // bytes written to it
	std::int64_t drawn_ = 0;                        // frames drawn and encoded (the record's end)
	double work_ = 0, worst_ = 0;                   // seconds drawing + encoding; the latest a frame went out after its time
	std::int64_t late_ = 0;                         // frames out more than a frame after their time
	std::atomic<LiveSession*> session_{nullptr};    // the frame thread's, while it lives
	std::mutex warmMutex_;                          // held while the speech thread warms it
	std::thread intake_, speech_, frames_;

	void error(const std::string& message, const std::string& id);
	void intakeLoop();
	void speechLoop();
	// A speak whose phones come in parts (perform/stream.h): a streamed one's piece, or a whole sound to
	// recognise. Errors go to the client; the utterance still ends.
	void streamed(Command& c, const SpeechLimits& limits);
	void hand(const Command& c, Utterance part);  // a part planned and queued for the frame thread
	void frameLoop();
	void frames(LiveSession& session);
	// The frame thread's steps: the hello (and the record's first line); a request into the session; the
	// requests handed over for this frame (false: the client is gone); a frame's pace; whether the session
	// ends after this frame (shutdown drained, or idle past --idle-timeout), telling the client why.
	bool hello(LiveSession& session, const std::string& codecs);
	void apply(LiveSession& session, Command& c, std::int64_t frame);
	bool take(LiveSession& session, std::deque<Command>& todo, std::deque<Command>& ready, std::int64_t n);
	// utterance_ended (interrupted) for say/speak that never joined the session; false: the client is gone.
	bool endUnstarted(LiveSession& session, const std::vector<std::string>& ids, std::int64_t n);
	void account(double took, double behind, double frameSeconds);
	// A frame's events to the client (an utterance's start with its latency); false when the client is gone.
	bool sendEvents(const std::vector<LiveEvent>& events, std::map<std::string, ServeClock::time_point>& requestTimes, ServeClock::time_point sent);
	bool ends(bool closing, bool busy, ServeClock::time_point deadline, bool& told);
	SpeechLimits limitsNow() const;  // under m_
	void record(const std::string& line, std::int64_t frame);  // a line of the record, within --record-max
};

}  // namespace talkhead
