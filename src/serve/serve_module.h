// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The network side of `talkhead serve` (server.cpp: Boost.Beast, Asio and their SSL layer) is the plugin
// libtalkhead-serve.so (D68): its templates are the costliest translation unit of the tree (~40–110 s of one
// core), which a first run (scripts/demo) and every command but serve do without. Built from the same tree
// with the same compiler, so C++ types cross the boundary; errors come back as their message.
#include <memory>
#include <string>

#include "synth/face.h"
#include "serve/server.h"
#include "serve/worker.h"

namespace talkhead {

constexpr int kServeModuleAbi = 2;

// What the plugin uses of the serve module, given by the Server facade: the plugin links only the base
// module (errors, JSON, text) and the access rules, no second copy of the library (checked by
// layout.plugins).
struct ServeHost {
	std::unique_ptr<SessionWorker> (*makeWorker)(const Face& face, const ServeOptions& options, int id, SessionWorker::Send send,
	                                             SessionWorker::Close close, std::shared_ptr<SessionStats> stats, ServeCounters& counters);
	bool (*lateRecently)(const SessionStats& stats);
	double sessionLoad = 0;  // cores one speaking session takes (measureSessionLoad; 0: not measured, --max-load 0)
};

struct ServeModule {
	int abi;  // kServeModuleAbi
	// A listening server (opaque), or nullptr with `error` set. The facade has checked the session's
	// options against the model and loaded the encoder's plugin.
	void* (*create)(const ServeHost& host, const Face& face, const ServeOptions& options, std::string& error);
	int (*port)(void* server);
	// Serves until stopped; false with `error` set when it failed.
	bool (*run)(void* server, std::string& error);
	void (*stop)(void* server);      // any thread
	void (*shutdown)(void* server);  // any thread
	void (*destroy)(void* server);
};

}  // namespace talkhead

extern "C" const void* talkhead_serve_module();
