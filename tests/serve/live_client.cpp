// SPDX-License-Identifier: GPL-3.0-or-later
// A scripted WebSocket client of talkhead serve for the tests and the latency bench (Boost.Beast):
//   live_client PORT OUT_PREFIX SECONDS [AT_MS:JSON | AT_MS:@FILE]…
// connects to ws://127.0.0.1:PORT/live, sends each JSON text message AT_MS milliseconds after the hello
// (from FILE with @), and after SECONDS closes. Writes OUT_PREFIX.mp4 (every binary message, in order)
// and OUT_PREFIX.events (one line per text message: milliseconds since the hello, a tab, the message).
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <chrono>
#include <algorithm>
#include <deque>
#include <memory>
#include <functional>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
	if (argc < 4) {
		std::cerr << "usage: live_client PORT OUT_PREFIX SECONDS [AT_MS:JSON | AT_MS:@FILE]...\n";
		return 2;
	}
	const std::string port = argv[1], prefix = argv[2];
	const double seconds = std::stod(argv[3]);
	struct Send {
		long at;
		std::string text;
	};
	std::vector<Send> sends;
	for (int i = 4; i < argc; ++i) {
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
	try {
		net::io_context ioc;
		tcp::resolver resolver(ioc);
		websocket::stream<tcp::socket> ws(ioc);
		net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", port));
		ws.handshake("127.0.0.1:" + port, "/live");
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
					if (ec != websocket::error::closed && ec != net::error::operation_aborted) std::cerr << "live_client: read: " << ec.message() << "\n";
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
	} catch (const std::exception& e) {
		std::cerr << "live_client: " << e.what() << "\n";
		return 1;
	}
	return 0;
}
