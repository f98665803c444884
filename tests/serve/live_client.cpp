// SPDX-License-Identifier: GPL-3.0-or-later
// A scripted WebSocket client of talkhead serve for the tests and the latency bench (Boost.Beast):
//   live_client [--tls] [--host HOST] [--header 'Name: value']… [--auth-first TOKEN] [--connect-at UNIX_MS] PORT OUT_PREFIX SECONDS
//               [AT_MS:JSON | AT_MS:@FILE]…
// connects to ws://127.0.0.1:PORT/live (wss:// with --tls, any certificate), sends each JSON text message
// AT_MS milliseconds after the hello (from FILE with @), and after SECONDS closes. Writes OUT_PREFIX.mp4
// (every binary message, in order) and OUT_PREFIX.events (one line per text message: milliseconds since
// the hello, a tab, the message; the close code as "close\tCODE"). --auth-first sends
// {"type": "auth", "token": TOKEN} before anything (the hello comes after it). A refused upgrade exits 3
// with "live_client: handshake: STATUS" on stderr. --connect-at waits until that wall-clock time (ms since
// the epoch) before connecting: clients started one after another then connect at the same moment.
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include <chrono>
#include <algorithm>
#include <deque>
#include <memory>
#include <functional>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

struct Send {
	long at;
	std::string text;
};
struct Options {
	bool tls = false;
	std::string host, authFirst;
	long long connectAt = 0;
	std::vector<std::pair<std::string, std::string>> headers;
};

template <class Ws>
int session(Ws& ws, net::io_context& ioc, const std::string& port, const std::string& prefix, double seconds, std::vector<Send>& sends, const Options& opt);

int main(int argc, char** argv) {
	Options opt;
	int a = 1;
	for (; a < argc && std::string(argv[a]).rfind("--", 0) == 0; ++a) {
		const std::string f = argv[a];
		if (f == "--tls") opt.tls = true;
		else if (f == "--host" && a + 1 < argc) opt.host = argv[++a];
		else if (f == "--auth-first" && a + 1 < argc) opt.authFirst = argv[++a];
		else if (f == "--connect-at" && a + 1 < argc) opt.connectAt = std::stoll(argv[++a]);
		else if (f == "--header" && a + 1 < argc) {
			const std::string h = argv[++a];
			const auto colon = h.find(':');
			opt.headers.emplace_back(h.substr(0, colon), h.substr(colon + 1 + (h.size() > colon + 1 && h[colon + 1] == ' ')));
		} else {
			std::cerr << "live_client: unknown flag " << f << "\n";
			return 2;
		}
	}
	if (argc - a < 3) {
		std::cerr << "usage: live_client [--tls] [--host H] [--header 'N: V']... [--auth-first TOKEN] PORT OUT_PREFIX SECONDS [AT_MS:JSON | AT_MS:@FILE]...\n";
		return 2;
	}
	const std::string port = argv[a], prefix = argv[a + 1];
	const double seconds = std::stod(argv[a + 2]);
	std::vector<Send> sends;
	for (int i = a + 3; i < argc; ++i) {
		const std::string a = argv[i];
		const auto colon = a.find(':');
		Send s{std::stol(a.substr(0, colon)), a.substr(colon + 1)};
		if (!s.text.empty() && s.text[0] == '@') {
			std::ifstream f(s.text.substr(1), std::ios::binary);
			std::stringstream b;
			b << f.rdbuf();
			s.text = b.str();
		}
		sends.push_back(std::move(s));
	}
	std::stable_sort(sends.begin(), sends.end(), [](const Send& a, const Send& b) { return a.at < b.at; });
	if (opt.connectAt > 0)
		std::this_thread::sleep_until(std::chrono::system_clock::time_point(std::chrono::milliseconds(opt.connectAt)));
	try {
		net::io_context ioc;
		tcp::resolver resolver(ioc);
		if (opt.tls) {
			net::ssl::context ctx(net::ssl::context::tls_client);
			ctx.set_verify_mode(net::ssl::verify_none);
			websocket::stream<beast::ssl_stream<tcp::socket>> ws(ioc, ctx);
			net::connect(beast::get_lowest_layer(ws), resolver.resolve("127.0.0.1", port));
			ws.next_layer().handshake(net::ssl::stream_base::client);
			return session(ws, ioc, port, prefix, seconds, sends, opt);
		}
		websocket::stream<tcp::socket> ws(ioc);
		net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", port));
		return session(ws, ioc, port, prefix, seconds, sends, opt);
	} catch (const std::exception& e) {
		std::cerr << "live_client: " << e.what() << "\n";
		return 1;
	}
}

template <class Ws>
int session(Ws& ws, net::io_context& ioc, const std::string& port, const std::string& prefix, double seconds, std::vector<Send>& sends, const Options& opt) {
	{
		ws.set_option(websocket::stream_base::decorator([&opt](websocket::request_type& req) {
			for (const auto& [k, v] : opt.headers) req.set(k, v);
		}));
		websocket::response_type res;
		beast::error_code hec;
		ws.handshake(res, opt.host.empty() ? "127.0.0.1:" + port : opt.host, "/live", hec);
		if (hec) {
			std::cerr << "live_client: handshake: " << hec.message() << " (HTTP " << res.result_int() << ")\n";
			return 3;
		}
		if (!opt.authFirst.empty()) ws.write(net::buffer("{\"type\": \"auth\", \"token\": \"" + opt.authFirst + "\"}"));
		std::ofstream video(prefix + ".mp4", std::ios::binary), events(prefix + ".events");
		beast::flat_buffer buffer;
		Clock::time_point hello{};
		bool started = false;
		std::size_t next = 0;
		std::vector<std::shared_ptr<net::steady_timer>> timers;
		std::deque<const std::string*> queue;  // one write at a time
		std::function<void()> write = [&] {
			ws.text(true);
			ws.async_write(net::buffer(*queue.front()), [&](beast::error_code ec, std::size_t) {
				if (ec) return;
				queue.pop_front();
				if (!queue.empty()) write();
			});
		};
		net::steady_timer end(ioc);
		std::function<void()> read = [&] {
			ws.async_read(buffer, [&](beast::error_code ec, std::size_t) {
				if (ec) {
					if (ec == websocket::error::closed) events << "close\t" << ws.reason().code << "\n";
					else if (ec != net::error::operation_aborted) std::cerr << "live_client: read: " << ec.message() << "\n";
					end.cancel();
					for (auto& t : timers) t->cancel();
					return;
				}
				const auto now = Clock::now();
				const std::string data = beast::buffers_to_string(buffer.data());
				buffer.consume(buffer.size());
				if (ws.got_text()) {
					if (!started) {
						started = true;
						hello = now;
						// One timer at a time, in the order given (messages due at the same time keep their order).
						auto timer = std::make_shared<net::steady_timer>(ioc);
						auto schedule = std::make_shared<std::function<void()>>();
						*schedule = [&, timer, schedule] {
							if (next >= sends.size()) return;
							timer->expires_at(hello + std::chrono::milliseconds(sends[next].at));
							timer->async_wait([&, timer, schedule](beast::error_code e) {
								if (e) return;
								const long due = sends[next].at;
								for (; next < sends.size() && sends[next].at == due; ++next) {
									const std::string* text = &sends[next].text;
									const double ms = std::chrono::duration<double, std::milli>(Clock::now() - hello).count();
									events << ms << "\t>" << (text->size() > 300 ? text->substr(0, 300) + "…" : *text) << "\n";
									queue.push_back(text);
									if (queue.size() == 1) write();
								}
								(*schedule)();
							});
						};
						timers.push_back(timer);
						(*schedule)();
						end.expires_at(hello + std::chrono::milliseconds(long(seconds * 1000)));
						end.async_wait([&](beast::error_code e) {
							if (e) return;
							ws.async_close(websocket::close_code::normal, [](beast::error_code) {});
						});
					}
					const double ms = started ? std::chrono::duration<double, std::milli>(now - hello).count() : 0;
					events << ms << "\t" << data << "\n";
				} else {
					video.write(data.data(), std::streamsize(data.size()));
				}
				read();
			});
		};
		read();
		ioc.run();
	}
	return 0;
}
