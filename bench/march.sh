#!/usr/bin/env bash
# Portable against native (issue 44, D74): the same work by two builds, alternating, medians — a 10-s
# utterance rendered to MP4 at 1280x720 (what a user waits for: x264 is the limit), the same drawn to y4m
# (drawing alone), and the default face's model built from its 782-image corpus (Eigen's GEMMs). Prints
# each median and the ratio B/A of the times (< 1: B is faster). Both draw with A's default face.
# usage: bench/march.sh [BUILD_A [BUILD_B [RUNS]]]   default: build (portable) and build/width-native
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
a="${1:-$root/build}"; b="${2:-$root/build/width-native}"; runs="${3:-5}"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
export TALKHEAD_MODEL="$a/models/default.thm"
corpus="$a/models/default-corpus/corpus.csv"
[ -f "$TALKHEAD_MODEL" ] && [ -f "$corpus" ] || { echo "no default face in $a/models"; exit 1; }
/usr/bin/python3 "$root/bench/make_utterance.py" 10 "$tmp/u10.tsv"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(grep -c avx512f /proc/cpuinfo | sed 's/^0$/no AVX-512/;s/^[1-9][0-9]*$/AVX-512/')"
echo "A: $a ($("$a/talkhead" --version))"
echo "B: $b ($("$b/talkhead" --version))"
"$a/talkhead" inspect -q >/dev/null  # the model in the page cache
median() { sort -n "$1" | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
compare() {  # LABEL RUNS COMMAND… (with @TH@ for the binary)
	local label=$1 n=$2; shift 2
	: >"$tmp/ta"; : >"$tmp/tb"
	for _ in $(seq 1 "$n"); do
		for side in a b; do
			local th; th=$([ $side = a ] && echo "$a/talkhead" || echo "$b/talkhead")
			/usr/bin/time -f "%e" -o "$tmp/t" "${@/@TH@/$th}" >/dev/null 2>"$tmp/err" || { cat "$tmp/err"; exit 1; }
			cat "$tmp/t" >>"$tmp/t$side"
		done
	done
	awk -v l="$label" -v x="$(median "$tmp/ta")" -v y="$(median "$tmp/tb")" -v n="$n" \
		'BEGIN { printf "%-34s A %6.2f s   B %6.2f s   B/A %.3f   (median of %d, alternating)\n", l, x, y, y / x, n }'
}
compare "render 10 s, 1280x720, MP4" "$runs" @TH@ render --transcript "$tmp/u10.tsv" --emotion joy --size 1280x720 -o "$tmp/o.mp4" -q
compare "draw 10 s, 1280x720, y4m" "$runs" @TH@ render --transcript "$tmp/u10.tsv" --emotion joy --size 1280x720 --format y4m -o "$tmp/o.y4m" -q
compare "build the default face (782 images)" 3 @TH@ build -q "$corpus" -o "$tmp/m.thm"
