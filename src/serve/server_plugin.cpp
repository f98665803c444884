// SPDX-License-Identifier: GPL-3.0-or-later
// The Server facade: forwards to the network plugin (libtalkhead-serve.so, serve_module.h), loaded once.
#include "base/error.h"
#include "base/plugin.h"
#include "media/video_writer.h"
#include "perform/plan.h"
#include "render/live.h"
#include "serve/serve_module.h"
#include "serve/server.h"
#include "serve/worker.h"

namespace talkhead {

namespace {

const ServeModule& serveModule() {
	static const auto* m = static_cast<const ServeModule*>(loadPlugin("libtalkhead-serve.so", "talkhead_serve_module", kServeModuleAbi));
	return *m;
}

std::unique_ptr<SessionWorker> makeWorker(const Face& face, const ServeOptions& options, int id, SessionWorker::Send send, SessionWorker::Close close,
                                          std::shared_ptr<SessionStats> stats, ServeCounters& counters) {
	return std::make_unique<LiveWorker>(face, options, id, std::move(send), std::move(close), std::move(stats), counters);
}


}  // namespace

Server::Server(const Face& face, ServeOptions options) : module_(&serveModule()) {
	if (options.maxSessions < 1) throw Error("{{max-sessions}} must be at least 1");
	if (options.tlsCert.empty() != options.tlsKey.empty()) throw Error("{{tls-cert}} and {{tls-key}} go together");
	// A session's options (emotion, size, sample rate) and the model checked before anyone connects, and
	// what a session reads of the model in the page cache.
	LiveSession(face, options.live);
	// The encoder's plugin loaded now: loaded later, it could meet a process out of file descriptors, and
	// one of libav's libraries (libgcrypt, through libssh) aborts the process in its initialiser then.
	loadVideoPlugin();
	// A speak with no timing recognises its phones (issue 49): the recogniser's plugin and model loaded now,
	// not in the first such request (~1 s). Without them that request gets the error; the server runs.
	try {
		prepareSpeechRecognition();
	} catch (const Error&) {
	}
	ServeHost host{makeWorker, lateRecently};
	if (options.maxLoad > 0) host.sessionLoad = measureSessionLoad(face, options);
	std::string error;
	server_ = module_->create(host, face, options, error);
	if (!server_) throw Error(error);
}

Server::~Server() { module_->destroy(server_); }

int Server::port() const { return module_->port(server_); }

void Server::run() {
	std::string error;
	if (!module_->run(server_, error)) throw Error(error);
}

void Server::stop() { module_->stop(server_); }

void Server::shutdown() { module_->shutdown(server_); }

}  // namespace talkhead
