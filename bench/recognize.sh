#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Phones recognised from audio alone (issue 49, D95) against the timings others wrote for the same audio:
#   GRID         the 11 evaluation clips of ../shared/data/grid and grid-s4's 6 shipped clips, against GRID's
#                official word alignments: the speech's first and last edge (ms), bilabial-initial words
#                (bin, blue, by, place, please, b, p) whose /p b m/ was recognised within ±80 ms of the word's
#                start, and the median distance from a word boundary to the nearest recognised boundary;
#   real-inputs  the five recordings of ../shared/data/real-inputs-3/audio against their own files' word
#                times (whisper-timestamped, Gentle): the same median, and the pause edges (words ≥ 150 ms apart);
#   speed        the 11 GRID clips joined 20 times (11 min): seconds, × real time, peak memory.
# The lip-opening r of renders from audio alone is bench/coarticulation.sh's (WAYS="learned words audio").
#   bench/recognize.sh [OUT]    (needs ../shared/data and ffmpeg; build first)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
DATA=${SHARED_DATA:-$root/../shared/data}
OUT=${1:-${TMPDIR:-/tmp}/talkhead-recognize}
[ -d "$DATA/grid" ] || { echo "recognize.sh: no $DATA/grid" >&2; exit 77; }
mkdir -p "$OUT"
labels="$DATA/open-av/grid/labels-for-shared-grid"
: >"$OUT/grid.tsv"
for clip in "$DATA"/grid/*.mpg "$root"/models/faces/grid-s4/*.mpg; do
	base=$(basename "$clip" .mpg); name=${base##*_}
	align=$(ls "$labels/"*"_${name}.align" "$(dirname "$clip")/"*"_${name}.align" 2>/dev/null | head -1 || true)
	"$TH" visemes --audio "$clip" -o "$OUT/$base.tsv" 2>/dev/null
	printf '%s\t%s\t%s\n' "$base" "$align" "$OUT/$base.tsv" >>"$OUT/grid.tsv"
done
: >"$OUT/real.tsv"
for a in "$DATA"/real-inputs-3/audio/*.mp3; do
	base=$(basename "$a" .mp3)
	case $base in wts_*) words=$(ls "$DATA/real-inputs-3/in/${base}"*.words.json | head -1) ;; gentle_*) words="$DATA/real-inputs-3/in/$base.json" ;; esac
	"$TH" visemes --audio "$a" -o "$OUT/$base.tsv" 2>"$OUT/$base.err" || true
	printf '%s\t%s\t%s\n' "$base" "$words" "$OUT/$base.tsv" >>"$OUT/real.tsv"
done
/usr/bin/python3 - "$OUT" <<'PY'
import json, sys
import numpy as np
out = sys.argv[1]
def phones(path):
    rows = [l.rstrip("\n").split("\t") for l in open(path)][1:]
    return [(float(r[0]), float(r[1]), r[2]) for r in rows]
def bounds(ph):
    return np.array(sorted({round(a, 3) for a, b, p in ph} | {round(b, 3) for a, b, p in ph}))
def nearest(b, t):
    return float(np.min(np.abs(b - t))) if len(b) else float("nan")
BILABIAL_WORDS = {"bin", "blue", "by", "place", "please", "b", "p"}
edges, near, hit, n = [], [], 0, 0
print("clip\tfirst edge ms\tlast edge ms\tbilabial words\tmedian boundary ms")
for base, align, tsv in (l.rstrip("\n").split("\t") for l in open(f"{out}/grid.tsv")):
    words = []
    for l in open(align):
        a, b, w = l.split()
        if w not in ("sil", "sp"): words.append((int(a) / 25000, int(b) / 25000, w))
    ph = phones(tsv); sp = [p for p in ph if p[2] != "_"]
    e1 = (sp[0][0] - words[0][0]) * 1000 if sp else float("nan"); e2 = (sp[-1][1] - words[-1][1]) * 1000 if sp else float("nan")
    edges += [abs(e1), abs(e2)]
    b = bounds(ph); d = [nearest(b, t) for w in words for t in (w[0], w[1])]; near += d
    h = m = 0
    for a, _, w in words:
        if w in BILABIAL_WORDS:
            m += 1; h += any(p[2] in ("p", "b", "m") and abs(p[0] - a) <= 0.08 for p in sp)
    hit += h; n += m
    print(f"{base}\t{e1:+.0f}\t{e2:+.0f}\t{h}/{m}\t{1000 * np.median(d):.0f}")
print(f"GRID: speech edges median {np.median(edges):.0f} ms (p90 {np.percentile(edges, 90):.0f}); bilabial-initial words {hit}/{n}; "
      f"word boundary to nearest recognised boundary median {1000 * np.median(near):.0f} ms")
print()
print("recording\twords\tmedian boundary ms\tpause edges median ms")
for base, words_path, tsv in (l.rstrip("\n").split("\t") for l in open(f"{out}/real.tsv")):
    d = json.load(open(words_path))
    if "segments" in d: words = [(w["start"], w["end"]) for s in d["segments"] for w in s.get("words", [])]
    else: words = [(w["start"], w["end"]) for w in d["words"] if w.get("case") == "success"]
    try: ph = phones(tsv)
    except Exception: print(f"{base}\t{len(words)}\t(refused: {open(tsv.replace('.tsv', '.err')).read().strip()})"); continue
    b = bounds(ph); sp = [p for p in ph if p[2] != "_"]
    d = [nearest(b, t) for w in words for t in w]
    # Pause edges: speech/pause changes of the recognised phones against the words' (gaps ≥ 150 ms).
    pe = [] if not sp else [sp[0][0]] + [x for i in range(1, len(sp)) if sp[i][0] - sp[i - 1][1] >= 0.15 for x in (sp[i - 1][1], sp[i][0])] + [sp[-1][1]]
    we = [] if not words else [words[0][0]] + [x for i in range(1, len(words)) if words[i][0] - words[i - 1][1] >= 0.15 for x in (words[i - 1][1], words[i][0])] + [words[-1][1]]
    pd = [nearest(np.array(pe), t) for t in we] if pe else []
    print(f"{base}\t{len(words)}\t{1000 * np.median(d):.0f}" if d else f"{base}\t0\t-", end="")
    print(f"\t{1000 * np.median(pd):.0f} ({len(we)} edges, {len(pe)} recognised)" if pd else "\t-")
PY
# Speed and memory over 11 minutes.
if command -v ffmpeg >/dev/null; then
	for c in "$DATA"/grid/*.mpg; do echo "file '$c'"; done >"$OUT/list.txt"
	ffmpeg -loglevel error -y -f concat -safe 0 -i "$OUT/list.txt" -ac 1 -ar 16000 "$OUT/once.wav"
	for i in $(seq 20); do echo "file '$OUT/once.wav'"; done >"$OUT/list20.txt"
	ffmpeg -loglevel error -y -f concat -safe 0 -i "$OUT/list20.txt" -c copy "$OUT/long.wav"
	for f in once long; do
		/usr/bin/time -f "%e %M" -o "$OUT/$f.time" "$TH" visemes --audio "$OUT/$f.wav" -o /dev/null 2>/dev/null
		read -r s kb <"$OUT/$f.time"
		d=$(ffprobe -v error -show_entries format=duration -of csv=p=0 "$OUT/$f.wav")
		/usr/bin/python3 -c "print('speed: $f.wav %.0f s of audio in %.1f s: %.1fx real time, peak memory %.0f MB' % ($d, $s, $d / $s, $kb / 1024))"
	done
fi
