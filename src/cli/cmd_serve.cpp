// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead serve: live streams for chatbots and voice assistants (issue 16);
// talkhead live: a session script (what serve --record writes) rendered offline, frame for frame.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <tuple>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/json.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/run.h"
#include "cli/commands.h"
#include "cli/video_options.h"
#include "render/frame_sink.h"
#include "render/live.h"
#include "render/render.h"
#include "serve/access.h"
#include "serve/server.h"
#include "synth/coarticulation.h"

namespace talkhead::cli {

namespace {

// Options both commands share: how the face looks and moves.
std::vector<OptionSpec> liveOptionSpecs() {
	std::vector<OptionSpec> specs = {faceOption(), {"--model", "M.thm", "face model file (default: the embedded default face)"},
	        {"--size", "WxH", "output size (default 1280x720)"},
	        {"--fit", "MODE", "face (default: the whole face kept), crop, pad or stretch when --size has another aspect than the model, as render's option"},
	        {"--fps", "RATE", "frame rate (default 30)"},
	        {"--emotion", "LABEL[:I]", "the emotion at the start (default neutral)"},
	        {"--lang", "LANG", "language of say requests without one (default en-US)"},
	        {"--blinks", "on|off", "blink (default on)"},
	        {"--head-motion", "on|off|X", "small head motion (default on; X scales it, 0–3)"},
	        {"--speech-brows", "on|off|X", "brow raises with speech (default on)"},
	        {"--seed", "N", "seed of blinks and head motion (default 1): the same seed and requests give the same frames"},
	        {"--sample-rate", "HZ", "the stream's sound (default 22050, espeak-ng's own rate)"},
	        {"--coarticulation", "on|off|F.tsv", "the mouth from its phone context (D62, D90): on (default, the model that ships), off (the thesis's path) or a model file, as render's option"},
	        {"--pauses", "STYLE", "natural (the default with --coarticulation off), still (the default) or thesis, as render's option"}};
	for (auto& d : drawingOptionSpecs()) specs.push_back(d);
	return specs;
}

LiveOptions liveOptions(const Args& args, const std::string& command) {
	LiveOptions o;
	o.rate = parseFps(args, command);
	parseSize(command + ": --size", args.get("--size", "1280x720"), o.render.synth.width, o.render.synth.height);
	o.render.fit = parseFit(args, command);
	o.expression = parseEmotionOption(args, command);
	o.modulation = parseModulation(args, command);
	o.speechBrows = parseSpeechBrows(args, command, "on");
	o.sampleRate = int(args.number("--sample-rate", 22050, 8000, 96000));
	o.pauses = parsePausesOption(args, command);
	parseDrawingOptions(args, command, o.render.synth);
	return o;
}

std::vector<OptionSpec> with(std::vector<OptionSpec> a, const std::vector<OptionSpec>& b) {
	a.insert(a.end(), b.begin(), b.end());
	return a;
}

}  // namespace

namespace {

// Who may open sessions: the token (required off loopback), the allowed origins and hosts, TLS.
void securityOptions(const Args& args, ServeOptions& o) {
	const bool loopback = isLoopbackHost(o.host);
	// The token: never from a log, and preferably not from the command line (ps shows it).
	if (auto file = args.get("--token-file")) {
		const std::string text = readTextFile(*file);
		o.token = std::string(trim(text.substr(0, text.find('\n'))));
		if (o.token.empty()) throw Error(*file, 1, "the token file is empty");
	} else if (auto t = args.get("--token")) {
		o.token = *t;
	} else if (const char* env = std::getenv("TALKHEAD_TOKEN"); env && *env) {
		o.token = env;
	}
	if (!o.token.empty() && o.token.size() < 16) throw UsageError("serve: the token must be at least 16 characters");
	if (!loopback && o.token.empty())
		throw UsageError("serve: listening on " + safeQuote(o.host) + " (not loopback) needs a token: --token-file FILE, $TALKHEAD_TOKEN or --token");
	auto list = [&](const char* name) {
		std::vector<std::string> out;
		if (auto v = args.get(name))
			for (const std::string& item : split(*v, ','))
				if (!trim(item).empty()) out.emplace_back(trim(item));
		return out;
	};
	o.allowOrigins = list("--allow-origin");
	o.allowHosts = list("--allow-host");
	o.tlsCert = args.get("--tls-cert", "");
	o.tlsKey = args.get("--tls-key", "");
	if (o.tlsCert.empty() != o.tlsKey.empty()) throw UsageError("serve: --tls-cert and --tls-key go together");
}

// --listen HOST:PORT ([v6]:PORT; port 0: any free one).
void listenOption(const Args& args, ServeOptions& o) {
	const std::string listen = args.get("--listen", "127.0.0.1:8765");
	const auto colon = listen.rfind(':');
	double port = -1;
	if (colon == std::string::npos || !parseDouble(listen.substr(colon + 1), port) || !(port >= 0 && port <= 65535) || port != std::floor(port))
		throw UsageError("serve: --listen takes HOST:PORT, e.g. 127.0.0.1:8765");
	o.host = listen.substr(0, colon);
	if (o.host.size() > 2 && o.host.front() == '[' && o.host.back() == ']') o.host = o.host.substr(1, o.host.size() - 2);
	o.port = int(port);
}

// What one session may take, and the server's load bar and drain.
void limitOptions(const Args& args, ServeOptions& o) {
	o.idleSeconds = args.number("--idle-timeout", 300, 0, 86400 * 7);
	o.limits.queuedRequests = int(args.number("--max-queued-requests", 32, 1, 100000));
	o.limits.queuedSeconds = args.number("--max-queued-speech", 900, 1, 86400);
	o.limits.utteranceSeconds = args.number("--max-utterance", 600, 1, 86400);
	o.limits.breakSeconds = args.number("--max-breaks", 60, 0, 86400);
	o.maxLoad = args.number("--max-load", 0.9, 0, 64);
	o.drainSeconds = args.number("--drain", 5, 0, 3600);
}

}  // namespace

int runServe(const std::vector<std::string>& argv) {
	Args args("serve", "talkhead serve [--listen 127.0.0.1:8765] [--demo] [--face NAME | --model M.thm] [--size WxH] [--fps N]",
	          with(liveOptionSpecs(),
	               {{"--listen", "HOST:PORT", "address to listen on (default 127.0.0.1:8765; port 0: any free one, printed)"},
	                {"--demo", "", "serve the browser demo (examples/live/index.html) at /"},
	                {"--max-sessions", "N", "live sessions at once (default 4); more are refused with an error"},
	                {"--crf", "N", "H.264 quality, 0–51 (default 23; 0 = lossless, which browsers do not play)"},
	                {"--preset", "NAME", "x264 preset (default veryfast)"},
	                {"--record", "DIR", "write each session's requests with the frame each took effect at (DIR/session-N.jsonl; 'talkhead live' replays one)"},
	                {"--record-max", "MiB", "the most one session's record may take (default 64); past it, its recording stops (the record ends there)"},
	                {"--token", "TOKEN", "every session must give it (header 'Authorization: Bearer TOKEN', or a first message {\"type\": \"auth\", \"token\": …}); also from $TALKHEAD_TOKEN or --token-file; required off loopback"},
	                {"--token-file", "FILE", "read the token from FILE (its first line), not the command line"},
	                {"--allow-origin", "O1,O2", "web pages (origins, e.g. https://app.example.com; * for any) that may open sessions besides the server's own and loopback pages"},
	                {"--allow-host", "H1,H2", "Host names the server answers to besides its listen address and loopback (e.g. behind a proxy; * for any)"},
	                {"--tls-cert", "PEM", "serve HTTPS and wss:// with this certificate (chain)"},
	                {"--tls-key", "PEM", "the certificate's private key"},
	                {"--idle-timeout", "S", "close a session after S seconds with no request and nothing to say (default 300; 0 = never)"},
	                {"--max-queued-requests", "N", "say/speak requests a session may have queued (default 32)"},
	                {"--max-queued-speech", "S", "seconds of speech a session may have queued (default 900)"},
	                {"--max-utterance", "S", "seconds of one say or speak (default 600)"},
	                {"--max-breaks", "S", "seconds of SSML breaks in one say (default 60)"},
	                {"--max-load", "X", "refuse a new session when the sessions would take more than X of the cores, or frames were late (default 0.9; 0 = off)"},
	                {"--drain", "S", "on SIGTERM/SIGINT, speech under way finishes for at most S seconds (default 5); a second signal stops at once"},
	                {"--quiet", "", "no log lines", "-q"}}),
	          "Live talking-head streams for chatbots and voice assistants. Each WebSocket connection to /live is a\n"
	          "session: the face is always on (blinks, small head motion, the emotion) and speaks what it is sent —\n"
	          "text (espeak-ng), or audio with its timing — streamed as fragmented MP4 (H.264 + AAC) for Media Source\n"
	          "Extensions, with JSON events (utterance started and ended, marks, visemes). Requests are JSON text\n"
	          "messages: say, speak, emotion, stop (docs/serve-protocol.md). Loopback only unless --listen says otherwise.");
	if (!args.parse(argv)) return 0;
	if (!args.positionals().empty()) throw UsageError("serve: no positional arguments");
	ServeOptions o;
	o.live = liveOptions(args, "serve");
	const auto coarticulation = parseCoarticulation(args);
	listenOption(args, o);
	o.maxSessions = int(args.number("--max-sessions", 4, 1, 64));
	o.crf = parseCrf(args, VideoFormat::Mp4Stream);
	o.preset = args.get("--preset", "veryfast");
	o.lang = args.get("--lang", "en-US");
	Language::get(o.lang);  // checked now
	const bool quiet = args.has("--quiet");
	if (!quiet) o.log = [](const std::string& s) { std::fprintf(stderr, "talkhead: serve: %s\n", shownLine(s).c_str()); };
	o.operatorField = [](const std::string& f) { return std::optional<std::string>(cliField(f)); };
	if (args.has("--demo")) {
		const auto page = findDataFile("examples/live/index.html");
		if (!page) throw Error("the demo page examples/live/index.html is not installed");
		o.demo = true;
		o.demoPage = *page;
	}
	if (auto dir = args.get("--record")) {
		checkWritableFolder(*dir + "/x");
		o.recordDir = *dir;
	}
	o.recordMaxBytes = std::uint64_t(args.number("--record-max", 64, 1, 1 << 20) * double(1 << 20));
	if (o.host == "localhost") o.host = "127.0.0.1";
	securityOptions(args, o);
	limitOptions(args, o);
	o.handleSignals = true;
	const FaceModel model = loadRenderModel(faceOrModel(args.get("--face"), args.get("--model"), "serve", false));
	const Face face(model, coarticulation);
	Server server(face, o);
	// The port line is the contract with scripts and tests (port 0 picks a free one).
	const bool tls = !o.tlsCert.empty();
	const std::string shown = o.host.find(':') != std::string::npos ? "[" + o.host + "]" : o.host;
	std::printf("talkhead: serving on %s://%s:%d/ (WebSocket %s://%s:%d/live)%s%s\n", tls ? "https" : "http", shown.c_str(), server.port(), tls ? "wss" : "ws",
	            shown.c_str(), server.port(), o.demo ? ", demo page at /" : "", o.token.empty() ? "" : ", token required");
	std::fflush(stdout);
	server.run();
	if (!quiet) std::fprintf(stderr, "talkhead: serve: stopped\n");
	return 0;
}

int runLive(const std::vector<std::string>& argv) {
	Args args("live", "talkhead live SESSION.jsonl -o OUT.mp4|OUT.y4m [options]",
	          with(liveOptionSpecs(),
	               {{"--format", "FORMAT", "mp4 (default), webm (VP9 + Vorbis; the default for -o F.webm) or y4m (raw frames, e.g. to compare with a stream)"},
	                {"--background", "KIND", "opaque (default) or transparent (the face on a feathered matte as alpha: --format webm)"},
	                {"--crf", "N", "quality: H.264 0–51 (default 20), VP9 0–63 (default 32)"},
	                {"--frames-total", "N", "how many frames (default: the script's end line)"},
	                {"--quiet", "", "no events on standard output", "-q"},
	                {"--output", "OUT", "the video to write", "-o"}}),
	          "Renders a live session offline, frame for frame: the requests of a session script (one JSON object per\n"
	          "line: {\"frame\": N, \"request\": {…}}, as 'talkhead serve --record' writes them) applied before the frames\n"
	          "they name. With the server's options and seed it gives the frames the stream had (say requests: as far\n"
	          "as espeak-ng's in-process state allows, D51; speak requests exactly). Events go to standard output as\n"
	          "JSON lines.");
	if (!args.parse(argv)) return 0;
	args.onePositional("give one session script");
	const std::string script = args.positionals()[0];
	const std::string out = args.required("--output", "-o OUT is required");
	const VideoFormat format = *parseVideoFormat(args, "live", out, false);
	const bool transparent = parseTransparent(args, "live", format);
	LiveOptions o = liveOptions(args, "live");
	const auto coarticulation = parseCoarticulation(args);
	const std::string lang = args.get("--lang", "en-US");
	Language::get(lang);
	// The script: requests by frame, and its end.
	const SessionScript sessionScript = readSessionScript(script);
	const std::vector<SessionScript::Step>& steps = sessionScript.steps;
	std::int64_t total = sessionScript.end;
	if (auto n = args.get("--frames-total")) total = std::int64_t(args.number("--frames-total", 0, 1, 1e7));
	if (total < 0) throw Error(script, 0, "no end line ({\"type\": \"end\", \"frame\": N}): give --frames-total N");
	const FaceModel model = loadRenderModel(faceOrModel(args.get("--face"), args.get("--model"), "live", false));
	const Face face(model, coarticulation);
	LiveSession session(face, o);
	const StreamInfo& info = session.info();
	OutputSpec spec;
	spec.format = format, spec.path = out, spec.crf = parseCrf(args, format), spec.alpha = transparent;
	// Through a frame sink, as render writes (a temporary name, renamed when complete: nothing partial). The
	// session's sound never ends: the video's length of it.
	const std::unique_ptr<FrameSink> sink = makeVideoSink(spec, shiftedSource(borrowedSource(session.audio()), Ticks(0), info.rate.time(total)));
	sink->begin(info);  // --background transparent: the sink needs alpha, and play() draws the face's matte (D65)
	const bool quiet = args.has("--quiet");
	std::vector<LiveEvent> events;
	std::size_t next = 0;
	std::unique_ptr<SpeechStream> stream;  // a streamed speak's, between its pieces
	std::deque<HeldPart> held;             // its parts made, waiting for their part steps (a record with them)
	for (std::int64_t n = 0; n < total; ++n) {
		for (; next < steps.size() && steps[next].frame <= n; ++next) {
			const SessionScript::Step& s = steps[next];
			if (s.part) {
				if (held.empty()) throw Error(script, s.line, "a 'part' step with no speech part made before it");
				HeldPart p = std::move(held.front());
				held.pop_front();
				if (p.expression) session.setEmotion(*p.expression, p.ramp);
				session.enqueue(std::move(p.utterance));
				continue;
			}
			try {
				const LiveRequest r = parseLiveRequest(s.json);  // errors worded as a client reads them (serve/access.h)
				if (r.kind == LiveRequest::Kind::Stop) stream.reset(), held.clear();  // a streamed speak under way ends
				if (speaksInParts(r)) {
					replaySpeakInParts(session, r, stream, lang, s.look, sessionScript.hasParts ? &held : nullptr);
					continue;
				}
				std::optional<PlannedUtterance> u;  // planned by the session when it is queued
				if (r.kind == LiveRequest::Kind::Say || r.kind == LiveRequest::Kind::Speak) u.emplace(prepareUtterance(r, lang, o.sampleRate));
				applyLiveRequest(session, r, std::move(u));
			} catch (const std::exception& e) {
				throw Error(script, s.line, forRequester(describeException(e)));
			}
		}
		events.clear();
		session.play(*sink, events);
		if (!quiet)
			for (const LiveEvent& e : events) std::printf("%s\n", liveEventJson(e).c_str());
	}
	sink->finish();
	sink->commit();
	return 0;
}

}  // namespace talkhead::cli
