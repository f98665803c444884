// SPDX-License-Identifier: GPL-3.0-or-later
// One session of talkhead serve (D54, D58): three threads, none of them the server's network thread.
//   intake  parses each request as it comes (a 30 MB message delays only its own session's requests), and
//           lets a stop overtake everything: it drops what waits for synthesis and cancels the synthesis
//           under way;
//   speech  synthesises (espeak-ng) or decodes each say/speak, within the session's limits;
//   frames  draws and encodes in real time. Prepared utterances wait in its own queue and go into the
//           LiveSession only when the speech before them is about to end, so the session plans only
//           what is near: the cost of a request and of a stop does not grow with the queue.
#include "serve/worker.h"

#include <algorithm>
#include <cstdio>
#include <ctime>

#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "media/video_writer.h"
#include "phonetics/labels.h"
#include "phonetics/language.h"
#include "render/output.h"
#include "serve/access.h"

namespace talkhead {

namespace {

constexpr double kHandoff = 2.0;                      // s: an utterance joins the session this long before the speech before it ends
constexpr std::size_t kInboxMessages = 4096;          // requests received, not yet parsed
constexpr double kLateMemory = 3.0;                   // s: a late frame counts against admission this long

// This thread's CPU time; each of a session's threads adds what it took to SessionStats::cpuNs.
std::int64_t threadCpuNs() {
	timespec t{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return std::int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}
struct CpuMeter {
	std::atomic<std::int64_t>& total;
	std::int64_t last = threadCpuNs();
	void add() {
		const std::int64_t now = threadCpuNs();
		total += now - last;
		last = now;
	}
};

std::int64_t nowNs() { return std::chrono::duration_cast<std::chrono::nanoseconds>(ServeClock::now().time_since_epoch()).count(); }

}  // namespace

void ServeCounters::latency(double seconds) {
	std::lock_guard<std::mutex> lock(latencyMutex);
	std::size_t b = 0;
	while (b < std::size(kBuckets) && seconds > kBuckets[b]) ++b;
	++latencyCounts[b];
	latencySum += seconds;
}

LiveWorker::LiveWorker(const Face& face, const ServeOptions& o, int id, Send send, Close close, std::shared_ptr<SessionStats> stats,
                       ServeCounters& counters)
    : face_(face), o_(o), id_(id), send_(std::move(send)), close_(std::move(close)), stats_(std::move(stats)), counters_(counters), lastRequestNs_(nowNs()) {
	if (o_.recordDir) {
		record_.open(*o_.recordDir + "/session-" + std::to_string(id_) + ".jsonl");
		if (!record_) throw Error(*o_.recordDir, 0, "cannot write the session record");
	}
	frames_ = std::thread([this] { frameLoop(); });
	speech_ = std::thread([this] { speechLoop(); });
	intake_ = std::thread([this] { intakeLoop(); });
}

LiveWorker::~LiveWorker() {
	cancel();
	if (intake_.joinable()) intake_.join();
	if (speech_.joinable()) speech_.join();  // before the frames: it may be warming the frame thread's session
	if (frames_.joinable()) frames_.join();
	if (record_.is_open()) record_ << JsonObject().add("type", "end").add("frame", static_cast<long long>(drawn_)).str() << "\n";
	if (o_.log && drawn_ > 0) {
		char b[200];
		std::snprintf(b, sizeof b, "session %d: %lld frames, %.1f ms each to draw and encode, %lld late by more than a frame (latest %.0f ms after its time)", id_,
		              static_cast<long long>(drawn_), 1000 * work_ / double(drawn_), static_cast<long long>(late_), 1000 * std::max(0.0, worst_));
		o_.log(b);
	}
}

void LiveWorker::cancel() {
	{
		std::lock_guard<std::mutex> lock(m_);
		quit_ = true;
	}
	cancel_ = true;
	inboxCv_.notify_all();
	speechCv_.notify_all();
	frameCv_.notify_all();
}

void LiveWorker::shutdown(ServeClock::time_point deadline) {
	std::lock_guard<std::mutex> lock(m_);
	closing_ = true;
	deadline_ = deadline;
	for (const Command& q : speechQueue_)  // not started: dropped (what is prepared still plays), each ended
		if (q.request.kind != LiveRequest::Kind::Emotion) orphans_.push_back(q.request.id);
	speechQueue_.clear();
	frameCv_.notify_all();
}

void LiveWorker::request(std::string text, bool oversize) {
	const auto received = ServeClock::now();
	lastRequestNs_ = nowNs();
	std::lock_guard<std::mutex> lock(m_);
	if (inbox_.size() >= kInboxMessages || inboxBytes_ + text.size() > 2 * o_.maxMessage) {
		// Requests arrive faster than they can be read: this one is answered at once (its id unknown: not parsed).
		send_(false, JsonObject().add("type", "error").add("message", "requests arrive faster than the session reads them: this one is dropped").str());
		return;
	}
	inboxBytes_ += text.size();
	inbox_.push_back(Inbound{std::move(text), oversize, received});
	inboxCv_.notify_all();
}

namespace {
// {"type": "error" or "warning", "message": …, "id": …}: what a session tells its client.
std::string messageJson(const char* type, const std::string& message, const std::string& id) {
	JsonObject j;
	j.add("type", type).add("message", safeLine(forRequester(message)));
	if (!id.empty()) j.raw("id", id);
	return j.str();
}
}  // namespace

void LiveWorker::error(const std::string& message, const std::string& id) {
	++counters_.requestErrors;
	send_(false, messageJson("error", message, id));
}

SpeechLimits LiveWorker::limitsNow() const {
	SpeechLimits l;
	const double room = o_.limits.queuedSeconds - stats_->queuedSeconds.load() - handedSeconds_;
	l.maxSeconds = std::max(0.0, std::min(o_.limits.utteranceSeconds, room));
	l.maxBreakSeconds = o_.limits.breakSeconds;
	l.cancel = &cancel_;
	return l;
}

void LiveWorker::intakeLoop() {
	CpuMeter cpu{stats_->cpuNs};
	for (;;) {
		cpu.add();
		Inbound in;
		bool closing = false;
		{
			std::unique_lock<std::mutex> lock(m_);
			inboxCv_.wait(lock, [&] { return quit_ || !inbox_.empty(); });
			if (quit_) return;
			in = std::move(inbox_.front());
			inbox_.pop_front();
			inboxBytes_ -= in.text.size();
			closing = closing_;
		}
		// Every answer to a request names its id: read from the text as far as it can be (item 10).
		auto idOf = [&] {
			auto id = jsonTopLevelMemberJson(in.text, "id");
			if (!id) id = jsonTopLevelMemberJson(in.text, "continue");  // a streamed speak's piece: the stream's
			try {
				return id ? requestIdJson(*id) : std::string();
			} catch (const Error&) {
				return std::string();  // not an id: the error names none
			}
		};
		if (in.oversize) {
			error("the request is larger than " + std::to_string(o_.maxMessage >> 20) + " MiB", idOf());
			continue;
		}
		LiveRequest r;
		try {
			r = parseLiveRequest(in.text);
		} catch (const std::exception& e) {
			error(describeException(e), idOf());
			continue;
		}
		++counters_.requests;
		if (closing) {
			error("the server is shutting down: no new requests", r.id);
			continue;
		}
		std::string recorded = o_.recordDir ? requestForRecord(in.text, r) : std::string();
		Command c{std::move(r), std::nullopt, std::move(recorded), 0, in.received, {}, {}};
		std::unique_lock<std::mutex> lock(m_);
		if (c.request.kind == LiveRequest::Kind::Stop) {
			// Barge-in: what waits for synthesis goes, the synthesis under way stops, and the stop overtakes
			// everything queued: the frame thread takes it at its next frame.
			++generation_;
			for (const Command& q : speechQueue_)
				if (q.request.kind != LiveRequest::Kind::Emotion && !q.request.continues) c.dropped.push_back(q.request.id);
			// A streamed speak none of whose parts reached the frames ends here; one that has, in the session.
			const bool streamHere = !streamId_.empty() && !streamHanded_;
			if (preparing_ && preparingId_ != streamId_) c.dropped.insert(c.dropped.begin(), preparingId_);
			if (streamHere) c.dropped.insert(c.dropped.begin(), streamId_);
			streamId_.clear();
			speechQueue_.clear();
			cancel_ = true;
			c.generation = generation_;
			frameQueue_.push_back(std::move(c));
			frameCv_.notify_all();
			continue;
		}
		if (c.request.kind != LiveRequest::Kind::Emotion && !c.request.continues) {
			const int queued = int(std::count_if(speechQueue_.begin(), speechQueue_.end(), [](const Command& q) { return q.request.kind != LiveRequest::Kind::Emotion; })) +
			                   (preparing_ ? 1 : 0) + handed_ + stats_->queuedRequests.load();
			if (queued >= o_.limits.queuedRequests) {
				lock.unlock();
				error(std::to_string(queued) + " requests are queued already, the most a session may have ({{max-queued-requests}}): wait for utterance_ended, or stop",
				      c.request.id);
				continue;
			}
		}
		c.generation = generation_;
		speechQueue_.push_back(std::move(c));
		speechCv_.notify_all();
	}
}

void LiveWorker::speechLoop() {
	CpuMeter cpu{stats_->cpuNs};
	for (;;) {
		cpu.add();
		Command c;
		SpeechLimits limits;
		{
			std::unique_lock<std::mutex> lock(m_);
			speechCv_.wait(lock, [&] { return quit_ || !speechQueue_.empty(); });
			if (quit_) return;
			c = std::move(speechQueue_.front());
			speechQueue_.pop_front();
			cancel_ = false;  // a stop from now on cancels this one
			preparing_ = c.request.kind != LiveRequest::Kind::Emotion;
			preparingId_ = c.request.id;
			limits = limitsNow();
		}
		double seconds = 0;
		if (speaksInParts(c.request)) {
			streamed(c, limits);
			std::lock_guard<std::mutex> lock(m_);
			preparing_ = false;
			continue;
		}
		if (c.request.kind == LiveRequest::Kind::Say || c.request.kind == LiveRequest::Kind::Speak) {
			try {
				if (limits.maxSeconds <= 0) {
					char b[200];
					std::snprintf(b, sizeof b, "the session has %.0f s of speech queued already, the most it may have ({{max-queued-speech}}): wait, or stop",
					              o_.limits.queuedSeconds);
					throw Error(b);
				}
				c.utterance = PlannedUtterance(prepareUtterance(c.request, o_.lang, o_.live.sampleRate, limits));
				seconds = toSeconds(c.utterance->duration());
				// Its keypose images made here, not in the frame thread (a frame would be late).
				Expression expression;
				{
					std::lock_guard<std::mutex> lock(m_);
					expression = c.request.expression.value_or(expression_);
				}
				std::lock_guard<std::mutex> warming(warmMutex_);
				if (LiveSession* s = session_.load()) c.utterance = s->plan(std::move(c.utterance->utterance), expression);
				for (const auto& w : c.utterance->utterance.warnings)
					send_(false, messageJson("warning", w, c.request.id));
			} catch (const SpeechCancelled&) {
				std::lock_guard<std::mutex> lock(m_);
				preparing_ = false;
				continue;  // a stop, or the session's end
			} catch (const std::exception& e) {
				{
					std::lock_guard<std::mutex> lock(m_);
					preparing_ = false;
				}
				error(describeException(e), c.request.id);
				continue;
			}
		}
		std::lock_guard<std::mutex> lock(m_);
		preparing_ = false;
		if (c.generation != generation_) continue;  // a stop came meanwhile: it ends this one (its `dropped`)
		if (closing_) {  // the server is going: it never starts
			if (c.utterance) orphans_.push_back(c.request.id);
			continue;
		}
		if (c.utterance) ++handed_, handedSeconds_ += seconds;
		frameQueue_.push_back(std::move(c));
		frameCv_.notify_all();
	}
}

void LiveWorker::hand(const Command& c, Utterance part) {
	Command p;  // what the frame thread reads of the request (not its audio, which may be megabytes)
	p.request.kind = c.request.kind;
	p.request.id = c.request.id;
	p.request.ramp = c.request.ramp;
	if (part.opens) p.request.expression = c.request.expression;  // the emotion changes with the first part only
	p.generation = c.generation;
	p.received = part.opens ? streamReceived_ : c.received;
	p.alsoRecorded = std::move(streamRecord_);  // the pieces that led to it, for the record
	streamRecord_.clear();
	p.part = true;
	const double seconds = toSeconds(part.duration());
	const bool opens = part.opens, closes = part.closes;
	{
		Expression expression;
		{
			std::lock_guard<std::mutex> lock(m_);
			expression = c.request.expression.value_or(expression_);
		}
		std::lock_guard<std::mutex> warming(warmMutex_);
		if (LiveSession* s = session_.load()) p.utterance = s->plan(std::move(part), expression);
		else p.utterance = PlannedUtterance(std::move(part));
	}
	for (const auto& w : p.utterance->utterance.warnings) send_(false, messageJson("warning", w, c.request.id));
	std::lock_guard<std::mutex> lock(m_);
	if (p.generation != generation_) throw SpeechCancelled();  // a stop came: it ends the utterance
	if (closing_) {  // the server is going: what has not started never does
		if (opens) orphans_.push_back(c.request.id);
		throw SpeechCancelled();
	}
	if (streamId_ == c.request.id) {
		streamHanded_ = true;
		if (closes) streamId_.clear();
	}
	++handed_, handedSeconds_ += seconds;
	frameQueue_.push_back(std::move(p));
	frameCv_.notify_all();
}

void LiveWorker::streamed(Command& c, const SpeechLimits& limits) {
	const LiveRequest& r = c.request;
	const int rate = o_.live.sampleRate;
	const auto emit = [&](Utterance part) { hand(c, std::move(part)); };
	bool opened = false;  // a part of this utterance went to the frames (an error must then end it there)
	bool fault = false;   // the error ends the stream (not a refusal of this request alone)
	try {
		if (r.continues) {
			if (stream_ && streamGeneration_ != c.generation) {  // a stop ended it
				stoppedStream_ = stream_->id();
				stream_.reset();
			}
			if (!stream_ || stream_->id() != r.id) {
				if (r.id == stoppedStream_) return;  // its pieces in flight after the stop: dropped
				throw Error("no streamed speak " + r.id + " is open ('continue' names the id of a speak sent with 'more': true)");
			}
			fault = true;
			if (r.pcmRate && r.pcmRate != stream_->inputRate())
				throw Error("the piece's 'sample_rate' (" + std::to_string(r.pcmRate) + ") is not the stream's (" + std::to_string(stream_->inputRate()) + ")");
			opened = stream_->opened();
			const std::vector<float> piece = pcmMono(r.audio, r.pcmChannels ? r.pcmChannels : streamChannels_);
			if (toSeconds(stream_->received()) + double(piece.size()) / stream_->inputRate() > o_.limits.utteranceSeconds) {
				char b[200];
				std::snprintf(b, sizeof b, "the streamed speak is longer than the %g s allowed ({{max-utterance}})", o_.limits.utteranceSeconds);
				throw Error(b);
			}
			bool waiting = false;  // the stream's next piece has come already: look for words after it (a fast TTS)
			{
				std::lock_guard<std::mutex> lock(m_);
				waiting = !speechQueue_.empty() && speechQueue_.front().request.continues && speechQueue_.front().request.id == r.id;
			}
			// Whether it looked is recorded: `talkhead live` must look where the stream did to give the same parts.
			if (!c.json.empty()) streamRecord_.push_back({c.json, !waiting || !r.more});
			stream_->feed(piece, !r.more, emit, &cancel_, !waiting);
			opened = stream_->opened();
			if (stream_->closed()) stream_.reset();
			return;
		}
		if (stream_ && streamGeneration_ == c.generation && !stream_->closed())
			throw Error("a streamed speak (" + stream_->id() + ") is open: send its last piece ('continue' without 'more') before another speak");
		if (stream_ && streamGeneration_ != c.generation) stoppedStream_ = stream_->id();
		stream_.reset();
		if (limits.maxSeconds <= 0) {
			char b[200];
			std::snprintf(b, sizeof b, "the session has %.0f s of speech queued already, the most it may have ({{max-queued-speech}}): wait, or stop", o_.limits.queuedSeconds);
			throw Error(b);
		}
		const Language& lang = Language::get(r.lang.empty() ? o_.lang : r.lang);
		if (r.more) {
			stream_ = std::make_unique<SpeechStream>(r.id, r.text, lang, r.pcmRate, rate);
			streamGeneration_ = c.generation;
			streamReceived_ = c.received;
			streamChannels_ = r.pcmChannels;
			streamRecord_.clear();
			if (!c.json.empty()) streamRecord_.push_back({c.json, true});
			{
				std::lock_guard<std::mutex> lock(m_);
				streamId_ = r.id;
				streamHanded_ = false;
			}
			fault = true;
			stream_->feed(pcmMono(r.audio, r.pcmChannels), false, emit, &cancel_);
			opened = stream_->opened();
			return;
		}
		// A whole sound with no timing: recognised an utterance at a time, the first part given out as soon as
		// its phones are known (issue 49's latency goal for speak with the audio alone).
		Utterance u = prepareUtterance(r, o_.lang, rate, limits, false);
		SpeechStream whole(r.id, "", lang, rate, rate);
		streamReceived_ = c.received;
		streamRecord_.clear();
		if (!c.json.empty()) streamRecord_.push_back({c.json, true});
		{
			std::lock_guard<std::mutex> lock(m_);
			streamId_ = r.id;  // parts in the session: a stop ends it there, not twice
			streamHanded_ = false;
		}
		fault = true;
		try {
			whole.feed(u.audio.samples, true, emit, &cancel_);
		} catch (...) {
			opened = whole.opened();
			throw;
		}
	} catch (const SpeechCancelled&) {
		if (stream_ && stream_->id() == r.id) {
			stoppedStream_ = r.id;
			stream_.reset();
		}
		return;  // a stop (it ends the utterance), or the session's end
	} catch (const std::exception& e) {
		error(describeException(e), r.id);
		if (!fault) return;  // this request refused; an open stream goes on
		if (stream_) opened = opened || stream_->opened();
		stream_.reset();
		{
			std::lock_guard<std::mutex> lock(m_);
			if (!opened && streamId_ == r.id) streamId_.clear();
		}
		if (opened) {
			// Its parts so far play; the utterance ends after them.
			Utterance end;
			end.id = r.id;
			end.opens = false;
			end.audio.sampleRate = rate, end.audio.channels = 1;
			try {
				hand(c, std::move(end));
			} catch (const std::exception&) {
			}
		}
	}
}

void LiveWorker::frameLoop() {
	{
		// Sessions admitted together start one after another (issue 45: a session's start takes ~90 ms of a
		// core, and eight at once made the running sessions' frames late); requests queue meanwhile.
		std::unique_lock<std::mutex> lock(m_);
		frameCv_.wait_until(lock, stats_->opened, [&] { return quit_; });
		if (quit_) return;
	}
	try {
		LiveSession session(face_, o_.live);
		session_ = &session;
		struct Forget {  // before the session goes, and never while the speech thread warms it
			std::atomic<LiveSession*>& p;
			std::mutex& m;
			~Forget() {
				std::lock_guard<std::mutex> lock(m);
				p = nullptr;
			}
		} forget{session_, warmMutex_};
		frames(session);
	} catch (const std::exception& e) {
		send_(false, messageJson("error", describeException(e), ""));
		if (o_.log) o_.log("session " + std::to_string(id_) + ": " + describeException(e));
		close_(End::Failed);
	}
}

bool LiveWorker::hello(LiveSession& session, const std::string& codecs) {
	const StreamInfo& info = session.info();
	JsonArray emotions;
	for (const auto& e : emotionLabels()) emotions.add(e.label);
	const std::string hello = JsonObject()
	                              .add("type", "hello")
	                              .add("session", id_)
	                              .add("width", info.width)
	                              .add("height", info.height)
	                              .add("fps", info.rate.fps(), "%.6g")
	                              .add("rate", info.rate.str())
	                              .add("sample_rate", session.sampleRate())
	                              .add("mime", "video/mp4; codecs=\"" + codecs + "\"")
	                              .add("emotion", session.expression().emotion().label())
	                              .raw("emotions", emotions.str())
	                              .str();
	record(JsonObject()
	           .add("type", "session")
	           .add("width", info.width)
	           .add("height", info.height)
	           .add("rate", info.rate.str())
	           .add("emotion", session.expression().emotion().label())
	           .add("lang", o_.lang)
	           .str(),
	       0);
	return send_(false, hello);
}

void LiveWorker::apply(LiveSession& session, Command& c, std::int64_t frame) {
	applyLiveRequest(session, c.request, std::move(c.utterance));
	std::lock_guard<std::mutex> lock(m_);
	expression_ = session.expression();
	for (const auto& [j, look] : c.alsoRecorded) {
		JsonObject step;
		step.add("frame", frame);
		if (!look) step.raw("look", "false");  // before the request: a script's reader takes the request to the line's end
		record(step.raw("request", j).str(), frame);
	}
	if (!c.json.empty()) record(JsonObject().add("frame", frame).raw("request", c.json).str(), frame);
	if (c.part) {
		JsonObject step;
		step.add("frame", frame).add("type", "part");
		if (!c.request.id.empty()) step.raw("id", c.request.id);  // JSON text already (the client's, as written)
		record(step.str(), frame);
	}
}

void LiveWorker::record(const std::string& line, std::int64_t frame) {
	if (!record_.is_open()) return;
	if (recorded_ + line.size() + 1 > o_.recordMaxBytes) {
		// Full (issue 45: ten 30 MB requests made a 300 MB file): the record ends here, a script that replays
		// what came before; the session goes on.
		record_ << JsonObject().add("type", "end").add("frame", static_cast<long long>(frame)).add("truncated", true).str() << "\n";
		record_.close();
		if (o_.log) o_.log("session " + std::to_string(id_) + ": its record reached " + std::to_string(o_.recordMaxBytes >> 20) + " MiB ({{record-max}}): recording stopped at frame " + std::to_string(frame));
		return;
	}
	recorded_ += line.size() + 1;
	record_ << line << "\n";
}

bool LiveWorker::endUnstarted(LiveSession& session, const std::vector<std::string>& ids, std::int64_t n) {
	for (const std::string& id : ids) {
		LiveEvent e;
		e.kind = LiveEvent::Kind::UtteranceEnded;
		e.frame = n;
		e.time = session.nextTime();
		e.id = id;
		e.interrupted = true;
		if (!send_(false, liveEventJson(e))) return false;
	}
	return true;
}

bool LiveWorker::take(LiveSession& session, std::deque<Command>& todo, std::deque<Command>& ready, std::int64_t n) {
	for (Command& c : todo) {
		try {
			if (c.request.kind == LiveRequest::Kind::Stop) {
				// Prepared utterances that never started end now, interrupted (as queued ones do in the session).
				// So do the requests the stop dropped before they were prepared: in the order they came, after
				// the one under way and before `stopped`.
				std::vector<std::string> ended;
				for (const Command& r : ready)
					if (r.utterance->utterance.opens) ended.push_back(r.request.id);  // a later part's utterance is the session's
				ended.insert(ended.end(), c.dropped.begin(), c.dropped.end());
				ready.clear();
				session.stop(c.request.id, ended);
				std::lock_guard<std::mutex> lock(m_);
				record(JsonObject().add("frame", n).raw("request", c.json).str(), n);
			} else if (c.utterance) {
				ready.push_back(std::move(c));
			} else {
				apply(session, c, n);
			}
		} catch (const std::exception& e) {
			error(describeException(e), c.request.id);
		}
	}
	return true;
}

void LiveWorker::account(double took, double behind, double frameSeconds) {
	work_ += took;
	worst_ = std::max(worst_, behind);
	++counters_.frames;
	if (behind > frameSeconds) {
		if (late_ == 0 && o_.log) {  // the first (admission should have refused before it, issue 45)
			char b[160];
			std::snprintf(b, sizeof b, "session %d: its first late frame, %lld (%.0f ms after its time)", id_, static_cast<long long>(drawn_), 1000 * behind);
			o_.log(b);
		}
		++late_;
		++counters_.lateFrames;
		stats_->lastLateNs = nowNs();
	}
}

bool LiveWorker::ends(bool closing, bool busy, ServeClock::time_point deadline, bool& told) {
	if (closing) {
		if (!told) {
			told = true;
			if (!send_(false, JsonObject().add("type", "closing").add("reason", "shutdown").add("message", "the server is shutting down").str())) return true;
		}
		if (busy && ServeClock::now() < deadline) return false;
		close_(End::Shutdown);
		return true;
	}
	if (o_.idleSeconds <= 0 || busy || double(nowNs() - lastRequestNs_.load()) * 1e-9 <= o_.idleSeconds) return false;
	{
		std::lock_guard<std::mutex> lock(m_);
		if (preparing_ || !speechQueue_.empty() || !inbox_.empty()) return false;
	}
	++counters_.closedIdle;
	char b[120];
	std::snprintf(b, sizeof b, "no request for %g s: the session is closed ({{idle-timeout}})", o_.idleSeconds);
	send_(false, JsonObject().add("type", "closing").add("reason", "idle").add("message", forRequester(b)).str());
	close_(End::Idle);
	return true;
}

namespace {

// The session's stream, from the registry of output formats (render/output.h), begun: its init segment is
// written and its codecs known.
std::unique_ptr<FrameSink> streamSink(const ServeOptions& o, LiveSession& session, std::function<bool(const std::uint8_t*, std::size_t)> write) {
	OutputSpec spec;
	spec.format = VideoFormat::Mp4Stream, spec.write = std::move(write), spec.crf = o.crf, spec.preset = o.preset, spec.threads = o.encoderThreads;
	std::unique_ptr<FrameSink> sink = makeVideoSink(spec, borrowedSource(session.audio()));
	sink->begin(session.info());
	return sink;
}

// The session's cores, smoothed over seconds: all its threads' CPU time over the wall time.
struct LoadSampler {
	std::int64_t cpu, wall;
	double load = -1;
	explicit LoadSampler(const SessionStats& s) : cpu(s.cpuNs.load()), wall(nowNs()) {}
	void sample(SessionStats& s) {
		const std::int64_t c = s.cpuNs.load(), w = nowNs();
		const double now = double(c - cpu) / double(std::max<std::int64_t>(1, w - wall));
		load = load < 0 ? now : 0.7 * load + 0.3 * now;
		s.load = load;
		cpu = c, wall = w;
	}
};

}  // namespace

bool LiveWorker::sendEvents(const std::vector<LiveEvent>& events, std::map<std::string, ServeClock::time_point>& requestTimes, ServeClock::time_point sent) {
	for (const LiveEvent& e : events) {
		std::optional<double> latencyMs;  // an utterance's start: from its request to the frame that shows it
		if (e.kind == LiveEvent::Kind::UtteranceStarted) {
			auto it = requestTimes.find(e.id);
			if (it != requestTimes.end()) {
				const double latency = std::chrono::duration<double>(sent - it->second).count();
				counters_.latency(latency);
				latencyMs = 1000 * latency;
				requestTimes.erase(it);
			}
		}
		if (!send_(false, liveEventJson(e, latencyMs))) return false;
	}
	return true;
}

void LiveWorker::frames(LiveSession& session) {
	{
		std::lock_guard<std::mutex> lock(m_);
		expression_ = session.expression();
	}
	const StreamInfo& info = session.info();
	std::string bytes;  // what the encoder made since the last send
	const std::unique_ptr<FrameSink> stream =
	    streamSink(o_, session, [&bytes](const std::uint8_t* d, std::size_t n) { bytes.append(reinterpret_cast<const char*>(d), n); return true; });
	if (!hello(session, stream->codecs()) || !send_(true, std::move(bytes))) return;
	bytes.clear();
	std::vector<LiveEvent> events;
	std::deque<Command> ready;  // prepared say/speak, not yet in the session
	std::vector<std::string> orphans;  // say/speak the shutdown dropped
	std::map<std::string, ServeClock::time_point> requestTimes;  // utterance id → when its request came
	const ServeClock::time_point start = ServeClock::now();
	const double frameSeconds = 1.0 / info.rate.fps();
	CpuMeter cpu{stats_->cpuNs};
	LoadSampler load(*stats_);
	bool told = false;  // of the shutdown
	for (std::int64_t n = 0;; ++n) {
		std::deque<Command> todo;
		bool closing = false;
		ServeClock::time_point deadline;
		const auto due = start + std::chrono::duration_cast<ServeClock::duration>(std::chrono::duration<double>(double(n) * frameSeconds));
		{
			std::unique_lock<std::mutex> lock(m_);
			frameCv_.wait_until(lock, due, [&] { return quit_; });
			if (quit_) break;
			todo.swap(frameQueue_);
			for (const Command& c : todo)
				if (c.utterance) --handed_, handedSeconds_ -= toSeconds(c.utterance->duration());
			if (handed_ == 0) handedSeconds_ = 0;
			closing = closing_;
			deadline = deadline_;
			orphans.swap(orphans_);
		}
		if (!take(session, todo, ready, n)) return;
		if (!orphans.empty() && !endUnstarted(session, orphans, n)) return;
		orphans.clear();
		// Into the session when the speech before is about to end.
		while (!ready.empty() && session.queueEnd() <= session.nextTime() + ticksFromSeconds(kHandoff)) {
			Command c = std::move(ready.front());
			ready.pop_front();
			try {
				if (c.utterance->utterance.opens) requestTimes[c.request.id] = c.received;
				apply(session, c, n);
			} catch (const std::exception& e) {
				error(describeException(e), c.request.id);
			}
		}
		double queued = std::max(0.0, toSeconds(session.queueEnd() - session.nextTime()));
		for (const Command& c : ready) queued += toSeconds(c.utterance->duration());
		stats_->queuedSeconds = queued;
		stats_->queuedRequests = int(ready.size()) + (session.speaking() ? 1 : 0);
		events.clear();
		const auto t0 = ServeClock::now();
		session.play(*stream, events);
		drawn_ = session.nextFrame();
		const auto sent = ServeClock::now();
		// Pace: a frame out later than one frame after its time is late (the stream falls behind).
		account(std::chrono::duration<double>(sent - t0).count(), std::chrono::duration<double>(sent - due).count(), frameSeconds);
		cpu.add();
		if (n % 15 == 14) load.sample(*stats_);  // every half second
		if (!sendEvents(events, requestTimes, sent)) return;
		if (!bytes.empty()) {
			if (!send_(true, std::move(bytes))) return;
			bytes.clear();
		}
		// After the frame and its events (an utterance's end goes out before a close).
		const bool busy = session.queueEnd() > info.rate.time(session.nextFrame() - 1) || !ready.empty();
		if (ends(closing, busy, deadline, told)) break;
	}
}

double measureSessionLoad(const Face& face, const ServeOptions& o) {
	LiveSession session(face, o.live);
	const StreamInfo& info = session.info();
	const std::unique_ptr<FrameSink> stream = streamSink(o, session, [](const std::uint8_t*, std::size_t) { return true; });
	// Speaking (the dearer case): a sentence long enough for the whole measurement; its synthesis and keypose
	// images, made on a session's speech thread, are counted too.
	const std::int64_t t0 = threadCpuNs();
	try {
		Utterance u = speakText("Hello, how are you today? I am fine, thank you very much.", Language::get(o.lang), "", o.live.sampleRate);
		session.enqueue(session.plan(std::move(u), session.expression()));
	} catch (const std::exception&) {  // no speech (espeak-ng missing): the idle face is measured
	}
	std::vector<LiveEvent> events;
	const int frames = std::max(10, int(std::lround(info.rate.fps())));
	for (int n = 0; n < frames; ++n) {
		session.play(*stream, events);
		events.clear();
	}
	return double(threadCpuNs() - t0) * 1e-9 / (double(frames) / info.rate.fps());
}

bool lateRecently(const SessionStats& s) {
	const std::int64_t t = s.lastLateNs.load();
	return t >= 0 && double(nowNs() - t) * 1e-9 < kLateMemory;
}

}  // namespace talkhead
