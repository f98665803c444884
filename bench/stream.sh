#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# A streamed speak with its text against aligning the whole (issue 49 part 2, D97/D98): GRID clips streamed
# in 0.2-s pieces (GRID's fluent read speech: no pause to cut at), their words from the official alignments.
# Per clip: when the first part came out, the parts, the same phones as the whole alignment or not, and
# how far the phones' starts lie from the whole's. The 6 grid-s4 clips shipped in models/ and the 11 of
# ../shared/data/grid (skipped when absent).
#   bench/stream.sh [BUILD_DIR] [PIECE_SECONDS]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=${1:-$root/build}
piece=${2:-0.2}
DATA=${SHARED_DATA:-$root/../shared/data}
[ -x "$build/bench/bench_stream" ] || { echo "stream.sh: build the benches first ($build/bench/bench_stream)" >&2; exit 1; }
args=()
words() { awk '$3 != "sil" && $3 != "sp" { printf "%s%s", sep, $3; sep = " " } END { print "" }' "$1"; }
for clip in "$root"/models/faces/grid-s4/*.mpg "$DATA"/grid/*.mpg; do
	[ -f "$clip" ] || continue
	base=$(basename "$clip" .mpg); name=${base##*_}
	align=$(ls "$(dirname "$clip")/"*"_${name}.align" "$DATA/open-av/grid/labels-for-shared-grid/"*"_${name}.align" 2>/dev/null | head -1 || true)
	[ -n "$align" ] || continue
	args+=("$clip" "$(words "$align")")
done
exec "$build/bench/bench_stream" "$piece" "${args[@]}"
