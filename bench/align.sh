#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Forced alignment (talkhead align, docs/decisions.md D30): accuracy and speed.
#   bench/align.sh [BUILD_DIR] [SHARED_DATA]
# Prints: the GRID clip's word-boundary errors against its alignment, the espeak-ng self-generated set's
# phone-boundary errors (pt-BR, en-US; from the unit test, which prints them), the speed as a fraction of
# the audio's duration, the confidence of every GRID clip with its own sentence, another clip's sentence
# and an unrelated one. TALKHEAD_ALIGN_TUNE="name=value,…" (see tests/align/align_test.cpp) varies the
# method's parameters for the unit-test part.
set -euo pipefail
B=${1:-build}
DATA=${2:-../shared/data}
TH=$B/talkhead
GRID=$DATA/grid
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT

echo "== espeak-ng speech of other voices, rates and pitches (24 utterances per language)"
"$B/tests/talkhead_tests" --gtest_filter='AlignEspeak.*:AlignGrid.*' | grep -a '^\[ \(espeak\|GRID\)'

if [ ! -d "$GRID" ]; then echo "GRID data not found in $GRID: skipping the rest"; exit 0; fi
sentence() {  # GRID file names spell their sentences (../shared/data/README.md)
	local n=$1 w=()
	case ${n:0:1} in b) w+=(bin) ;; l) w+=(lay) ;; p) w+=(place) ;; s) w+=(set) ;; esac
	case ${n:1:1} in b) w+=(blue) ;; g) w+=(green) ;; r) w+=(red) ;; w) w+=(white) ;; esac
	case ${n:2:1} in a) w+=(at) ;; b) w+=(by) ;; i) w+=(in) ;; w) w+=(with) ;; esac
	w+=("${n:3:1}")
	case ${n:4:1} in z) w+=(zero) ;; 1) w+=(one) ;; 2) w+=(two) ;; 3) w+=(three) ;; 4) w+=(four) ;; 5) w+=(five) ;;
		6) w+=(six) ;; 7) w+=(seven) ;; 8) w+=(eight) ;; 9) w+=(nine) ;; esac
	case ${n:5:1} in a) w+=(again) ;; n) w+=(now) ;; p) w+=(please) ;; s) w+=(soon) ;; esac
	echo "${w[*]}"
}
echo
echo "== speed: the GRID clip (2.98 s), 10 runs, one thread"
start=$(date +%s.%N)
for i in $(seq 10); do "$TH" align "$GRID/id2_vcd_swwp2s.mpg" --text "set white with p two soon" --lang en-US -o "$T/g.TextGrid" -q; done
end=$(date +%s.%N)
awk -v a="$start" -v b="$end" 'BEGIN { s = (b - a) / 10; printf "%.3f s per run (decoding included) = %.3f x the audio duration\n", s, s / 2.978 }'

echo
echo "== confidence: own sentence / another clip's sentence / an unrelated sentence"
files=("$GRID"/*.mpg)
n=${#files[@]}
conf() { "$TH" align "$1" --text "$2" --lang en-US --force -o "$T/c.TextGrid" 2>&1 | grep -o 'confidence [0-9.]*' | head -1 | cut -d' ' -f2; }
for ((i = 0; i < n; i++)); do
	f=${files[$i]}
	b=$(basename "$f" .mpg); b=${b#id2_vcd_}
	o=$(basename "${files[$(((i + 1) % n))]}" .mpg); o=${o#id2_vcd_}
	words=$("$TH" align "$f" --text "$(sentence "$b")" --lang en-US --force -o "$T/w.TextGrid" 2>/dev/null
	        awk '/name = "phones"/ { exit } /xmin = / { s = $3 } /xmax = / { e = $3 } /text = "[^"]/ { l = $3; gsub(/"/, "", l); printf "%s[%.2f-%.2f] ", l, s, e }' "$T/w.TextGrid")
	printf "%-7s %s / %s / %s   %s\n" "$b" "$(conf "$f" "$(sentence "$b")")" "$(conf "$f" "$(sentence "$o")")" \
		"$(conf "$f" "the quick brown fox jumps over the lazy dog")" "$words"
done
