// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead batch MANIFEST -o OUTDIR: perceptual-test stimuli (issue 14, D51).
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <map>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/sha256.h"
#include "base/text.h"
#include "cli/run.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "base/interrupt.h"
#include "base/json.h"
#include "base/progress.h"
#include "stimuli/batch.h"
#include "stimuli/side_by_side.h"

namespace fs = std::filesystem;

extern char** environ;

namespace talkhead::cli {

namespace {

// Runs a job as a child process (this executable: `talkhead job FILE`, the job written as JSON to a
// temporary file beside `near`, removed after) and waits: each stimulus in a fresh process,
// because libespeak-ng's timings depend on what it synthesised before in the same process (the same
// sentence comes out a few milliseconds apart after another one), which would make a stimulus depend on
// the rows before it — and a shard on which rows it holds. Returns the exit code; *message gets the last
// line the child wrote on stderr.
int runChild(const Job& job, const std::string& near, std::string* message) {
	const std::string jobPath = temporaryNameFor(near + ".job.json");
	registerTemporary(jobPath);
	struct Remove {
		std::string path;
		~Remove() {
			std::error_code e;
			fs::remove(path, e);
			releaseTemporary(path);
		}
	} remove{jobPath};
	writeFileAtomically(jobPath, jobJson(job) + "\n");
	const std::vector<std::string> args{"job", jobPath};
	int pipefd[2];
	if (::pipe(pipefd) != 0) throw Error("batch: cannot create a pipe");
	posix_spawn_file_actions_t actions;
	posix_spawn_file_actions_init(&actions);
	posix_spawn_file_actions_adddup2(&actions, pipefd[1], 2);
	posix_spawn_file_actions_addclose(&actions, pipefd[0]);
	std::vector<std::string> all{"talkhead"};
	all.insert(all.end(), args.begin(), args.end());
	std::vector<char*> argv;
	for (auto& a : all) argv.push_back(a.data());
	argv.push_back(nullptr);
	pid_t pid = 0;
	const int rc = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
	posix_spawn_file_actions_destroy(&actions);
	if (rc == 0) setInterruptChild(pid);
	::close(pipefd[1]);
	if (rc != 0) {
		::close(pipefd[0]);
		throw Error(std::string("batch: cannot start talkhead: ") + std::strerror(rc));
	}
	std::string err;
	char buf[4096];
	for (ssize_t n; (n = ::read(pipefd[0], buf, sizeof buf)) != 0;) {
		if (n < 0) {
			if (errno == EINTR) continue;
			break;
		}
		err.append(buf, std::size_t(n));
	}
	::close(pipefd[0]);
	int status = 0;
	while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
	}
	setInterruptChild(0);
	while (!err.empty() && err.back() == '\n') err.pop_back();
	const auto nl = err.rfind('\n');
	std::string last = nl == std::string::npos ? err : err.substr(nl + 1);
	if (startsWith(last, "talkhead: error: ")) last = last.substr(17);
	if (message) *message = last;
	if (WIFEXITED(status)) return WEXITSTATUS(status);
	if (message && WIFSIGNALED(status)) *message = "killed by signal " + std::to_string(WTERMSIG(status)) + (last.empty() ? "" : " (" + last + ")");
	return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// A row's job with what the batch adds: its output and how the child runs.
Job rowJob(const std::string& command, const std::vector<JobField>& fields, std::initializer_list<JobField> extra) {
	Job j{command, fields};
	j.fields.insert(j.fields.end(), extra);
	return j;
}

// A side-by-side stimulus: both sides rendered as y4m (lossless) in a temporary folder beside the output —
// the row's sound track from its own side — then composed into one MP4 (stimuli/side_by_side.h).
template <class Run>
void renderSideBySide(const BatchRow& row, const std::string& path, const std::string& timeline, const std::string& threads, Run&& run) {
	const std::string dir = temporaryNameFor(path + ".d");
	std::error_code ec;
	fs::create_directory(dir, ec);
	if (ec) throw Error(dir, 0, "cannot create folder: " + ec.message());
	struct Cleanup {
		std::string dir;
		~Cleanup() {
			std::error_code e;
			fs::remove_all(dir, e);
			releaseTemporary(dir);
		}
	} cleanup{dir};
	const std::string own = dir + "/row.y4m", other = dir + "/versus.y4m", wav = dir + "/row.wav", json = dir + "/row.json";
	for (const auto& f : {own, other, wav, json}) registerTemporary(f);
	struct Release {
		std::vector<std::string> files;
		~Release() {
			for (const auto& f : files) releaseTemporary(f);
		}
	} release{{own, other, wav, json}};
	// A sound track: speech from text (say), or a render's audio, unless muted.
	const bool muted = jobValue(row.job, "no-audio") || (row.command == "render" && !jobValue(row.job, "audio"));
	Job a = rowJob(row.command, row.job, {{"format", "y4m"}, {"output", own}, {"quiet", std::nullopt}, {"threads", threads}, {"timeline-out", json}});
	if (!muted) a.fields.push_back({"audio-out", wav});
	run(a, own);
	Job b = rowJob(row.command, row.versusJob, {{"format", "y4m"}, {"output", other}, {"quiet", std::nullopt}, {"threads", threads}});
	if (!muted) b.fields.push_back({"no-audio", std::nullopt});
	run(b, other);
	SideBySideOptions o;
	if (auto crf = row.fields.find("crf"); crf != row.fields.end()) o.mp4.crf = std::stoi(crf->second);
	writeSideBySide(row.versusLeft ? other : own, row.versusLeft ? own : other, muted ? "" : wav, path, o);
	fs::rename(json, timeline, ec);  // the sidecar once the stimulus is complete (same folder: atomic)
	if (ec) throw Error(timeline, 0, "cannot write: " + ec.message());
}

}  // namespace

namespace {

Args batchArgs() {
	return Args("batch", "talkhead batch MANIFEST -o OUTDIR [options]   |   talkhead batch --merge OUTDIR SHARD_DIR…",
	          {{"--output", "OUTDIR", "folder for the stimuli (ID.mp4), key.csv and the orders (required)", "-o"},
	           {"--seed", "N", "seed of the blind IDs and the orders (default 1)"},
	           {"--participants", "N", "presentation orders to write, one per participant (default: one full design: n stimuli, 2n when n is odd)"},
	           {"--no-repeat", "COLUMN", "no order shows two stimuli with the same value of this column in a row (e.g. emotion)"},
	           {"--shard", "I/N", "render only the rows of shard I of N (rows I, I+N, …; IDs, key and orders come from the whole manifest)"},
	           {"--threads", "N", "worker threads per stimulus (default: all cores)"},
	           {"--player", "", "also write index.html, a browser test player (the thesis's protocol; no server or network)"},
	           {"--player-replays", "N", "extra plays of a clip per question in the player (default 0)"},
	           {"--player-lang", "LANG", "the player's voting terms: en (default) or pt (the thesis's Portuguese)"},
	           {"--score", "KEY.csv", "score the player's answer files (positional arguments) against this key: recognition per emotion and condition"},
	           {"--confusion", "F.png", "with --score: also draw the confusion matrix (true emotion × answer)"},
	           {"--merge", "OUTDIR", "join the folders of shards (positional arguments) into OUTDIR, checking every SHA-256"},
	           {"--progress", "MODE", "bar (default on a terminal), json (default otherwise: one JSON line per stimulus, then a summary line) or none"},
	           {"--quiet", "", "no progress and no summary", "-q"}},
	          "Renders one stimulus per manifest row (CSV with a header, or JSON) under a blind ID, and writes\n"
	          "key.csv (ID → row, conditions, SHA-256) and one balanced presentation order per participant\n"
	          "(order-NN.csv, a Williams design). The whole manifest is checked before anything renders; a rerun\n"
	          "skips stimuli already complete (checked against key.csv's SHA-256); a failing row is reported and\n"
	          "the others go on; the exit code is 0 only when every row of the shard succeeded. Columns: README\n"
	          "'Perceptual-test stimuli'.");
}

// --score and --merge: the two modes that render nothing.
int runScoreOrMerge(const Args& args) {
	if (auto key = args.get("--score")) {
		if (args.positionals().empty()) throw UsageError("batch --score KEY.csv: name the answer files (answers-NN.csv)");
		const Score s = scoreAnswers(*key, args.positionals());
		std::fputs(scoreReport(s).c_str(), stdout);
		if (auto png = args.get("--confusion")) writeConfusionPng(s, *png);
		return 0;
	}
	const std::string merge = *args.get("--merge");
	if (args.positionals().empty()) throw UsageError("batch --merge OUTDIR: name the shard folders to join");
	const std::size_t missing = mergeShards(merge, args.positionals());
	if (missing) std::fprintf(stderr, "talkhead: error: %s: %zu stimuli are in no shard yet (key.csv says 'missing')\n", merge.c_str(), missing);
	else if (!args.has("--quiet")) std::fprintf(stderr, "batch: %zu shards joined into %s\n", args.positionals().size(), merge.c_str());
	return missing ? 1 : 0;
}

// One run over a manifest's rows: renders the shard's stimuli, resumes complete ones, reports each, and
// keeps key.csv current after every stimulus.
struct BatchRun {
	const Manifest& m;
	const std::vector<std::string>& ids;
	std::string out, keyPath, threads, progressMode;
	std::size_t shard = 0, shards = 1, inShard = 0;
	std::map<std::string, std::string> previous;  // ID → SHA-256 from an earlier run's key.csv
	std::vector<StimulusResult> results;
	std::size_t ok = 0, skipped = 0, failed = 0;
	std::vector<std::pair<long, std::string>> failures;  // row line, message
	ProgressBar bar;
	std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();

	BatchRun(const Manifest& manifest, const std::vector<std::string>& blindIds, bool noBar) : m(manifest), ids(blindIds), results(manifest.rows.size()), bar(noBar) {}

	double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }

	// One progress event per stimulus of the shard: a JSON line, or the bar.
	void report(const BatchRow& row, const char* status, double seconds, const std::string& message) {
		const std::size_t done = ok + skipped + failed;
		if (progressMode == "json") {
			JsonObject j;
			j.add("type", "stimulus").add("done", done).add("total", inShard).add("id", ids[row.index]).add("row", row.line).add("status", status).add("seconds", seconds, "%.3f");
			if (!message.empty()) j.add("message", message);
			std::fprintf(stderr, "%s\n", j.str().c_str());
			std::fflush(stderr);
		} else if (progressMode == "bar") {
			bar.report(inShard ? double(done) / double(inShard) : 1.0,
			           std::to_string(done) + "/" + std::to_string(inShard) + (failed ? ", " + std::to_string(failed) + " failed" : ""));
		}
	}

	void row(const BatchRow& row) {
		std::error_code ec;
		StimulusResult& res = results[row.index];
		res.file = ids[row.index] + ".mp4";
		const std::string path = (fs::path(out) / res.file).string();
		if (row.index % shards != shard) {
			// Another shard's row: kept as complete when another shard already made it in this folder.
			auto p = previous.find(ids[row.index]);
			const bool done = p != previous.end() && fs::is_regular_file(path, ec) && sha256File(path) == p->second;
			res.status = done ? "ok" : "not-in-shard";
			if (done) res.sha256 = p->second;
			return;
		}
		// Resume: a file whose checksum key.csv already holds is complete.
		if (auto p = previous.find(ids[row.index]); p != previous.end() && fs::is_regular_file(path, ec) && sha256File(path) == p->second) {
			res.status = "ok", res.sha256 = p->second;  // complete (the key does not say which run made it)
			++skipped;
			report(row, "complete", 0, "");
			return;
		}
		const auto started = std::chrono::steady_clock::now();
		const std::string timeline = (fs::path(out) / (ids[row.index] + ".json")).string();
		try {
			std::string message;
			auto run = [&](const Job& job, const std::string& near) {
				const int rc = runChild(job, near, &message);
				if (rc != 0) throw Error(message.empty() ? "exit code " + std::to_string(rc) : message);
			};
			if (!row.sideBySide) {
				run(rowJob(row.command, row.job, {{"output", path}, {"quiet", std::nullopt}, {"threads", threads}, {"timeline-out", timeline}}), path);
			} else {
				renderSideBySide(row, path, timeline, threads, run);
			}
			res.status = "ok", res.sha256 = sha256File(path);
			++ok;
			report(row, "rendered", std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), "");
		} catch (const std::exception& e) {
			res.status = "failed", res.message = e.what();
			++failed;
			failures.emplace_back(row.line, e.what());
			bar.finish();
			std::fprintf(stderr, "talkhead: error: %s\n", shownLine(m.path + ":" + std::to_string(row.line) + ": " + e.what()).c_str());
			report(row, "failed", std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), e.what());
		}
		// After every stimulus, so a batch stopped half-way resumes from where it was.
		writeFileAtomically(keyPath, keyCsv(m, ids, results));
	}

	void summary(std::size_t orders) const {
		const std::size_t n = m.rows.size();
		if (progressMode == "json")
			std::fprintf(stderr, "%s\n",
			             JsonObject().add("type", "summary").add("stimuli", n).add("in_shard", inShard).add("rendered", ok).add("complete", skipped).add("failed", failed)
			                 .add("seconds", elapsed(), "%.3f").str().c_str());
		if (progressMode != "none") {
			// The summary table: counts per outcome, then every failed row.
			std::fprintf(stderr, "batch: %zu stimuli%s in %.1f s; key.csv and %zu orders in %s\n", n,
			             shards > 1 ? (" (shard " + std::to_string(shard) + "/" + std::to_string(shards) + ")").c_str() : "", elapsed(), orders, out.c_str());
			std::fprintf(stderr, "  %-18s %6zu\n  %-18s %6zu\n  %-18s %6zu\n", "rendered", ok, "already complete", skipped, "failed", failed);
			if (shards > 1) std::fprintf(stderr, "  %-18s %6zu\n", "other shards", n - inShard);
			for (const auto& [line, message] : failures) std::fprintf(stderr, "  failed: %s:%ld: %s\n", m.path.c_str(), line, message.c_str());
		}
	}
};

}  // namespace

int runBatch(const std::vector<std::string>& argv) {
	Args args = batchArgs();
	if (!args.parse(argv)) return 0;
	if (args.has("--score") || args.has("--merge")) return runScoreOrMerge(args);
	args.onePositional("expected one MANIFEST (CSV or JSON)");
	const std::string out = args.required("--output", "-o OUTDIR is required");
	const std::uint64_t seed = std::uint64_t(args.number("--seed", 1, 0, 9007199254740991.0));
	std::size_t shard = 0, shards = 1;
	if (auto s = args.get("--shard")) {
		const auto parts = split(*s, '/');
		long long i = -1, n = 0;
		if (parts.size() != 2 || !parseInt(parts[0], i) || !parseInt(parts[1], n) || n < 1 || n > 100000 || i < 0 || i >= n)
			throw UsageError("batch: --shard takes I/N with 0 ≤ I < N (e.g. 0/4)");
		shard = std::size_t(i), shards = std::size_t(n);
	}
	const std::string threads = std::to_string(long(args.number("--threads", 0, 0, 256)));
	const bool quiet = args.has("--quiet");
	const std::string progressMode = quiet ? "none" : args.get("--progress", ::isatty(2) ? "bar" : "json");
	if (progressMode != "bar" && progressMode != "json" && progressMode != "none") throw UsageError("batch: --progress takes bar, json or none");

	Manifest m;
	try {
		m = loadManifest(args.positionals()[0]);
		// Every face the rows name is built here, once, before the rows run (each in its own process).
		checkManifestModels(m, [&](const std::string& face) { return shippedFaceModel(face, quiet); });
		for (const BatchRow& row : m.rows)
			if (auto face = jobValue(row.job, "face")) {
				try {
					shippedFaceModel(*face, quiet);
				} catch (const Error& e) {
					throw Error(m.path + ":" + std::to_string(row.line) + ":face: " + e.what());
				}
			}
	} catch (const ManifestErrors& e) {
		for (const auto& msg : e.messages) std::fprintf(stderr, "talkhead: error: %s\n", shownLine(msg).c_str());
		return 1;
	}
	const std::size_t n = m.rows.size();
	const std::size_t participants = std::size_t(args.number("--participants", double(n % 2 ? 2 * n : n), 1, 100000));
	std::vector<std::string> labels;
	if (auto column = args.get("--no-repeat")) {
		if (std::find(m.columns.begin(), m.columns.end(), *column) == m.columns.end())
			throw UsageError("batch: --no-repeat: the manifest has no column '" + *column + "'");
		for (const auto& r : m.rows) labels.push_back(*column == "emotion" ? r.emotion : (r.fields.count(*column) ? r.fields.at(*column) : ""));
	}
	const std::vector<std::string> ids = blindIds(n, seed);
	std::string warning;
	const auto orders = presentationOrders(n, participants, seed, labels.empty() ? nullptr : &labels, &warning);
	if (!warning.empty()) std::fprintf(stderr, "talkhead: warning: --no-repeat: %s\n", warning.c_str());

	BatchRun run(m, ids, progressMode != "bar");
	run.out = out, run.threads = threads, run.progressMode = progressMode, run.shard = shard, run.shards = shards;
	std::error_code ec;
	fs::create_directories(out, ec);
	if (ec) throw Error(out, 0, "cannot create folder: " + ec.message());
	run.keyPath = (fs::path(out) / "key.csv").string();
	run.previous = readKeyChecksums(run.keyPath);
	run.inShard = n / shards + (shard < n % shards ? 1 : 0);
	assignSides(m, seed);
	for (const BatchRow& row : m.rows) run.row(row);
	run.bar.finish();
	writeFileAtomically(run.keyPath, keyCsv(m, ids, run.results));
	const int width = participants >= 100 ? 3 : 2;
	for (std::size_t q = 0; q < orders.size(); ++q) {
		char name[32];
		std::snprintf(name, sizeof name, "order-%0*zu.csv", width, q + 1);
		writeFileAtomically((fs::path(out) / name).string(), orderCsv(orders[q], ids, run.results));
	}
	if (args.has("--player") || args.has("--player-replays") || args.has("--player-lang")) {
		const std::string lang = args.get("--player-lang", "en");
		if (lang != "en" && lang != "pt") throw UsageError("batch: --player-lang takes en or pt");
		const int replays = int(args.number("--player-replays", 0, 0, 10));
		writeFileAtomically((fs::path(out) / "index.html").string(), playerHtml(ids, run.results, orders, replays, lang));
	}
	run.summary(orders.size());
	return run.failed ? 1 : 0;
}

}  // namespace talkhead::cli
