// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace talkhead {

// Who may use `talkhead serve` (issue 28 items 2 and 3, D58): the Host a request names (DNS rebinding),
// the Origin of the page that opens a WebSocket (cross-site control), and the token. Pure functions of
// the headers, so that each rule is tested on its own.
struct AccessPolicy {
	std::string listenHost;                // the address listened on ("127.0.0.1", "0.0.0.0", "192.0.2.7", "::")
	std::vector<std::string> allowOrigins; // origins allowed besides the server's own and loopback pages; "*": any
	std::vector<std::string> allowHosts;   // Host names allowed besides the listen address and loopback names; "*": any
	std::string token;                     // empty: no token asked
};

// How a client reads a field a message names ({{field}}, base/error.h): a request's member as "the
// request's 'lang'"; nullopt for the server's own settings (the clause that suggests one is left out: a
// client cannot change them). forRequester words a whole message so. (Here, with the other pure rules,
// because the network plugin words its refusals too.)
std::optional<std::string> requestField(const std::string& field);
std::string forRequester(const std::string& message);

// localhost (and *.localhost), 127.0.0.0/8, ::1.
bool isLoopbackHost(std::string_view host);
// The host part of a Host header or an origin's authority, lower case, without the port or IPv6 brackets.
std::string hostOnly(std::string_view authority);

// Why a request naming `hostHeader` is refused, or nullopt. Loopback names are always allowed; the listen
// address when it is one address; any IP address when listening on all of them; names only from
// allowHosts.
std::optional<std::string> refusedHost(const AccessPolicy& policy, std::string_view hostHeader);
// Why a WebSocket upgrade from a page of `origin` is refused, or nullopt. No Origin (not a browser):
// allowed. Allowed: the server's own origin (the scheme it serves and `hostHeader`), pages on a loopback
// host, allowOrigins (exact, or "*"). "null" (file: pages, sandboxed frames) only when allowOrigins says so.
std::optional<std::string> refusedOrigin(const AccessPolicy& policy, std::string_view origin, std::string_view hostHeader, bool tls);

// The token of an "Authorization: Bearer T" header, or nullopt.
std::optional<std::string> bearerToken(std::string_view authorization);
// Compares in time independent of where the strings differ.
bool sameToken(std::string_view expected, std::string_view given);

}  // namespace talkhead
