// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead serve: HTTP + WebSocket with Boost.Beast (D54). One io thread runs the network; each session
// has a frame thread (LiveSession paced in real time, x264/AAC fragmented MP4) and a speech thread
// (espeak-ng, audio decoding), so a long synthesis never holds up frames.
#include "serve/server.h"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "phonetics/labels.h"
#include "media/video_writer.h"

namespace talkhead {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::size_t kMaxQueuedBytes = 64u << 20;  // a client this far behind is dropped

std::string errorJson(const std::string& message, const std::string& id = "") {
	std::string j = "{\"type\": \"error\", \"message\": " + jsonQuote(safeLine(message));
	if (!id.empty()) j += ", \"id\": " + jsonQuote(id);
	return j + "}";
}


}  // namespace

// One session's rendering: the frame thread and the speech thread. Output goes through `send` (binary or
// text, in order) from the frame thread; `request` is called from the io thread.
class LiveWorker {
public:
	using Send = std::function<bool(bool binary, std::string data)>;  // false: the client is gone or too slow
	LiveWorker(const FaceModel& model, const ServeOptions& o, int id, Send send, std::function<void()> close)
	    : model_(model), o_(o), id_(id), send_(std::move(send)), close_(std::move(close)) {
		if (o_.recordDir) {
			record_.open(*o_.recordDir + "/session-" + std::to_string(id_) + ".jsonl");
			if (!record_) throw Error(*o_.recordDir, 0, "cannot write the session record");
		}
		frames_ = std::thread([this] { frameLoop(); });
		speech_ = std::thread([this] { speechLoop(); });
	}
	~LiveWorker() {
		{
			std::lock_guard<std::mutex> lock(m_);
			quit_ = true;
		}
		cv_.notify_all();
		speechCv_.notify_all();
		if (speech_.joinable()) speech_.join();  // first: it may be warming the frame thread's session
		if (frames_.joinable()) frames_.join();
		if (record_) record_ << "{\"type\": \"end\", \"frame\": " << drawn_ << "}\n";
		if (o_.log && drawn_ > 0) {
			char b[200];
			std::snprintf(b, sizeof b, "session %d: %lld frames, %.1f ms each to draw and encode, %lld late by more than a frame (latest %.0f ms after its time)", id_,
			              static_cast<long long>(drawn_), 1000 * stats_.work / double(drawn_), static_cast<long long>(stats_.late), 1000 * std::max(0.0, stats_.worst));
			o_.log(b);
		}
	}

	// A request's text (from the io thread): parsed here, errors answered at once.
	void request(const std::string& json) {
		const auto received = Clock::now();
		LiveRequest r;
		try {
			r = parseLiveRequest(json);
		} catch (const std::exception& e) {
			send_(false, errorJson(describeException(e)));
			return;
		}
		std::lock_guard<std::mutex> lock(m_);
		if (r.kind == LiveRequest::Kind::Stop) {
			// Barge-in: what is waiting for synthesis goes, and the stop overtakes everything queued.
			++generation_;
			speechQueue_.clear();
			frameQueue_.push_back(Command{r, std::nullopt, json, generation_, received});
			cv_.notify_all();
			return;
		}
		speechQueue_.push_back(Command{r, std::nullopt, json, generation_, received});
		speechCv_.notify_all();
	}

private:
	struct Command {
		LiveRequest request;
		std::optional<Utterance> utterance;
		std::string json;
		std::uint64_t generation = 0;
		Clock::time_point received;
	};
	const FaceModel& model_;
	const ServeOptions& o_;
	int id_;
	Send send_;
	std::function<void()> close_;
	std::mutex m_;
	std::condition_variable cv_, speechCv_;
	bool quit_ = false;
	std::uint64_t generation_ = 0;
	std::deque<Command> speechQueue_, frameQueue_;
	std::thread frames_, speech_;
	std::ofstream record_;
	std::int64_t drawn_ = 0;  // frames drawn and encoded (the record's end)
	std::atomic<LiveSession*> session_{nullptr};  // the frame thread's, while it lives
	std::mutex warmMutex_;                         // held while the speech thread warms it
	std::string emotion_;                          // the session's emotion and intensity (under m_)
	double intensity_ = 1;
	struct {
		double work = 0, worst = 0;  // seconds drawing + encoding; the latest a frame went out after its time
		std::int64_t late = 0;       // frames out more than a frame after their time
	} stats_;
	std::map<std::string, Clock::time_point> requestTimes_;  // utterance id → when its request came

	void speechLoop() {
		for (;;) {
			Command c;
			{
				std::unique_lock<std::mutex> lock(m_);
				speechCv_.wait(lock, [&] { return quit_ || !speechQueue_.empty(); });
				if (quit_) return;
				c = std::move(speechQueue_.front());
				speechQueue_.pop_front();
			}
			if (c.request.kind == LiveRequest::Kind::Say || c.request.kind == LiveRequest::Kind::Speak) {
				try {
					c.utterance = prepareUtterance(c.request, o_.lang, o_.live.sampleRate);
					// Its keypose images made here, not in the frame thread (a frame would be late).
					std::string emotion;
					double intensity = 1;
					{
						std::lock_guard<std::mutex> lock(m_);
						emotion = c.request.emotion ? *c.request.emotion : emotion_;
						intensity = c.request.emotion ? c.request.intensity : intensity_;
					}
					std::lock_guard<std::mutex> warming(warmMutex_);
					if (LiveSession* s = session_.load()) s->warm(*c.utterance, emotion, intensity);
					for (const auto& w : c.utterance->warnings)
						send_(false, "{\"type\": \"warning\", \"message\": " + jsonQuote(safeLine(w)) + (c.request.id.empty() ? "" : ", \"id\": " + jsonQuote(c.request.id)) + "}");
				} catch (const std::exception& e) {
					send_(false, errorJson(describeException(e), c.request.id));
					continue;
				}
			}
			std::lock_guard<std::mutex> lock(m_);
			if (c.generation != generation_) continue;  // a stop came meanwhile
			frameQueue_.push_back(std::move(c));
			cv_.notify_all();
		}
	}

	void frameLoop() {
		try {
			std::unique_ptr<LiveSession> session = std::make_unique<LiveSession>(model_, o_.live);
			session_ = session.get();
			{
				std::lock_guard<std::mutex> lock(m_);
				emotion_ = session->emotion();
				intensity_ = session->intensity();
			}
			struct Forget {  // before the session goes, and never while the speech thread warms it
				std::atomic<LiveSession*>& p;
				std::mutex& m;
				~Forget() {
					std::lock_guard<std::mutex> lock(m);
					p = nullptr;
				}
			} forget{session_, warmMutex_};
			const StreamInfo& info = session->info();
			std::string bytes;  // what the encoder made since the last send
			VideoOptions vo;
			vo.width = info.width, vo.height = info.height, vo.rate = info.rate, vo.crf = o_.crf, vo.preset = o_.preset, vo.threads = o_.encoderThreads;
			Mp4LiveWriter writer([&bytes](const std::uint8_t* d, std::size_t n) { bytes.append(reinterpret_cast<const char*>(d), n); return true; }, vo,
			                     &session->audio());
			std::string emotions;
			for (const auto& e : emotionLabels()) emotions += (emotions.empty() ? "" : ", ") + jsonQuote(e.label);
			char head[256];
			std::snprintf(head, sizeof head, "{\"type\": \"hello\", \"session\": %d, \"width\": %d, \"height\": %d, \"fps\": %.6g, \"rate\": \"%s\", \"sample_rate\": %d",
			              id_, info.width, info.height, info.rate.fps(), info.rate.str().c_str(), session->sampleRate());
			const std::string hello = std::string(head) + ", \"mime\": " + jsonQuote("video/mp4; codecs=\"" + writer.codecs() + "\"") +
			                          ", \"emotion\": " + jsonQuote(session->emotion()) + ", \"emotions\": [" + emotions + "]}";
			if (record_) record_ << "{\"type\": \"session\", \"width\": " << info.width << ", \"height\": " << info.height << ", \"rate\": \"" << info.rate.str()
			                     << "\", \"emotion\": " << jsonQuote(session->emotion()) << ", \"lang\": " << jsonQuote(o_.lang) << "}\n";
			if (!send_(false, hello) || !send_(true, std::move(bytes))) return;
			bytes.clear();
			YuvImage frame;
			Points points;
			std::vector<LiveEvent> events;
			const Clock::time_point start = Clock::now();
			const double frameSeconds = 1.0 / info.rate.fps();
			for (std::int64_t n = 0;; ++n) {
				std::deque<Command> todo;
				{
					std::unique_lock<std::mutex> lock(m_);
					const auto due = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(double(n) * frameSeconds));
					cv_.wait_until(lock, due, [&] { return quit_; });
					if (quit_) break;
					todo.swap(frameQueue_);
				}
				for (Command& c : todo) {
					try {
						if (c.utterance && c.request.kind != LiveRequest::Kind::Stop) requestTimes_[c.request.id] = c.received;
						applyLiveRequest(*session, c.request, std::move(c.utterance));
						{
							std::lock_guard<std::mutex> lock(m_);
							emotion_ = session->emotion();
							intensity_ = session->intensity();
						}
						if (record_) record_ << "{\"frame\": " << n << ", \"request\": " << c.json << "}\n";
					} catch (const std::exception& e) {
						send_(false, errorJson(describeException(e), c.request.id));
					}
				}
				events.clear();
				const auto due = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(double(n) * frameSeconds));
				const auto t0 = Clock::now();
				session->drawNext(frame, points, events);
				writer.write(frame);
				drawn_ = session->nextFrame();
				const auto sent = Clock::now();
				// Pace: a frame out later than one frame after its time is late (the stream falls behind).
				const double late = std::chrono::duration<double>(sent - due).count();
				stats_.work += std::chrono::duration<double>(sent - t0).count();
				stats_.worst = std::max(stats_.worst, late);
				if (late > frameSeconds) ++stats_.late;
				for (const LiveEvent& e : events) {
					std::string j = liveEventJson(e);
					if (e.kind == LiveEvent::Kind::UtteranceStarted) {
						auto it = requestTimes_.find(e.id);
						if (it != requestTimes_.end()) {
							char b[64];
							std::snprintf(b, sizeof b, ", \"latency_ms\": %.1f}", std::chrono::duration<double, std::milli>(sent - it->second).count());
							j.pop_back();
							j += b;
							requestTimes_.erase(it);
						}
					}
					if (!send_(false, std::move(j))) return;
				}
				if (!bytes.empty()) {
					if (!send_(true, std::move(bytes))) return;
					bytes.clear();
				}
			}
		} catch (const std::exception& e) {
			send_(false, errorJson(describeException(e)));
			if (o_.log) o_.log("session " + std::to_string(id_) + ": " + describeException(e));
			close_();
		}
	}
};

namespace {

class WsSession;

}  // namespace

struct Server::Impl {
	const FaceModel& model;
	ServeOptions o;
	net::io_context ioc{1};
	tcp::acceptor acceptor{ioc};
	std::atomic<int> sessions{0};
	std::atomic<int> nextId{1};
	std::string demoPage;
	Impl(const FaceModel& m, ServeOptions opts) : model(m), o(std::move(opts)) {}
	void log(const std::string& s) const {
		if (o.log) o.log(s);
	}
	void accept();
};

namespace {

class WsSession : public std::enable_shared_from_this<WsSession> {
public:
	WsSession(tcp::socket&& socket, Server::Impl& server) : ws_(std::move(socket)), server_(server) {}
	~WsSession() {
		worker_.reset();
		if (counted_) --server_.sessions;
	}

	void run(http::request<http::string_body> req) {
		ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
		ws_.read_message_max(0);  // messages are read in parts and bounded here (an oversized one is an error, not a drop)
		ws_.async_accept(req, beast::bind_front_handler(&WsSession::onAccept, shared_from_this()));
	}

private:
	websocket::stream<beast::tcp_stream> ws_;
	Server::Impl& server_;
	beast::flat_buffer buffer_;
	std::string message_;
	bool oversize_ = false, counted_ = false, closing_ = false;
	std::deque<std::pair<bool, std::string>> out_;
	bool writing_ = false;
	std::atomic<std::size_t> queued_{0};
	std::atomic<bool> gone_{false};
	std::unique_ptr<LiveWorker> worker_;
	int id_ = 0;

	void onAccept(beast::error_code ec) {
		if (ec) return;
		if (++server_.sessions > server_.o.maxSessions) {
			--server_.sessions;
			push(false, errorJson("the server has " + std::to_string(server_.o.maxSessions) + " sessions already (--max-sessions)"));
			closing_ = true;
			return;
		}
		counted_ = true;
		id_ = server_.nextId++;
		server_.log("session " + std::to_string(id_) + " opened");
		std::weak_ptr<WsSession> weak = shared_from_this();
		auto executor = ws_.get_executor();
		worker_ = std::make_unique<LiveWorker>(
		    server_.model, server_.o, id_,
		    [weak, executor](bool binary, std::string data) {
			    auto self = weak.lock();
			    if (!self || self->gone_) return false;
			    if (self->queued_ + data.size() > kMaxQueuedBytes) {
				    self->gone_ = true;
				    net::post(executor, [self] {
					    self->push(false, errorJson("the client reads too slowly: the session is closed"));
					    self->closing_ = true;
				    });
				    return false;
			    }
			    self->queued_ += data.size();
			    net::post(executor, [self, binary, d = std::move(data)]() mutable { self->push(binary, std::move(d)); });
			    return true;
		    },
		    [weak, executor] {
			    if (auto self = weak.lock())
				    net::post(executor, [self] {
					    self->closing_ = true;
					    if (!self->writing_) self->close();
				    });
		    });
		read();
	}

	void read() {
		ws_.async_read_some(buffer_, 1 << 16, beast::bind_front_handler(&WsSession::onRead, shared_from_this()));
	}

	void onRead(beast::error_code ec, std::size_t) {
		if (ec) {  // closed or broken: the session ends (the worker stops with this object)
			gone_ = true;
			if (counted_) server_.log("session " + std::to_string(id_) + " closed");
			worker_.reset();
			return;
		}
		const std::size_t n = buffer_.size();
		if (!oversize_ && message_.size() + n <= server_.o.maxMessage) {
			const auto data = buffer_.data();
			message_.append(static_cast<const char*>(data.data()), data.size());
		} else {
			oversize_ = true;
			message_.clear();
		}
		buffer_.consume(n);
		if (ws_.is_message_done()) {
			if (oversize_) {
				push(false, errorJson("the request is larger than " + std::to_string(server_.o.maxMessage >> 20) + " MiB"));
			} else if (!ws_.got_text()) {
				push(false, errorJson("binary messages are not requests: send JSON text (audio goes base64 in a speak request)"));
			} else if (worker_) {
				worker_->request(message_);
			}
			message_.clear();
			oversize_ = false;
		}
		read();
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
		ws_.async_write(net::buffer(out_.front().second), beast::bind_front_handler(&WsSession::onWrite, shared_from_this()));
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

	void close() {
		ws_.async_close(websocket::close_code::normal, [self = shared_from_this()](beast::error_code) {});
	}
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
public:
	HttpSession(tcp::socket&& socket, Server::Impl& server) : stream_(std::move(socket)), server_(server) {}
	void run() { net::dispatch(stream_.get_executor(), beast::bind_front_handler(&HttpSession::read, shared_from_this())); }

private:
	beast::tcp_stream stream_;
	beast::flat_buffer buffer_;
	Server::Impl& server_;
	std::optional<http::request_parser<http::string_body>> parser_;

	void read() {
		parser_.emplace();
		parser_->body_limit(1 << 16);
		stream_.expires_after(std::chrono::seconds(30));
		http::async_read(stream_, buffer_, *parser_, beast::bind_front_handler(&HttpSession::onRead, shared_from_this()));
	}

	void onRead(beast::error_code ec, std::size_t) {
		if (ec) {
			beast::error_code ignored;
			stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
			return;
		}
		http::request<http::string_body> req = parser_->release();
		const std::string target(req.target());
		if (websocket::is_upgrade(req)) {
			if (target == "/live") {
				stream_.expires_never();
				std::make_shared<WsSession>(stream_.release_socket(), server_)->run(std::move(req));
				return;
			}
			return reply(req, http::status::not_found, "text/plain", "talkhead serve: WebSocket sessions are at /live\n");
		}
		if (req.method() != http::verb::get && req.method() != http::verb::head)
			return reply(req, http::status::method_not_allowed, "text/plain", "talkhead serve: GET only; requests go over the WebSocket at /live\n");
		if (target == "/" || target == "/index.html") {
			if (server_.demoPage.empty()) return reply(req, http::status::not_found, "text/plain", "talkhead serve: the demo page is off (--demo)\n");
			return reply(req, http::status::ok, "text/html; charset=utf-8", server_.demoPage);
		}
		if (target == "/health") {
			const std::string j = "{\"sessions\": " + std::to_string(server_.sessions.load()) + ", \"max_sessions\": " + std::to_string(server_.o.maxSessions) + "}\n";
			return reply(req, http::status::ok, "application/json", j);
		}
		reply(req, http::status::not_found, "text/plain", "talkhead serve: not found\n");
	}

	void reply(const http::request<http::string_body>& req, http::status status, const char* type, std::string body) {
		auto res = std::make_shared<http::response<http::string_body>>(status, req.version());
		res->set(http::field::server, "talkhead");
		res->set(http::field::content_type, type);
		res->set(http::field::cache_control, "no-store");
		res->keep_alive(req.keep_alive());
		if (req.method() == http::verb::head) res->content_length(body.size());
		else res->body() = std::move(body);
		res->prepare_payload();
		http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
			if (ec || !res->keep_alive()) {
				beast::error_code ignored;
				self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
				return;
			}
			self->read();
		});
	}
};

}  // namespace

void Server::Impl::accept() {
	acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket socket) {
		if (ec) {
			if (ec != net::error::operation_aborted) log("accept: " + ec.message());
			if (!acceptor.is_open()) return;
		} else {
			std::make_shared<HttpSession>(std::move(socket), *this)->run();
		}
		accept();
	});
}

Server::Server(const FaceModel& model, ServeOptions options) : impl_(std::make_unique<Impl>(model, std::move(options))) {
	Impl& s = *impl_;
	if (s.o.maxSessions < 1) throw Error("--max-sessions must be at least 1");
	// A session's options (emotion, size, sample rate) and the model checked before anyone connects, and
	// what a session reads of the model in the page cache.
	LiveSession(model, s.o.live);
	if (s.o.demo) {
		std::ifstream f(s.o.demoPage, std::ios::binary);
		if (!f) throw Error(s.o.demoPage, 0, "cannot read the demo page");
		std::ostringstream b;
		b << f.rdbuf();
		s.demoPage = b.str();
	}
	beast::error_code ec;
	const auto address = net::ip::make_address(s.o.host, ec);
	if (ec) throw Error("--listen: '" + safeQuote(s.o.host) + "' is not an IP address");
	const tcp::endpoint ep{address, static_cast<unsigned short>(s.o.port)};
	s.acceptor.open(ep.protocol(), ec);
	if (!ec) s.acceptor.set_option(net::socket_base::reuse_address(true), ec);
	if (!ec) s.acceptor.bind(ep, ec);
	if (!ec) s.acceptor.listen(net::socket_base::max_listen_connections, ec);
	if (ec) throw Error("cannot listen on " + s.o.host + ":" + std::to_string(s.o.port) + ": " + ec.message());
}

Server::~Server() = default;

int Server::port() const { return impl_->acceptor.local_endpoint().port(); }

void Server::run() {
	impl_->accept();
	impl_->ioc.run();
}

void Server::stop() {
	net::post(impl_->ioc, [this] {
		beast::error_code ignored;
		impl_->acceptor.close(ignored);
		impl_->ioc.stop();
	});
}

}  // namespace talkhead
