#!/usr/bin/env bash
# Issue 15: a signal mid-run leaves nothing behind. render (MP4 + landmarks, then y4m) and say are started,
# stopped by SIGINT / SIGTERM / SIGHUP once their first progress line is out, and must exit at once with
# 128 + the signal, say "talkhead: interrupted", and leave no output and no temporary in the folder.
set -euo pipefail
TH=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
# 60 s of speech-like phones: long enough that the render is still running when the signal comes.
/usr/bin/python3 - "$T/long.tsv" <<'PY'
import sys
phones = "p a t a k a m i s u".split()
with open(sys.argv[1], "w") as f:
    t = 0.0
    while t < 60:
        for p in phones:
            f.write(f"{t:.3f}\t{t + 0.1:.3f}\t{p}\n"); t += 0.1
PY
stop() {  # stop SIGNAL CODE DIR -- COMMAND…: run, wait for progress, signal, check
	local sig=$1 code=$2 dir=$3; shift 4
	mkdir -p "$dir"
	# (Through python, which gives the command default signal handling: a background job of this script
	# would start with SIGINT ignored, and an ignored SIGINT rightly stays ignored.)
	/usr/bin/python3 -c 'import os, signal, sys
for s in (signal.SIGINT, signal.SIGHUP): signal.signal(s, signal.SIG_DFL)
os.execvp(sys.argv[1], sys.argv[1:])' "$@" --json-progress 2>"$dir.err" &
	local pid=$! i=0
	until grep -q '"type": "progress"' "$dir.err" 2>/dev/null; do
		sleep 0.05; i=$((i + 1))
		if [ $i -gt 600 ]; then echo "no progress within 30 s: $*"; kill -9 $pid; exit 1; fi
	done
	local t0; t0=$(date +%s%N)
	kill -s "$sig" $pid
	local rc=0; wait $pid || rc=$?
	local ms=$(( ($(date +%s%N) - t0) / 1000000 ))
	if [ "$rc" != "$code" ]; then echo "$sig: exit $rc, expected $code: $*"; cat "$dir.err"; exit 1; fi
	grep -qx 'talkhead: interrupted' "$dir.err" || { echo "$sig: no 'interrupted' line"; cat "$dir.err"; exit 1; }
	if [ $ms -gt 500 ]; then echo "$sig: took $ms ms to stop"; exit 1; fi
	local left; left=$(ls -A "$dir")
	if [ -n "$left" ]; then echo "$sig: left behind in $dir: $left"; exit 1; fi
}
stop INT 130 "$T/a" -- "$TH" render --transcript "$T/long.tsv" -o "$T/a/out.mp4" --landmarks-out "$T/a/points.tsv" --frames "$T/a/frames"
stop TERM 143 "$T/b" -- "$TH" render --transcript "$T/long.tsv" --format y4m -o "$T/b/out.y4m"
stop HUP 129 "$T/c" -- "$TH" say "$(printf 'Bom dia, vamos ver o resultado amanhã. %.0s' {1..12})" -o "$T/c/out.mp4" --save-audio "$T/c/speech.wav"
# batch: a side-by-side row (two children, a folder of y4m sides) stopped mid-render: the child stops too
# and no file is left (the output folder itself may stay, empty).
mkdir -p "$T/d"
printf 'transcript,versus:trajectory,size\n%s,linear,320x180\n' "$T/long.tsv" >"$T/d.csv"
/usr/bin/python3 -c 'import os, signal, sys
for s in (signal.SIGINT, signal.SIGHUP): signal.signal(s, signal.SIG_DFL)
os.execvp(sys.argv[1], sys.argv[1:])' "$TH" batch "$T/d.csv" -o "$T/d/out" 2>"$T/d.err" &
pid=$!; i=0
until [ -n "$(find "$T/d/out" -name '.tmp-*' -type d 2>/dev/null)" ] && [ -n "$(find "$T/d/out" -name '.tmp-*.y4m' 2>/dev/null)" ]; do
	sleep 0.05; i=$((i + 1)); [ $i -lt 600 ] || { echo "batch: no side being rendered within 30 s"; kill -9 $pid; exit 1; }
done
sleep 0.3
kill -s INT $pid
rc=0; wait $pid || rc=$?
[ "$rc" = 130 ] || { echo "batch: exit $rc, expected 130"; cat "$T/d.err"; exit 1; }
sleep 0.2
left=$(find "$T/d" -mindepth 1 ! -type d)
[ -z "$left" ] && [ -z "$(find "$T/d/out" -mindepth 1 2>/dev/null)" ] || { echo "batch: left behind: $left $(find "$T/d/out" -mindepth 1)"; exit 1; }
pgrep -f "$T/d/out" >/dev/null && { echo "batch: a child is still running"; exit 1; }
# corpus synth: all or nothing (its staged folder goes, with the images already in it).
/usr/bin/python3 -c 'import os, signal, sys
for s in (signal.SIGINT, signal.SIGHUP): signal.signal(s, signal.SIG_DFL)
os.execvp(sys.argv[1], sys.argv[1:])' "$TH" corpus synth -o "$T/e/corpus" --size 512x512 2>"$T/e.err" &
pid=$!; i=0
mkdir -p "$T/e"
until [ "$(find "$T/e" -name '*.png' 2>/dev/null | head -3 | wc -l)" -ge 3 ]; do
	sleep 0.05; i=$((i + 1)); [ $i -lt 600 ] || { echo "corpus synth: no image within 30 s"; kill -9 $pid; exit 1; }
done
kill -s TERM $pid
rc=0; wait $pid || rc=$?
[ "$rc" = 143 ] || { echo "corpus synth: exit $rc, expected 143"; cat "$T/e.err"; exit 1; }
[ -z "$(ls -A "$T/e")" ] || { echo "corpus synth: left behind: $(ls -A "$T/e")"; exit 1; }
# An ignored SIGINT (a background job) stays ignored: the render goes on and completes.
"$TH" render --transcript "$T/long.tsv" --size 320x180 -o "$T/ignored.mp4" --json-progress 2>"$T/ignored.err" &
pid=$!; i=0
until grep -q '"type": "progress"' "$T/ignored.err" 2>/dev/null; do sleep 0.05; i=$((i + 1)); [ $i -lt 600 ] || { echo "no progress"; exit 1; }; done
kill -s INT $pid 2>/dev/null || true
rc=0; wait $pid || rc=$?
if [ "$rc" != 0 ] || [ ! -s "$T/ignored.mp4" ]; then echo "an ignored SIGINT stopped the render (exit $rc)"; exit 1; fi
echo "interrupt: ok"
