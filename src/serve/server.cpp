// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead serve: HTTP + WebSocket with Boost.Beast (D54), plain or TLS (Boost.Asio SSL, OpenSSL), built as
// the plugin libtalkhead-serve.so (serve_module.h, D68): Beast's templates are the costliest translation unit of
// the tree, and only `talkhead serve` needs them. One io
// thread runs the network and nothing else: each session's parsing, synthesis and frames run on its own
// threads (worker.cpp), and a closed session's threads are joined by a reaper thread. Who may connect:
// access.h (Host, Origin, token); how many: --max-sessions and the measured load (D58).
#include "serve/server.h"
#include "serve/serve_module.h"

#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <deque>
#include <fstream>
#include <list>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>
#include <type_traits>

#include "base/error.h"
#include "base/json.h"
#include "base/plugin.h"
#include "base/text.h"
#include "serve/access.h"
#include "serve/worker.h"

namespace talkhead {

namespace net = boost::asio;
namespace ssl = net::ssl;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using Clock = ServeClock;
using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

// The server behind the Server facade of server.h (same interface), created by the plugin's entry points.
class NetServer {
public:
	NetServer(const ServeHost& host, const Face& face, ServeOptions options);
	~NetServer();
	NetServer(const NetServer&) = delete;
	NetServer& operator=(const NetServer&) = delete;
	int port() const;
	void run();
	void stop();
	void shutdown();
	struct Impl;

private:
	std::unique_ptr<Impl> impl_;
};

namespace {

constexpr std::size_t kMaxQueuedBytes = 64u << 20;  // a client this far behind is dropped
constexpr std::size_t kMaxAuthMessage = 4096;       // an auth message; larger before authentication closes the connection
constexpr int kAuthSeconds = 10;                    // to authenticate after the upgrade
constexpr int kMaxConnections = 512;                // TCP connections at once (HTTP and sessions)
// Connections not yet authenticated (issue 45: 512 idle ones from someone without the token locked out every
// token holder): a small budget of their own, and a smaller one per address. When a budget is full, a new
// connection takes the place of the oldest one that has waited kEvictAfter without authenticating (that one
// is closed); when none has waited that long, the new one is refused. A client that has the token sends it
// with its first request, within milliseconds of connecting, so idle connections cannot keep it out.
constexpr int kMaxUnauthenticated = 64;
constexpr int kMaxUnauthenticatedPerAddress = 16;
constexpr auto kEvictAfter = std::chrono::seconds(1);
constexpr auto kCloseGrace = std::chrono::milliseconds(500);  // shutdown: for clients to answer the close frames
// Admission by load (D58, issue 45 item 3).
constexpr auto kSettled = std::chrono::seconds(3);  // a session's own load is known after this long
constexpr double kOverhead = 1.15;                 // process CPU over the sessions' own, until measured
constexpr double kHysteresis = 0.1;                // of the cores: the bar after a load refusal
constexpr std::int64_t kLateFrames = 3;            // late frames in the window that refuse new sessions (not a blip)
constexpr double kLoadWindowSeconds = 3;
constexpr auto kLoadSample = std::chrono::milliseconds(500);
constexpr auto kStartGap = std::chrono::milliseconds(150);  // between two sessions' starts

// The cores admission divides (at least 1).
double machineCores() { return std::max(1u, std::thread::hardware_concurrency()); }

std::string errorJson(const std::string& message) { return JsonObject().add("type", "error").add("message", safeLine(message)).str(); }

// The sessions' interface the server keeps (one io thread uses it).
class SessionBase {
public:
	virtual ~SessionBase() = default;
	virtual void beginShutdown(Clock::time_point deadline) = 0;
	virtual void dropWorker() = 0;
	virtual bool closeSent() const = 0;  // its close frame is written: nothing more to send
};

// A connection not yet authenticated (io thread): a place in the unauthenticated budget until it
// authenticates or goes; `close` ends it when a newer connection takes its place.
struct Unauthenticated {
	std::string address;
	Clock::time_point since;
	std::function<void()> close;
	bool listed = true;
};

}  // namespace

struct NetServer::Impl {
	const ServeHost host;
	const Face& face;
	ServeOptions o;
	AccessPolicy policy;
	ServeCounters counters;
	// The reaper joins closed sessions' threads (declared before the io context: destroyed after it).
	std::mutex reapMutex;
	std::condition_variable reapCv;
	std::deque<std::unique_ptr<SessionWorker>> toReap;
	bool reapQuit = false;
	std::thread reaper;

	std::atomic<int> sessions{0};
	int connections = 0;  // io thread
	std::atomic<int> nextId{1};
	std::string demoPage;
	bool shuttingDown = false;  // io thread
	std::list<std::pair<std::weak_ptr<SessionBase>, std::shared_ptr<SessionStats>>> live;  // io thread
	Clock::time_point lastAcceptLog{};
	std::int64_t acceptErrorsSinceLog = 0;
	Clock::time_point drainEnd{};
	std::optional<Clock::time_point> allClosedAt;
	bool refusingForLoad = false;  // io thread
	Clock::time_point nextStart{};  // io thread: the earliest a newly admitted session's frames start
	struct LoadSample {
		Clock::time_point at;
		std::int64_t processCpuNs, lateFrames;
		double machineBusy = -1, machineTotal = -1;  // /proc/stat's jiffies, all CPUs (−1: unreadable)
	};
	std::deque<LoadSample> loadSamples;  // every kLoadSample, the last kLoadWindowSeconds

	std::list<std::shared_ptr<Unauthenticated>> unauthenticated;  // io thread: oldest first
	std::map<std::string, int> unauthenticatedBy;                  // per address
	Clock::time_point lastUnauthLog{};
	std::int64_t unauthRefusedSinceLog = 0, unauthClosedSinceLog = 0;
	std::optional<ssl::context> tls;
	// The io context after what its handlers use (destroyed first), the io objects after it.
	net::io_context ioc{1};
	tcp::acceptor acceptor{ioc};
	net::steady_timer backoff{ioc};
	std::optional<net::signal_set> signals;
	net::steady_timer drainTimer{ioc};
	net::steady_timer loadTimer{ioc};

	Impl(const ServeHost& h, const Face& m, ServeOptions opts) : host(h), face(m), o(std::move(opts)) {
		reaper = std::thread([this] {
			std::unique_lock<std::mutex> lock(reapMutex);
			for (;;) {
				reapCv.wait(lock, [&] { return reapQuit || !toReap.empty(); });
				while (!toReap.empty()) {
					std::unique_ptr<SessionWorker> w = std::move(toReap.front());
					toReap.pop_front();
					lock.unlock();
					w.reset();  // joins its threads
					lock.lock();
				}
				if (reapQuit) return;
			}
		});
	}
	~Impl() { stopReaper(); }
	void stopReaper() {
		{
			std::lock_guard<std::mutex> lock(reapMutex);
			reapQuit = true;
		}
		reapCv.notify_all();
		if (reaper.joinable()) reaper.join();
	}
	void retire(std::unique_ptr<SessionWorker> w) {
		if (!w) return;
		w->cancel();
		std::unique_lock<std::mutex> lock(reapMutex);
		if (reapQuit) {  // after the reaper: joined here (the server is ending)
			lock.unlock();
			w.reset();
			return;
		}
		toReap.push_back(std::move(w));
		reapCv.notify_all();
	}
	void log(const std::string& s) const {
		if (o.log) o.log(s);
	}
	// Why a new session cannot start now, or "" (io thread).
	std::string admission(const char*& reason) {
		if (shuttingDown) {
			reason = "shutdown";
			return "the server is shutting down";
		}
		if (sessions.load() >= o.maxSessions) {
			reason = "full";
			std::string m = "the server has " + std::to_string(o.maxSessions) + " sessions already ({{max-sessions}})";
			if (o.idleSeconds > 0) {
				char b[96];
				std::snprintf(b, sizeof b, "; idle sessions close after %g s: try again later", o.idleSeconds);
				m += b;
			}
			return m;
		}
		if (o.maxLoad > 0 && !live.empty()) {  // one session is always served
			// Each session counts at what a speaking one takes (issue 45 item 3: an admitted session not yet
			// measured counted as 0, so a burst of 40 was all admitted): the larger of the start-up
			// measurement and what settled sessions take, or its own measured load when that is more; times
			// what the sessions' own threads do not see (the network thread, the kernel: the process's CPU
			// time over theirs). A load refusal lowers the bar by kHysteresis until a session fits under it.
			const auto now = Clock::now();
			const double cores = machineCores();
			double expected = host.sessionLoad, settledLoad = 0, measured = 0;
			int settled = 0;
			for (const auto& [w, s] : live) {
				measured += s->load.load();
				if (now - s->opened >= kSettled) settledLoad += s->load.load(), ++settled;
			}
			if (settled > 0) expected = std::max(expected, settledLoad / settled);
			double overhead = kOverhead;
			const auto window = loadWindow();
			if (window && settled == int(live.size()) && measured > 0.1 * cores) overhead = std::clamp(window->processLoad / measured, 1.0, 2.0);
			double committed = 0;
			for (const auto& [w, s] : live) committed += std::max(s->load.load(), expected);
			committed *= overhead;
			const double next = expected * overhead;
			// What other processes take is not the sessions' to have.
			const double bar = std::max(0.0, (refusingForLoad ? o.maxLoad - kHysteresis : o.maxLoad) * cores - (window ? window->others : 0.0));
			const std::int64_t late = window ? window->lateFrames : 0;
			if (late >= kLateFrames || committed + next > bar) {
				refusingForLoad = true;
				reason = "load";
				char b[400];
				if (late >= kLateFrames)
					std::snprintf(b, sizeof b, "the server is at capacity (%lld frames were late in the last %d s): a new session's frames would be late; try again later",
					              static_cast<long long>(late), int(kLoadWindowSeconds));
				else
					std::snprintf(b, sizeof b, "the server is at capacity (its %zu sessions take %.2f of %g cores, a new one %.2f more, over %.2f; other processes %.2f): a new session's frames would be late; try again later",
					              live.size(), committed, cores, next, bar, window ? window->others : 0.0);
				return b;
			}
			refusingForLoad = false;
		}
		return "";
	}
	// A place for a new connection from `address` that has not authenticated yet, or nullptr: refused.
	std::shared_ptr<Unauthenticated> admitUnauthenticated(const std::string& address) {
		const auto now = Clock::now();
		auto makeRoom = [&](bool sameAddress) {
			auto oldest = unauthenticated.end();
			for (auto it = unauthenticated.begin(); it != unauthenticated.end(); ++it)
				if (!sameAddress || (*it)->address == address) {
					oldest = it;
					break;
				}
			if (oldest == unauthenticated.end() || now - (*oldest)->since < kEvictAfter) return false;
			const std::shared_ptr<Unauthenticated> gone = *oldest;
			std::shared_ptr<Unauthenticated> place = gone;
			authenticated(place);  // its place is free now; the connection ends when its handlers run
			++counters.closedUnauthenticated;
			++unauthClosedSinceLog;
			if (gone->close) gone->close();
			return true;
		};
		bool ok = true;
		if (unauthenticatedBy[address] >= kMaxUnauthenticatedPerAddress) ok = makeRoom(true);
		if (ok && int(unauthenticated.size()) >= kMaxUnauthenticated) ok = makeRoom(false);
		if (!ok) ++counters.refusedUnauthenticated, ++unauthRefusedSinceLog;
		if ((unauthRefusedSinceLog > 0 || unauthClosedSinceLog > 0) && now - lastUnauthLog >= std::chrono::seconds(1)) {  // once a second at most
			char b[320];
			std::snprintf(b, sizeof b, "connections not yet authenticated: %lld refused, %lld closed for newer ones since the last line (%zu open; at most %d, %d per address; %s has %d)",
			              static_cast<long long>(unauthRefusedSinceLog), static_cast<long long>(unauthClosedSinceLog), unauthenticated.size(), kMaxUnauthenticated,
			              kMaxUnauthenticatedPerAddress, address.c_str(), unauthenticatedBy[address]);
			log(b);
			lastUnauthLog = now;
			unauthRefusedSinceLog = unauthClosedSinceLog = 0;
		}
		if (!ok) {
			if (unauthenticatedBy[address] == 0) unauthenticatedBy.erase(address);
			return nullptr;
		}
		auto u = std::make_shared<Unauthenticated>(Unauthenticated{address, now, {}, true});
		unauthenticated.push_back(u);
		++unauthenticatedBy[address];
		return u;
	}
	// Its place is given back: authenticated, gone or closed for a newer one (null: nothing to give back).
	void authenticated(std::shared_ptr<Unauthenticated>& u) {
		if (!u) return;
		if (u->listed) {
			u->listed = false;
			unauthenticated.remove(u);
			if (--unauthenticatedBy[u->address] <= 0) unauthenticatedBy.erase(u->address);
		}
		u.reset();
	}
	// The authentication deadline of a connection not yet authenticated: kAuthSeconds after it connected.
	static Clock::time_point authDeadline(const Unauthenticated& u) { return u.since + std::chrono::seconds(kAuthSeconds); }
	struct LoadWindow {
		double processLoad;       // cores the whole process took
		std::int64_t lateFrames;  // frames sent late, all sessions
		double others = 0;        // cores the machine's other processes took
	};
	// Over the last kLoadWindowSeconds (nullopt until a second has been sampled).
	std::optional<LoadWindow> loadWindow() const {
		if (loadSamples.size() < 3) return std::nullopt;
		const LoadSample &a = loadSamples.front(), &b = loadSamples.back();
		const double wall = std::chrono::duration<double>(b.at - a.at).count();
		LoadWindow w{double(b.processCpuNs - a.processCpuNs) * 1e-9 / std::max(1e-3, wall), counters.lateFrames.load() - a.lateFrames};
		if (a.machineTotal > 0 && b.machineTotal > a.machineTotal) {
			const double cores = machineCores();
			w.others = std::max(0.0, (b.machineBusy - a.machineBusy) / (b.machineTotal - a.machineTotal) * cores - w.processLoad);
		}
		return w;
	}
	// The machine's CPU time, busy and in all, from /proc/stat's first line (when it counts the CPUs this
	// process sees: in a container it may count the host's, and then it is not used).
	static std::pair<double, double> machineCpu() {
		std::ifstream f("/proc/stat");
		std::string line;
		double busy = -1, total = -1;
		int cpus = 0;
		while (std::getline(f, line)) {
			if (line.rfind("cpu ", 0) == 0) {
				std::istringstream in(line.substr(4));
				double v[8] = {};
				for (double& x : v) in >> x;
				total = v[0] + v[1] + v[2] + v[3] + v[4] + v[5] + v[6] + v[7];
				busy = total - v[3] - v[4];  // not idle, not waiting for I/O
			} else if (line.rfind("cpu", 0) == 0) {
				++cpus;
			}
		}
		if (cpus != int(machineCores())) return {-1, -1};
		return {busy, total};
	}
	void sampleLoad() {
		timespec t{};
		clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
		const auto [busy, total] = machineCpu();
		loadSamples.push_back({Clock::now(), std::int64_t(t.tv_sec) * 1000000000 + t.tv_nsec, counters.lateFrames.load(), busy, total});
		while (loadSamples.size() > 2 && loadSamples.back().at - loadSamples[1].at >= std::chrono::duration<double>(kLoadWindowSeconds)) loadSamples.pop_front();
	}
	// Samples the load every kLoadSample (io thread).
	void loadTick() {
		sampleLoad();
		loadTimer.expires_after(kLoadSample);
		loadTimer.async_wait([this](beast::error_code e) {
			if (!e) loadTick();
		});
	}
	void accept();
	void beginShutdown();
	void drainCheck();
	std::string metrics();
};

namespace {

template <class Stream>
constexpr bool kTls = std::is_same_v<Stream, TlsStream>;

template <class Stream>
class WsSession : public SessionBase, public std::enable_shared_from_this<WsSession<Stream>> {
public:
	WsSession(Stream&& stream, NetServer::Impl& server) : ws_(std::move(stream)), server_(server), authTimer_(server.ioc) {}
	~WsSession() override {
		dropWorker();
		server_.authenticated(unauthenticated_);
		if (counted_) --server_.sessions;
		--server_.connections;
	}

	void run(http::request<http::string_body> req, bool authenticated, std::shared_ptr<Unauthenticated> unauthenticated) {
		authenticated_ = authenticated;
		unauthenticated_ = std::move(unauthenticated);
		if (unauthenticated_) {
			unauthenticated_->close = [weak = this->weak_from_this()] {
				if (auto self = weak.lock()) {
					beast::error_code ignored;
					beast::get_lowest_layer(self->ws_).socket().close(ignored);
				}
			};
		}
		ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
		ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& res) { res.set(http::field::server, "talkhead"); }));
		ws_.read_message_max(0);  // messages are read in parts and bounded here (an oversized one is an error, not a drop)
		ws_.async_accept(req, beast::bind_front_handler(&WsSession::onAccept, this->shared_from_this()));
	}

	void beginShutdown(Clock::time_point deadline) override {
		if (worker_) worker_->shutdown(deadline);
		else if (!closing_) refuse("the server is shutting down", websocket::close_code::going_away);
	}
	void dropWorker() override {
		gone_ = true;
		server_.retire(std::move(worker_));
	}
	bool closeSent() const override { return closeSent_ && !writing_; }

private:
	websocket::stream<Stream> ws_;
	NetServer::Impl& server_;
	net::steady_timer authTimer_;
	beast::flat_buffer buffer_;
	std::string message_;
	bool oversize_ = false, counted_ = false, closing_ = false, authenticated_ = false;
	websocket::close_reason closeReason_{websocket::close_code::normal};
	std::deque<std::pair<bool, std::string>> out_;
	bool writing_ = false;
	std::atomic<std::size_t> queued_{0};
	std::atomic<bool> gone_{false};
	std::unique_ptr<SessionWorker> worker_;
	std::shared_ptr<SessionStats> stats_;
	std::shared_ptr<Unauthenticated> unauthenticated_;  // until the token came
	int id_ = 0;

	void onAccept(beast::error_code ec) {
		if (ec) return;
		if (!authenticated_) {
			// The token comes as the first message: {"type": "auth", "token": "…"}, within kAuthSeconds of connecting.
			if (unauthenticated_) authTimer_.expires_at(NetServer::Impl::authDeadline(*unauthenticated_));
			else authTimer_.expires_after(std::chrono::seconds(kAuthSeconds));
			authTimer_.async_wait([weak = this->weak_from_this()](beast::error_code e) {
				auto self = weak.lock();
				if (e || !self || self->authenticated_ || self->closing_) return;
				++self->server_.counters.refusedAuth;
				self->refuse("no token within " + std::to_string(kAuthSeconds) + " s: send {\"type\": \"auth\", \"token\": \"…\"} first", websocket::close_code::policy_error);
				// A client that does not answer the close frame either is cut off a second later.
				self->authTimer_.expires_after(std::chrono::seconds(1));
				self->authTimer_.async_wait([weak = self->weak_from_this()](beast::error_code e2) {
					if (auto s2 = weak.lock(); s2 && !e2) {
						beast::error_code ignored;
						beast::get_lowest_layer(s2->ws_).socket().close(ignored);
					}
				});
			});
			read();
			return;
		}
		start();
	}

	void refuse(const std::string& message, websocket::close_code code) {
		push(false, errorJson(message));
		closeReason_ = websocket::close_reason(code);
		closing_ = true;
		if (!writing_) close();
	}

	void start() {
		const char* reason = "";
		const std::string why = server_.admission(reason);
		if (!why.empty()) {
			auto& c = server_.counters;
			++(std::string(reason) == "load" ? c.refusedLoad : std::string(reason) == "shutdown" ? c.refusedShutdown : c.refusedFull);
			server_.log("session refused: " + why);
			refuse(forRequester(why), websocket::close_code::try_again_later);
			return;
		}
		++server_.sessions;
		counted_ = true;
		++server_.counters.sessionsOpened;
		id_ = server_.nextId++;
		server_.log("session " + std::to_string(id_) + " opened");
		stats_ = std::make_shared<SessionStats>();
		stats_->opened = std::max(Clock::now(), server_.nextStart);  // paced: kStartGap apart
		server_.nextStart = stats_->opened + kStartGap;
		server_.live.emplace_back(this->weak_from_this(), stats_);
		std::weak_ptr<WsSession> weak = this->shared_from_this();
		auto executor = ws_.get_executor();
		worker_ = server_.host.makeWorker(
		    server_.face, server_.o, id_,
		    [weak, executor](bool binary, std::string data) {
			    auto self = weak.lock();
			    if (!self || self->gone_) return false;
			    if (self->queued_ + data.size() > kMaxQueuedBytes) {
				    self->gone_ = true;
				    net::post(executor, [self] { self->refuse("the client reads too slowly: the session is closed", websocket::close_code::policy_error); });
				    return false;
			    }
			    self->queued_ += data.size();
			    net::post(executor, [self, binary, d = std::move(data)]() mutable { self->push(binary, std::move(d)); });
			    return true;
		    },
		    [weak, executor](SessionWorker::End end) {
			    if (auto self = weak.lock())
				    net::post(executor, [self, end] {
					    self->closeReason_ = websocket::close_reason(end == SessionWorker::End::Shutdown ? websocket::close_code::going_away
					                                                 : end == SessionWorker::End::Idle   ? websocket::close_code::normal
					                                                                                  : websocket::close_code::internal_error);
					    self->closing_ = true;
					    if (!self->writing_) self->close();
				    });
		    },
		    stats_, server_.counters);
		if (server_.shuttingDown) worker_->shutdown(server_.drainEnd);
		if (!reading_) read();
	}

	bool reading_ = false;
	void read() {
		reading_ = true;
		ws_.async_read_some(buffer_, 1 << 16, beast::bind_front_handler(&WsSession::onRead, this->shared_from_this()));
	}

	void onRead(beast::error_code ec, std::size_t) {
		if (ec) {  // closed or broken: the session ends; its threads are joined elsewhere (never here)
			gone_ = true;
			authTimer_.cancel();
			if (counted_) server_.log("session " + std::to_string(id_) + " closed");
			forget();
			dropWorker();
			return;
		}
		const std::size_t n = buffer_.size();
		const std::size_t limit = authenticated_ ? server_.o.maxMessage : kMaxAuthMessage;
		if (!oversize_ && message_.size() + n <= limit) {
			const auto data = buffer_.data();
			message_.append(static_cast<const char*>(data.data()), data.size());
		} else if (!oversize_) {
			oversize_ = true;
			message_.resize(std::min<std::size_t>(message_.size(), 1 << 16));  // its beginning: for its id
		}
		buffer_.consume(n);
		if (!authenticated_ && oversize_) return refuse("the first message must be a short auth request", websocket::close_code::policy_error);
		if (ws_.is_message_done()) {
			if (!authenticated_) {
				authenticate();
			} else if (!ws_.got_text() && !oversize_) {
				push(false, errorJson("binary messages are not requests: send JSON text (audio goes base64 in a speak request)"));
			} else if (worker_) {
				worker_->request(std::move(message_), oversize_);
			}
			message_.clear();
			oversize_ = false;
			if (closing_) return;
		}
		read();
	}

	// The first message when the upgrade had no token: at most kMaxAuthMessage bytes, read for two members.
	void authenticate() {
		const auto type = jsonTopLevelMember(message_, "type");
		const auto token = jsonTopLevelMember(message_, "token");
		if (!ws_.got_text() || type != "auth" || !token || !sameToken(server_.o.token, *token)) {
			++server_.counters.refusedAuth;
			server_.log("session refused: no valid token");
			refuse(type == "auth" ? "authentication failed: wrong token" : "authentication required: send {\"type\": \"auth\", \"token\": \"…\"} first",
			       websocket::close_code::policy_error);
			return;
		}
		authenticated_ = true;
		authTimer_.cancel();
		server_.authenticated(unauthenticated_);
		start();
	}

	void forget() {
		auto& l = server_.live;
		for (auto it = l.begin(); it != l.end();) {
			auto s = it->first.lock();
			if (!s || s.get() == this) it = l.erase(it);
			else ++it;
		}
		if (server_.shuttingDown) server_.drainCheck();
	}

	void push(bool binary, std::string data) {
		out_.emplace_back(binary, std::move(data));
		if (!writing_) write();
	}

	void write() {
		if (out_.empty()) {
			writing_ = false;
			if (closing_) close();
			return;
		}
		writing_ = true;
		ws_.binary(out_.front().first);
		ws_.async_write(net::buffer(out_.front().second), beast::bind_front_handler(&WsSession::onWrite, this->shared_from_this()));
	}

	void onWrite(beast::error_code ec, std::size_t) {
		queued_ -= std::min<std::size_t>(queued_, out_.front().second.size());
		out_.pop_front();
		if (ec) {
			gone_ = true;
			writing_ = false;
			return;
		}
		write();
	}

	bool closeSent_ = false;
	void close() {
		if (closeSent_) return;
		closeSent_ = true;
		ws_.async_close(closeReason_, [self = this->shared_from_this()](beast::error_code) {});
	}
};

template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
public:
	template <class... Args>
	HttpSession(NetServer::Impl& server, Args&&... args) : stream_(std::forward<Args>(args)...), server_(server) {
		++server_.connections;
	}
	~HttpSession() {
		server_.authenticated(unauthenticated_);
		if (!upgraded_) --server_.connections;
	}
	void run(std::shared_ptr<Unauthenticated> unauthenticated) {
		unauthenticated_ = std::move(unauthenticated);
		unauthenticated_->close = [weak = this->weak_from_this()] {
			if (auto self = weak.lock()) {
				beast::error_code ignored;
				beast::get_lowest_layer(self->stream_).socket().close(ignored);
			}
		};
		net::dispatch(stream_.get_executor(), [self = this->shared_from_this()] {
			if constexpr (kTls<Stream>) {
				beast::get_lowest_layer(self->stream_).expires_at(NetServer::Impl::authDeadline(*self->unauthenticated_));
				self->stream_.async_handshake(ssl::stream_base::server, [self](beast::error_code ec) {
					if (!ec) self->read();
				});
			} else {
				self->read();
			}
		});
	}

private:
	Stream stream_;
	beast::flat_buffer buffer_;
	NetServer::Impl& server_;
	std::optional<http::request_parser<http::string_body>> parser_;
	bool upgraded_ = false;
	std::shared_ptr<Unauthenticated> unauthenticated_;  // until a request proves it may come in

	void read() {
		parser_.emplace();
		parser_->body_limit(1 << 16);
		parser_->header_limit(16 << 10);
		// Not yet authenticated: kAuthSeconds from the connection on, whatever it sends meanwhile.
		if (unauthenticated_) beast::get_lowest_layer(stream_).expires_at(NetServer::Impl::authDeadline(*unauthenticated_));
		else beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(30));
		http::async_read(stream_, buffer_, *parser_, beast::bind_front_handler(&HttpSession::onRead, this->shared_from_this()));
	}

	void shutdown() {
		if constexpr (kTls<Stream>) {
			beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(5));
			stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {});
		} else {
			beast::error_code ignored;
			stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
		}
	}

	void onRead(beast::error_code ec, std::size_t) {
		if (ec == http::error::header_limit || ec == http::error::body_limit) {
			// Answered, then closed (issue 45: an oversized header just closed the connection).
			http::request<http::string_body> req;
			req.version(11);
			req.keep_alive(false);
			return ec == http::error::header_limit
			           ? reply(req, http::status::request_header_fields_too_large, "text/plain", "talkhead serve: the request's header is larger than 16 KiB\n")
			           : reply(req, http::status::payload_too_large, "text/plain", "talkhead serve: the request's body is larger than 64 KiB\n");
		}
		if (ec) return shutdown();
		http::request<http::string_body> req = parser_->release();
		// The path without its query (issue 45: /health?x=1 was not found).
		const std::string target(req.target().substr(0, req.target().find('?')));
		const std::string host(req[http::field::host]);
		if (auto why = refusedHost(server_.policy, host)) {
			++server_.counters.refusedHost;
			return reply(req, http::status::forbidden, "text/plain", "talkhead serve: " + wordFields(*why, server_.o.operatorField) + "\n");
		}
		const auto bearer = bearerToken(std::string(req[http::field::authorization]));
		const bool tokenOk = server_.o.token.empty() || (bearer && sameToken(server_.o.token, *bearer));
		if (tokenOk) server_.authenticated(unauthenticated_);  // no token asked, or the right one given
		if (websocket::is_upgrade(req)) {
			if (target != "/live") return reply(req, http::status::not_found, "text/plain", "talkhead serve: WebSocket sessions are at /live\n");
			if (auto why = refusedOrigin(server_.policy, std::string(req[http::field::origin]), host, kTls<Stream>)) {
				++server_.counters.refusedOrigin;
				server_.log("upgrade refused: " + *why);
				return reply(req, http::status::forbidden, "text/plain", "talkhead serve: " + wordFields(*why, server_.o.operatorField) + "\n");
			}
			if (bearer && !tokenOk) {
				++server_.counters.refusedAuth;
				server_.log("upgrade refused: wrong token");
				return reply(req, http::status::unauthorized, "text/plain", "talkhead serve: wrong token\n");
			}
			if (server_.connections > kMaxConnections) return reply(req, http::status::service_unavailable, "text/plain", "talkhead serve: too many connections\n");
			beast::get_lowest_layer(stream_).expires_never();
			upgraded_ = true;
			std::make_shared<WsSession<Stream>>(std::move(stream_), server_)->run(std::move(req), tokenOk, std::move(unauthenticated_));
			return;
		}
		if (req.method() != http::verb::get && req.method() != http::verb::head)
			return reply(req, http::status::method_not_allowed, "text/plain", "talkhead serve: GET only; requests go over the WebSocket at /live\n");
		if (target == "/" || target == "/index.html") {
			if (server_.demoPage.empty()) return reply(req, http::status::not_found, "text/plain", "talkhead serve: the demo page is off (" + wordFields("{{demo}}", server_.o.operatorField) + ")\n");
			return reply(req, http::status::ok, "text/html; charset=utf-8", server_.demoPage);
		}
		if (target == "/health") {
			const std::string j = JsonObject()
			                          .add("sessions", static_cast<long long>(server_.sessions.load()))
			                          .add("max_sessions", server_.o.maxSessions)
			                          .add("shutting_down", bool(server_.shuttingDown))
			                          .str() + "\n";
			return reply(req, server_.shuttingDown ? http::status::service_unavailable : http::status::ok, "application/json", j);
		}
		if (target == "/metrics") {
			if (!tokenOk) return reply(req, http::status::unauthorized, "text/plain", "talkhead serve: /metrics needs the token (Authorization: Bearer …)\n");
			return reply(req, http::status::ok, "text/plain; version=0.0.4", server_.metrics());
		}
		reply(req, http::status::not_found, "text/plain", "talkhead serve: not found\n");
	}

	void reply(const http::request<http::string_body>& req, http::status status, const char* type, std::string body) {
		auto res = std::make_shared<http::response<http::string_body>>(status, req.version());
		res->set(http::field::server, "talkhead");
		res->set(http::field::content_type, type);
		res->set(http::field::cache_control, "no-store");
		res->set("X-Content-Type-Options", "nosniff");
		res->keep_alive(req.keep_alive() && status != http::status::forbidden && status != http::status::unauthorized);
		if (req.method() == http::verb::head) res->content_length(body.size());
		else res->body() = std::move(body);
		res->prepare_payload();
		http::async_write(stream_, *res, [self = this->shared_from_this(), res](beast::error_code ec, std::size_t) {
			if (ec || !res->keep_alive()) return self->shutdown();
			self->read();
		});
	}
};

}  // namespace

std::string NetServer::Impl::metrics() {
	std::string m;
	auto metric = [&](const char* name, const char* type, const char* help, const std::string& lines) {
		m += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n" + lines;
	};
	auto one = [](const char* name, double v) {
		char b[160];
		std::snprintf(b, sizeof b, "%s %.6g\n", name, v);
		return std::string(b);
	};
	double load = 0, queuedSeconds = 0;
	int queued = 0;
	for (const auto& [w, s] : live) load += s->load.load(), queued += s->queuedRequests.load(), queuedSeconds += s->queuedSeconds.load();
	const ServeCounters& c = counters;
	metric("talkhead_sessions", "gauge", "Live sessions open.", one("talkhead_sessions", sessions.load()));
	metric("talkhead_sessions_max", "gauge", "The most sessions at once (the max-sessions setting).", one("talkhead_sessions_max", o.maxSessions));
	metric("talkhead_sessions_opened_total", "counter", "Sessions opened.", one("talkhead_sessions_opened_total", double(c.sessionsOpened)));
	std::string refused;
	for (const auto& [reason, v] : {std::pair<const char*, std::int64_t>{"full", c.refusedFull}, {"load", c.refusedLoad}, {"auth", c.refusedAuth},
	                                {"origin", c.refusedOrigin}, {"host", c.refusedHost}, {"shutdown", c.refusedShutdown},
	                                {"unauthenticated", c.refusedUnauthenticated}})
		refused += "talkhead_sessions_refused_total{reason=\"" + std::string(reason) + "\"} " + std::to_string(v) + "\n";
	metric("talkhead_sessions_refused_total", "counter", "Connections refused, by reason.", refused);
	metric("talkhead_unauthenticated_closed_total", "counter", "Connections not yet authenticated closed for newer ones (their budget was full).",
	       one("talkhead_unauthenticated_closed_total", double(c.closedUnauthenticated)));
	metric("talkhead_unauthenticated_connections", "gauge", "Connections not yet authenticated.", one("talkhead_unauthenticated_connections", double(unauthenticated.size())));
	metric("talkhead_sessions_closed_idle_total", "counter", "Sessions closed for idleness (the idle-timeout setting).", one("talkhead_sessions_closed_idle_total", double(c.closedIdle)));
	metric("talkhead_frames_total", "counter", "Frames drawn and sent.", one("talkhead_frames_total", double(c.frames)));
	metric("talkhead_late_frames_total", "counter", "Frames sent more than one frame after their time.", one("talkhead_late_frames_total", double(c.lateFrames)));
	metric("talkhead_session_load_expected_cores", "gauge", "Cores a speaking session takes, as admission counts a session whose own load is not yet known (measured at start-up).",
	       one("talkhead_session_load_expected_cores", host.sessionLoad));
	metric("talkhead_load_cores", "gauge", "Cores the sessions' frames take (drawing and encoding), measured.", one("talkhead_load_cores", load));
	metric("talkhead_queued_requests", "gauge", "say and speak requests queued in all sessions.", one("talkhead_queued_requests", queued));
	metric("talkhead_queued_speech_seconds", "gauge", "Seconds of speech queued in all sessions.", one("talkhead_queued_speech_seconds", queuedSeconds));
	metric("talkhead_requests_total", "counter", "Requests parsed.", one("talkhead_requests_total", double(c.requests)));
	metric("talkhead_request_errors_total", "counter", "Requests answered with an error.", one("talkhead_request_errors_total", double(c.requestErrors)));
	metric("talkhead_accept_errors_total", "counter", "Failed accepts (e.g. out of file descriptors).", one("talkhead_accept_errors_total", double(c.acceptErrors)));
	{
		std::lock_guard<std::mutex> lock(counters.latencyMutex);
		std::string h;
		std::int64_t cumulative = 0;
		char b[160];
		for (std::size_t i = 0; i <= std::size(ServeCounters::kBuckets); ++i) {
			cumulative += counters.latencyCounts[i];
			if (i < std::size(ServeCounters::kBuckets)) std::snprintf(b, sizeof b, "talkhead_utterance_latency_seconds_bucket{le=\"%g\"} %lld\n", ServeCounters::kBuckets[i], static_cast<long long>(cumulative));
			else std::snprintf(b, sizeof b, "talkhead_utterance_latency_seconds_bucket{le=\"+Inf\"} %lld\n", static_cast<long long>(cumulative));
			h += b;
		}
		std::snprintf(b, sizeof b, "talkhead_utterance_latency_seconds_sum %.6f\ntalkhead_utterance_latency_seconds_count %lld\n", counters.latencySum, static_cast<long long>(cumulative));
		h += b;
		metric("talkhead_utterance_latency_seconds", "histogram", "From a say or speak request's arrival to its first frame.", h);
	}
	return m;
}

void NetServer::Impl::accept() {
	acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket socket) {
		if (ec) {
			if (ec == net::error::operation_aborted || !acceptor.is_open()) return;
			// Out of file descriptors, say: wait a little and try again, and log once a second at most.
			++counters.acceptErrors;
			++acceptErrorsSinceLog;
			if (Clock::now() - lastAcceptLog >= std::chrono::seconds(1)) {
				log("accept: " + ec.message() + (acceptErrorsSinceLog > 1 ? " (" + std::to_string(acceptErrorsSinceLog) + " times since the last line)" : ""));
				lastAcceptLog = Clock::now();
				acceptErrorsSinceLog = 0;
			}
			backoff.expires_after(std::chrono::milliseconds(100));
			backoff.async_wait([this](beast::error_code e) {
				if (!e) accept();
			});
			return;
		}
		beast::error_code aec;
		const auto remote = socket.remote_endpoint(aec);
		std::shared_ptr<Unauthenticated> place;
		if (connections < kMaxConnections && !aec) place = admitUnauthenticated(remote.address().to_string());
		if (!place) {
			beast::error_code ignored;
			socket.close(ignored);
		} else if (tls) {
			std::make_shared<HttpSession<TlsStream>>(*this, std::move(socket), *tls)->run(std::move(place));
		} else {
			std::make_shared<HttpSession<PlainStream>>(*this, std::move(socket))->run(std::move(place));
		}
		accept();
	});
}

void NetServer::Impl::beginShutdown() {
	if (shuttingDown) return;
	shuttingDown = true;
	drainEnd = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.drainSeconds));
	char b[160];
	std::snprintf(b, sizeof b, "shutting down: %zu session(s) finish their speech (at most %g s)", live.size(), o.drainSeconds);
	log(b);
	beast::error_code ignored;
	acceptor.close(ignored);
	backoff.cancel();
	for (auto& [w, s] : live)
		if (auto session = w.lock()) session->beginShutdown(drainEnd);
	drainCheck();
}

// Stops the io context once every session has closed, or a little after the drain's end.
// A session that has sent its close frame is done: its client has kCloseGrace to answer it (issue 45: a
// client that never answered kept the server for the whole drain and 2 s more).
void NetServer::Impl::drainCheck() {
	bool any = false, open = false;
	for (auto& [w, s] : live)
		if (auto session = w.lock()) any = true, open |= !session->closeSent();
	const auto now = Clock::now();
	if (open) allClosedAt.reset();
	else if (!allClosedAt) allClosedAt = now;
	if (!any || (allClosedAt && now - *allClosedAt >= kCloseGrace) || now > drainEnd + std::chrono::seconds(2)) {
		ioc.stop();
		return;
	}
	drainTimer.expires_after(std::chrono::milliseconds(100));
	drainTimer.async_wait([this](beast::error_code e) {
		if (!e) drainCheck();
	});
}

NetServer::NetServer(const ServeHost& host, const Face& face, ServeOptions options) : impl_(std::make_unique<Impl>(host, face, std::move(options))) {
	Impl& s = *impl_;  // the options' own checks are the facade's (server_plugin.cpp), before the model's
	s.policy.listenHost = s.o.host;
	s.policy.allowOrigins = s.o.allowOrigins;
	s.policy.allowHosts = s.o.allowHosts;
	s.policy.token = s.o.token;
	if (s.o.demo) {
		std::ifstream f(s.o.demoPage, std::ios::binary);
		if (!f) throw Error(s.o.demoPage, 0, "cannot read the demo page");
		std::ostringstream b;
		b << f.rdbuf();
		s.demoPage = b.str();
	}
	if (!s.o.tlsCert.empty()) {
		s.tls.emplace(ssl::context::tls_server);
		s.tls->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1);
		beast::error_code ec;
		s.tls->use_certificate_chain_file(s.o.tlsCert, ec);
		if (ec) throw Error(s.o.tlsCert, 0, "not a PEM certificate (chain): " + ec.message());
		s.tls->use_private_key_file(s.o.tlsKey, ssl::context::pem, ec);
		if (ec) throw Error(s.o.tlsKey, 0, "not a PEM private key: " + ec.message());
		if (SSL_CTX_check_private_key(s.tls->native_handle()) != 1) throw Error(s.o.tlsKey, 0, "the key does not match the certificate " + s.o.tlsCert);
	}
	beast::error_code ec;
	const auto address = net::ip::make_address(s.o.host, ec);
	if (ec) throw Error("{{listen}}: '" + safeQuote(s.o.host) + "' is not an IP address");
	const tcp::endpoint ep{address, static_cast<unsigned short>(s.o.port)};
	s.acceptor.open(ep.protocol(), ec);
	if (!ec) s.acceptor.set_option(net::socket_base::reuse_address(true), ec);
	if (!ec) s.acceptor.bind(ep, ec);
	if (!ec) s.acceptor.listen(net::socket_base::max_listen_connections, ec);
	if (ec) throw Error("cannot listen on " + s.o.host + ":" + std::to_string(s.o.port) + ": " + ec.message());
	if (s.o.maxLoad > 0 && s.host.sessionLoad > 0) {
		const double cores = machineCores();
		char b[240];
		std::snprintf(b, sizeof b, "a speaking session at %dx%d takes %.2f cores (measured at start-up): about %d at once within {{max-load}} %g of %g cores",
		              s.o.live.render.synth.width, s.o.live.render.synth.height, s.host.sessionLoad,
		              int(std::floor(s.o.maxLoad * cores / (s.host.sessionLoad * kOverhead))), s.o.maxLoad, cores);
		s.log(b);
	}
}

NetServer::~NetServer() = default;

int NetServer::port() const { return impl_->acceptor.local_endpoint().port(); }

void NetServer::run() {
	Impl& s = *impl_;
	if (s.o.handleSignals) {
		s.signals.emplace(s.ioc, SIGTERM, SIGINT);
		s.signals->async_wait([&s](beast::error_code ec, int) {
			if (ec) return;
			s.beginShutdown();
			s.signals->async_wait([&s](beast::error_code e, int) {  // a second one: at once
				if (e) return;
				s.log("a second signal: stopping now");
				s.ioc.stop();
			});
		});
	}
	s.accept();
	if (s.o.maxLoad > 0) s.loadTick();
	s.ioc.run();
	// Every session's threads end before the io context goes (their callbacks post to it).
	for (auto& [w, st] : s.live)
		if (auto session = w.lock()) session->dropWorker();
	s.stopReaper();
	if (s.signals) {
		beast::error_code ignored;
		s.signals->cancel(ignored);
	}
}

void NetServer::stop() {
	net::post(impl_->ioc, [this] {
		beast::error_code ignored;
		impl_->acceptor.close(ignored);
		impl_->ioc.stop();
	});
}

void NetServer::shutdown() {
	net::post(impl_->ioc, [this] { impl_->beginShutdown(); });
}

namespace {

// The plugin's entry points: no exception crosses the boundary (guarded), errors come back as their message.
void* createServer(const ServeHost& host, const Face& face, const ServeOptions& options, std::string& error) {
	NetServer* server = nullptr;
	guarded(error, [&] { server = new NetServer(host, face, options); });
	return server;
}
int serverPort(void* server) { return static_cast<NetServer*>(server)->port(); }
bool runServer(void* server, std::string& error) {
	return guarded(error, [&] { static_cast<NetServer*>(server)->run(); });
}
void stopServer(void* server) { static_cast<NetServer*>(server)->stop(); }
void shutdownServer(void* server) { static_cast<NetServer*>(server)->shutdown(); }
void destroyServer(void* server) { delete static_cast<NetServer*>(server); }

const ServeModule kModule = {kServeModuleAbi, createServer, serverPort, runServer, stopServer, shutdownServer, destroyServer};

}  // namespace

}  // namespace talkhead

extern "C" const void* talkhead_serve_module() { return &talkhead::kModule; }
