#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Real faces that talk (issue 10 §5), with talkhead's own commands only:
#   1. a model of franck from franck/franck.mp4 (landmarks tracked with dlib, frames chosen by mouth shape),
#      drawn with `talkhead inspect -o`;
#   2. franck saying each of the 11 GRID sentences with that clip's own audio, aligned by `talkhead align`
#      from the sentence text (spelled by the file name);
#   3. `talkhead compare` of each against the real GRID speaker (Hermite, linear and monotone trajectories), and
#      the mean;
#   4. held-out reconstruction: a model of the first 150 s, frames of the last 50 s reconstructed.
# Reads ../shared/data (research-use data: nothing of it, nor anything built from it, is committed) and writes
# to out/real-face/ (or $1).
#
# usage: examples/real-face/run.sh [OUT_DIR]        (TALKHEAD=path/to/talkhead, SHARED_DATA=path/to/data)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
DATA=${SHARED_DATA:-$root/../shared/data}
OUT=${1:-$root/out/real-face}
[ -x "$TH" ] || { echo "run.sh: $TH not built (scripts/build)" >&2; exit 1; }
[ -f "$DATA/franck/franck.mp4" ] || { echo "run.sh: no $DATA/franck/franck.mp4 (the shared data folder)" >&2; exit 77; }
mkdir -p "$OUT"
log() { echo "== $*" >&2; }

# 1. franck: landmarks of the whole video, a corpus chosen by mouth shape, the model.
if [ ! -f "$OUT/franck-landmarks/landmarks.tsv" ]; then
	log "landmarks of franck.mp4 (4800 frames)"
	"$TH" corpus landmarks "$DATA/franck/franck.mp4" -o "$OUT/franck-landmarks" --sheet 36 --no-pts
fi
log "corpus by mouth shape"
"$TH" corpus from-video "$DATA/franck/franck.mp4" --landmarks "$OUT/franck-landmarks/landmarks.tsv" --select-by-shape -o "$OUT/franck-corpus"
"$TH" build -q "$OUT/franck-corpus/corpus.csv" -o "$OUT/franck.thm"
"$TH" inspect "$OUT/franck.thm" -o "$OUT/franck-model" >"$OUT/franck-model.txt"

# 2–3. The GRID sentences, aligned, rendered, compared.
source "$root/examples/real-face/grid-words.sh"
mkdir -p "$OUT/grid"
printf 'clip\tsentence\talign_confidence\tr_hermite\tr_linear\tr_monotone\tr_best_hermite\tlag_ms\tlmd\n' >"$OUT/grid/results.tsv"
for clip in "$DATA"/grid/*.mpg; do
	base=$(basename "$clip" .mpg)
	name=${base##*_}
	text=$(grid_words "$name")
	log "$base: \"$text\""
	"$TH" align "$clip" --text "$text" --lang en-US -o "$OUT/grid/$base.TextGrid" 2>"$OUT/grid/$base.align.txt"
	conf=$(grep -o 'confidence [0-9.]*' "$OUT/grid/$base.align.txt" | tail -1 | cut -d' ' -f2)
	for traj in hermite linear monotone; do
		"$TH" render -q --model "$OUT/franck.thm" --transcript "$OUT/grid/$base.TextGrid" --audio "$clip" --lang en-US --fps 25 \
			--trajectory "$traj" -o "$OUT/grid/$base.$traj.mp4"
		"$TH" compare --json "$OUT/grid/$base.$traj.mp4" "$clip" >"$OUT/grid/$base.$traj.json"
	done
	get() { sed -E "s/.*\"$2\": ([-0-9.null]+).*/\1/" "$OUT/grid/$base.$1.json"; }
	printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$base" "$text" "$conf" "$(get hermite r_lag0)" "$(get linear r_lag0)" "$(get monotone r_lag0)" "$(get hermite r_best)" \
		"$(get hermite best_lag_ms)" "$(get hermite lmd)" >>"$OUT/grid/results.tsv"
done
awk -F'\t' 'NR > 1 { h += $4; l += $5; m += $6; n++ } END { printf "mean\t(%d clips)\t\t%.3f\t%.3f\t%.3f\n", n, h / n, l / n, m / n }' "$OUT/grid/results.tsv" >>"$OUT/grid/results.tsv"
column -t -s $'\t' "$OUT/grid/results.tsv"

# A frame grid of franck talking (every 3rd frame of the first clip).
first=$(ls "$OUT"/grid/*.hermite.mp4 | head -1)
"$TH" render -q --model "$OUT/franck.thm" --transcript "${first%.hermite.mp4}.TextGrid" --audio "$DATA/grid/$(basename "${first%.hermite.mp4}").mpg" \
	--lang en-US --fps 25 --frames "$OUT/talking-frames" -o "$OUT/talking-frames.mp4"
if command -v ffmpeg >/dev/null; then
	ffmpeg -v error -y -framerate 25 -i "$OUT/talking-frames/frame_%06d.png" -vf "select=not(mod(n\,3)),scale=240:-2,tile=6x4" -frames:v 1 "$OUT/franck-talking.png" || true
fi

# 4. Held-out reconstruction: build on the first 150 s, reconstruct frames chosen from the last 50 s.
log "held-out reconstruction"
"$TH" corpus from-video "$DATA/franck/franck.mp4" --select-by-shape --duration 150 -o "$OUT/franck-first150" -q
"$TH" corpus from-video "$DATA/franck/franck.mp4" --select-by-shape --start 150 -o "$OUT/franck-last50" -q
"$TH" build -q "$OUT/franck-first150/corpus.csv" -o "$OUT/franck-first150.thm"
# Each held-out frame once (one frame may stand for several CDVs).
awk -F, '/^#/ || !seen[$1]++' "$OUT/franck-last50/corpus.csv" >"$OUT/franck-last50/unique.csv"
"$TH" inspect "$OUT/franck-first150.thm" --recon "$OUT/franck-last50/unique.csv" | tee "$OUT/heldout-recon.txt"
log "done: $OUT"
