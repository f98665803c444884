#!/usr/bin/env bash
# Issue 44 (D74): the same bytes whatever the CPU's vector width. This build (portable x86-64-v3) and a
# second build of another -march (native: AVX-512 on a machine that has it; cli.width_build makes it), and
# this build with its run-time kernels forced down (the scalar warp; OpenCV's AVX/AVX2/AVX-512 paths off),
# make the same models and draw the same frames, byte for byte: the default face, a synthetic face built by
# each, a face from a real video (the frames `corpus from-video` chooses), and a corpus of two takes with an
# emotion change. Any float sum that rounds by the vector width, an FMA the compiler fused in one build
# only, or a kernel chosen at run time that rounds its own way shows up here as a differing byte.
#   cross_width_test.sh TALKHEAD OTHER_WIDTH_TALKHEAD TEST_DATA SHARED_DATA
set -euo pipefail
TH=$1; TW=$2; DATA=$3; SHARED=$4
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
trap 'echo "cross_width_test.sh: failed at line $LINENO: $BASH_COMMAND" >&2' ERR
[ -x "$TW" ] || { echo "no second-width build at $TW (cli.width_build makes it)"; exit 1; }
echo "this build: $("$TH" --version); the other: $("$TW" --version)"
"$TH" --version | grep -q "built for x86-64-v3\|built for native"
# Forced-down kernels: every OpenCV feature above its Debian baseline (SSE2) off, and the scalar warp.
down() { env TALKHEAD_SCALAR_WARP=1 OPENCV_CPU_DISABLE=AVX512F,AVX512-SKX,AVX512-COMMON,AVX512BW,AVX512CD,AVX512DQ,AVX512VL,AVX2,FMA3,FP16,AVX,POPCNT,SSE4.2,SSE4.1,SSSE3,SSE3 "$TH" "$@"; }
same() {  # same FILE_A FILE_B WHAT
	if cmp -s "$1" "$2"; then echo "   same bytes: $3 ($(du -k "$1" | cut -f1) KiB)"; return; fi
	echo "FAIL: $3 differs between the builds: $(cmp "$1" "$2" | head -1)"; exit 1
}
same_dir() {  # every file of two folders, byte for byte
	(cd "$1" && find . -type f | sort) >"$T/la"; (cd "$2" && find . -type f | sort) >"$T/lb"
	cmp -s "$T/la" "$T/lb" || { echo "FAIL: $3: the builds wrote different files"; diff "$T/la" "$T/lb" | head; exit 1; }
	while IFS= read -r f; do cmp -s "$1/$f" "$2/$f" || { echo "FAIL: $3: $f differs"; exit 1; }; done <"$T/la"
	echo "   same bytes: $3 ($(wc -l <"$T/la") files)"
}
TG=$DATA/transcripts/que_noticia.TextGrid

# 1. The default face, as each build and the forced-down kernels draw it.
"$TH" render -q --transcript "$TG" --emotion joy --format y4m -o "$T/d1.y4m"
"$TW" render -q --transcript "$TG" --emotion joy --format y4m -o "$T/d2.y4m"
down render -q --transcript "$TG" --emotion joy --format y4m -o "$T/d3.y4m"
same "$T/d1.y4m" "$T/d2.y4m" "the default face's frames, other width"
same "$T/d1.y4m" "$T/d3.y4m" "the default face's frames, scalar warp and OpenCV's baseline kernels"

# 2. A synthetic face built by each (the PCA's products), and its frames.
"$TH" corpus synth -q -o "$T/c" --size 320x180 --emotions neutral,joy,anger
"$TH" build -q "$T/c/corpus.csv" -o "$T/s1.thm"
"$TW" build -q "$T/c/corpus.csv" -o "$T/s2.thm"
same "$T/s1.thm" "$T/s2.thm" "a model built from the synthetic corpus"
"$TH" corpus au-appearance -q "$T/c/corpus.csv" -o "$T/au1.bin"
"$TW" corpus au-appearance -q "$T/c/corpus.csv" -o "$T/au2.bin"
same "$T/au1.bin" "$T/au2.bin" "the action units' skin maps learned from it"
"$TH" render -q --model "$T/s1.thm" --transcript "$TG" --emotion anger --format y4m -o "$T/s1.y4m"
"$TW" render -q --model "$T/s1.thm" --transcript "$TG" --emotion anger --format y4m -o "$T/s2.y4m"
same "$T/s1.y4m" "$T/s2.y4m" "its frames"

G=$SHARED/grid
if [ ! -f "$G/bbaf2n.mpg" ]; then echo "skipped the rest: no shared data in $SHARED (grid/)"; exit 77; fi
# 3. A face from a real video: the frames `corpus from-video` chooses (tracking, scores, colour gains),
# the model, the frames drawn.
"$TH" corpus from-video "$G/bbaf2n.mpg" --text "bin blue at f two now" --lang en-US -o "$T/v1" -q
"$TW" corpus from-video "$G/bbaf2n.mpg" --text "bin blue at f two now" --lang en-US -o "$T/v2" -q
same_dir "$T/v1" "$T/v2" "a corpus from a GRID clip"
"$TH" build -q "$T/v1/corpus.csv" -o "$T/v1.thm"
"$TW" build -q "$T/v1/corpus.csv" -o "$T/v2.thm"
same "$T/v1.thm" "$T/v2.thm" "its model"
"$TH" render -q --model "$T/v1.thm" --transcript "$G/swwp2s.align" --format y4m -o "$T/v1.y4m"
"$TW" render -q --model "$T/v1.thm" --transcript "$G/swwp2s.align" --format y4m -o "$T/v2.y4m"
down render -q --model "$T/v1.thm" --transcript "$G/swwp2s.align" --format y4m -o "$T/v3.y4m"
same "$T/v1.y4m" "$T/v2.y4m" "its frames, other width"
same "$T/v1.y4m" "$T/v3.y4m" "its frames, forced-down kernels"

# 4. Two takes of one speaker (the second brighter, as another session would be), one model of both
# emotions, a sentence with an emotion change: colour matching, exemplar choice and the dissolve.
ffmpeg -v error -i "$G/lbax4n.mpg" -vf "eq=brightness=0.06:gamma_r=1.15" -c:v libx264 -crf 12 -an "$T/bright.mp4"
printf 'video\temotion\n%s\tneutral\nbright.mp4\tjoy\n' "$G/bbaf2n.mpg" >"$T/takes.tsv"
"$TH" corpus from-video --takes "$T/takes.tsv" -o "$T/t1" -q
"$TW" corpus from-video --takes "$T/takes.tsv" -o "$T/t2" -q
same_dir "$T/t1" "$T/t2" "a corpus of two takes"
"$TH" build -q "$T/t1/corpus.csv" -o "$T/t.thm"
printf '{"events": [{"type": "emotion", "time": 0, "emotion": "neutral", "intensity": 1, "ramp": 0}, {"type": "emotion", "time": 0.5, "emotion": "joy", "intensity": 1, "ramp": 0.3}]}\n' >"$T/change.json"
"$TH" render -q --model "$T/t.thm" --transcript "$G/swwp2s.align" --controls "$T/change.json" --format y4m -o "$T/t1.y4m"
"$TW" render -q --model "$T/t.thm" --transcript "$G/swwp2s.align" --controls "$T/change.json" --format y4m -o "$T/t2.y4m"
down render -q --model "$T/t.thm" --transcript "$G/swwp2s.align" --controls "$T/change.json" --format y4m -o "$T/t3.y4m"
same "$T/t1.y4m" "$T/t2.y4m" "the takes face's frames across an emotion change, other width"
same "$T/t1.y4m" "$T/t3.y4m" "the same, forced-down kernels"
echo "cross-width tests passed"
