// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdint>
#include <map>
#include <stdexcept>

#include "base/error.h"
#include "perform/job.h"
#include "phonetics/emotion.h"
#include <optional>
#include <functional>
#include <string>
#include <vector>

namespace talkhead {

// Perceptual-test stimuli (issue 14; decision D51): a manifest of stimuli, their blind IDs, the key and
// balanced presentation orders. Rendering each row is the CLI's `talkhead batch` (it runs the row's
// `say` or `render` in process).
//
// A manifest is CSV (a header row, then one row per stimulus) or JSON (an array of objects, or
// {"stimuli": [...]}); the columns (README "Perceptual-test stimuli"):
//   text, transcript, audio, lang, voice, model, emotion (LABEL or LABEL:I), intensity, muted, fps, size,
//   trajectory, dissolve, warp, resampling, pauses, blinks, head-motion, speech-brows, emotion-source,
//   au-appearance, controls, seed, rate, pitch, crf, lead-in, tail, av-offset (ms), drive (a video: render --drive), drive-mouth (yes: the
//   mouth from it too, no text or transcript); and free annotations: condition, and any column
//   starting with "x-" (kept in the key). `versus:COLUMN` columns (model, emotion, intensity, trajectory,
//   dissolve, warp, resampling, pauses, blinks, head-motion, speech-brows, emotion-source, au-appearance,
//   controls, seed, components; "default" = the option's default) make the row a side-by-side stimulus: the row as
//   written on one side, with those columns replaced on the other.
// A row with a transcript (or text + audio, or a drive video) is a `render`, one with text alone a `say`.
// A row's job is its fields in the row command's words (perform/job.h): the command line hands it to the
// row's child process as JSON (cmd_batch.cpp); the library never spells a flag.
struct BatchRow {
	std::size_t index = 0;  // 0-based
	long line = 0;          // CSV line / JSON item number (1-based), for messages
	std::map<std::string, std::string> fields;  // column → value (empty values left out)
	std::string command;                        // "say" or "render"
	std::vector<JobField> job;                  // what the command is to do (without its output)
	std::string emotion = Emotion::neutralLabel();            // canonical
	// Side-by-side (any `versus:COLUMN`): the other side's arguments (the row's with those columns
	// replaced), and which side it is on (assignSides).
	bool sideBySide = false;
	std::vector<JobField> versusJob;
	bool versusLeft = false;
};

struct Manifest {
	std::string path;
	std::vector<std::string> columns;  // in file order
	std::vector<BatchRow> rows;
};

// Every problem of a manifest at once: each message "MANIFEST:LINE:COLUMN: what".
struct ManifestErrors : Error {
	std::vector<std::string> messages;
	explicit ManifestErrors(std::vector<std::string> m);
};

// Parses and validates a manifest: unknown columns, emotions and values, missing files (relative paths
// resolve against the manifest's folder), rows without text or transcript. Throws ManifestErrors.
Manifest parseManifest(const std::string& text, const std::string& path);
Manifest loadManifest(const std::string& path);
// What needs the models: every `components` region exists in its row's model (each model's render parts
// loaded once; a row's `face` is a model through faceModel, the caller's: built if need be). Throws
// ManifestErrors.
void checkManifestModels(const Manifest& m, const std::function<std::string(const std::string&)>& faceModel = {});

// Blind IDs: "S" + 6 base-32 characters per row, from the seed and the row's position only (never from
// its conditions), all distinct.
std::vector<std::string> blindIds(std::size_t rows, std::uint64_t seed);

// One presentation order per participant (indices into the rows): a Williams design (Williams 1949; each
// row of a balanced Latin square: every stimulus equally often in every position over each n participants
// — 2n for odd n — and every ordered pair of neighbours equally often), its stimuli relabelled by a seeded
// permutation. With `noRepeat` (one label per stimulus, e.g. the emotion) the permutation is chosen among
// seeded candidates so that no order shows the same label twice in a row; *warning says when none could.
std::vector<std::vector<std::size_t>> presentationOrders(std::size_t n, std::size_t participants, std::uint64_t seed,
                                                         const std::vector<std::string>* noRepeat = nullptr, std::string* warning = nullptr);

// The side of each side-by-side row's `versus` variant, from the seed and the rows' positions only,
// balanced: the versus variant is on the left in half of the side-by-side rows (± 1), chosen at random.
void assignSides(Manifest& m, std::uint64_t seed);

// key.csv: id, row, status, sha256, file, (left, right: "row" or "versus", when the manifest has
// side-by-side rows), then every manifest column (RFC 4180 quoting).
struct StimulusResult {
	std::string status;  // ok (complete, now or before), failed, not-in-shard
	std::string sha256, file, message;
};
std::string keyCsv(const Manifest& m, const std::vector<std::string>& ids, const std::vector<StimulusResult>& results);
// Reads a key.csv written before: id → sha256 (for resuming); empty when the file is missing.
std::map<std::string, std::string> readKeyChecksums(const std::string& path);
// `talkhead batch --merge OUTDIR SHARD_DIR…`: the shards' key.csv must come from the same manifest and seed
// (same rows, IDs and conditions) and their orders must agree; every stimulus complete in some shard is
// checked against its SHA-256 and copied (with its sidecar) into OUTDIR, whose key.csv then holds them all.
// Returns the number of stimuli no shard has (0: the merge is complete). Throws Error naming the shard.
std::size_t mergeShards(const std::string& outDir, const std::vector<std::string>& shardDirs);

// index.html, the browser test player (no server, network, external scripts or fonts): the thesis's
// protocol (Costa 2015 §6.2) — a participant number picks the order; each stimulus plays, then the
// valence question (negative / neutral / positive / no opinion), then it plays again and the emotion
// question (the thesis's 22 voting terms, Table 6.1, or "none of the above"); answers only after the clip
// ended, confirmed; `replays` extra plays allowed per question; response times from the clip's end; the
// answers download as CSV (participant, position, id, valence, valence_ms, emotion, emotion_ms, with the
// emotion as its canonical label). Keyboard only works (radio groups, arrows, Enter). lang: en or pt.
std::string playerHtml(const std::vector<std::string>& ids, const std::vector<StimulusResult>& results,
                       const std::vector<std::vector<std::size_t>>& orders, int replays, const std::string& lang);

// `talkhead batch --score ANSWERS.csv… --key key.csv`: the player's answers against the key. Per true
// emotion (the key's emotion column; neutral where empty) and per condition (the key's condition column,
// if any): answers, and how many named the emotion; the confusion counts (true emotion × answer, the
// answers being the 22 terms or "none"). Throws Error naming the file and line of a bad answer.
struct Score {
	std::vector<std::string> truths, answers;           // row and column labels, in the thesis's order
	std::vector<std::vector<int>> confusion;            // truths × answers
	std::map<std::string, std::pair<int, int>> byCondition;  // condition → (correct, answered)
	int correct = 0, answered = 0;
};
Score scoreAnswers(const std::string& keyPath, const std::vector<std::string>& answerPaths);
// The report (plain text): recognition per emotion and per condition, and overall.
std::string scoreReport(const Score& s);
// The confusion matrix as a picture (rows: true emotion; columns: answer; shade = share of the row).
void writeConfusionPng(const Score& s, const std::string& path);

// order-NN.csv: position (1-based), id, file.
std::string orderCsv(const std::vector<std::size_t>& order, const std::vector<std::string>& ids, const std::vector<StimulusResult>& results);

}  // namespace talkhead
