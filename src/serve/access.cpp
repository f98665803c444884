// SPDX-License-Identifier: GPL-3.0-or-later
#include "serve/access.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "base/error.h"
#include "base/text.h"

namespace talkhead {

namespace {

std::string lower(std::string_view s) {
	std::string out(s);
	for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
	return out;
}

bool isIpv4(std::string_view s, int* first = nullptr) {
	int parts = 0, value = -1, lead = -1;
	for (char c : std::string(s) + '.') {
		if (c == '.') {
			if (value < 0 || value > 255) return false;
			if (parts++ == 0) lead = value;
			value = -1;
		} else if (std::isdigit(static_cast<unsigned char>(c))) {
			value = (value < 0 ? 0 : value * 10) + (c - '0');
			if (value > 255) return false;
		} else {
			return false;
		}
	}
	if (first) *first = lead;
	return parts == 4;
}

bool isIpv6(std::string_view s) {
	return !s.empty() && s.find(':') != std::string_view::npos &&
	       std::all_of(s.begin(), s.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) || c == ':' || c == '.'; });
}

bool listed(const std::vector<std::string>& list, const std::string& value) {
	return std::any_of(list.begin(), list.end(), [&](const std::string& l) { return l == "*" || lower(l) == value; });
}

}  // namespace

std::string hostOnly(std::string_view authority) {
	std::string a = lower(authority);
	if (!a.empty() && a.front() == '[') {
		const auto close = a.find(']');
		return close == std::string::npos ? a : a.substr(1, close - 1);
	}
	const auto colon = a.find(':');
	if (colon != std::string::npos && a.find(':', colon + 1) == std::string::npos) a = a.substr(0, colon);  // name:port
	while (!a.empty() && a.back() == '.') a.pop_back();  // "localhost." is localhost
	return a;
}

std::optional<std::string> requestField(const std::string& field) {
	static const std::set<std::string> members = {"text", "lang", "voice", "rate", "pitch", "emotion", "intensity", "ramp", "audio",
	                                              "encoding", "sample_rate", "channels", "transcript", "visemes", "alignment", "id"};
	if (members.count(field)) return "the request's '" + field + "'";
	return std::nullopt;
}

std::string forRequester(const std::string& message) { return wordFields(message, requestField); }

bool isLoopbackHost(std::string_view raw) {
	const std::string h = hostOnly(raw);
	int first = -1;
	if (isIpv4(h, &first)) return first == 127;
	return h == "localhost" || endsWith(h, ".localhost") || h == "::1" || h == "0:0:0:0:0:0:0:1";
}

std::optional<std::string> refusedHost(const AccessPolicy& p, std::string_view hostHeader) {
	const std::string h = hostOnly(hostHeader);
	if (h.empty()) return std::string("the request names no Host");
	if (isLoopbackHost(h) || listed(p.allowHosts, h)) return std::nullopt;
	const std::string listen = hostOnly(p.listenHost);
	const bool all = listen == "0.0.0.0" || listen == "::";
	if (h == listen || (all && (isIpv4(h) || isIpv6(h)))) return std::nullopt;
	return "Host '" + safeQuote(h, 80) + "' is not this server's ({{allow-host}} NAME allows a name)";
}

std::optional<std::string> refusedOrigin(const AccessPolicy& p, std::string_view rawOrigin, std::string_view hostHeader, bool tls) {
	if (rawOrigin.empty()) return std::nullopt;
	std::string origin = lower(rawOrigin);
	while (!origin.empty() && origin.back() == '/') origin.pop_back();
	if (listed(p.allowOrigins, origin)) return std::nullopt;
	const std::string shown = "origin '" + safeQuote(origin, 80) + "' is not allowed ({{allow-origin}} ORIGIN allows one)";
	if (origin == "null") return shown;
	const auto scheme = origin.find("://");
	if (scheme == std::string::npos) return shown;
	const std::string authority = origin.substr(scheme + 3);
	const std::string s = origin.substr(0, scheme);
	if ((s == "http" || s == "https") && isLoopbackHost(authority) && authority.find('/') == std::string::npos) return std::nullopt;
	if (origin == std::string(tls ? "https://" : "http://") + lower(hostHeader)) return std::nullopt;
	return shown;
}

std::optional<std::string> bearerToken(std::string_view a) {
	std::string_view s = a;
	while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
	if (s.size() < 7 || lower(s.substr(0, 7)) != "bearer ") return std::nullopt;
	s.remove_prefix(7);
	while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
	while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
	return std::string(s);
}

bool sameToken(std::string_view expected, std::string_view given) {
	unsigned char diff = expected.size() == given.size() ? 0 : 1;
	for (std::size_t i = 0; i < expected.size(); ++i) diff |= static_cast<unsigned char>(expected[i] ^ (i < given.size() ? given[i] : 0));
	return diff == 0 && !expected.empty();
}

}  // namespace talkhead
