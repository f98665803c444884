#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Measures the visual lead of the shipped coarticulation model (D104): how far a rendered mouth must move
# ahead of its keyposes (the phones' midpoints in the aligned audio) to follow the real speaker best.
# The aligner's times come late against the mouth (D104: GRID's own alignment needs no lead); corpus-tools/
# coarticulation-grid.sh writes the figure this prints into models/coarticulation/grid.tsv (its
# `visual_lead`), and every keypose of phones talkhead's aligner timed moves by it.
# Only the training clips (models/coarticulation/clips.tsv) are used — never the 11 evaluation clips of
# ../shared/data/grid. Each clip is rendered as the user gets it (the default face, no flags but the
# model, 640x360 at 25 frames/s) with a model learned WITHOUT its speaker and without a lead; the rendered
# video and the real one are tracked by dlib with no smoothing (`corpus landmarks --no-smooth`: the
# tracker's filter lags a slow mouth more than a fast one, and a viewer sees no filter); then the mean
# over clips of Pearson r between the two inner-lip openings is taken at each shift of the render, −80 …
# +80 ms in 5-ms steps. Prints the curve and the best shift, as the lead (seconds, < 0 = earlier).
#   corpus-tools/visual-lead.sh [--work DIR]      (~15 min on 2 cores; the work folder caches everything)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
DATA=${SHARED_DATA:-$root/../shared/data}
DEFAULT=${DEFAULT_MODEL:-$root/build/models/default.thm}
work=${TMPDIR:-/tmp}/talkhead-visual-lead
while [ $# -gt 0 ]; do
	case $1 in
		--work) work=$2; shift 2 ;;
		*) echo "visual-lead.sh: unknown argument '$1'" >&2; exit 2 ;;
	esac
done
[ -x "$TH" ] || { echo "visual-lead.sh: no talkhead at $TH (build first)" >&2; exit 1; }
[ -f "$DEFAULT" ] || { echo "visual-lead.sh: no default face at $DEFAULT (build first)" >&2; exit 1; }
[ -d "$DATA/av-candidates" ] && [ -d "$DATA/open-av" ] || { echo "visual-lead.sh: no GRID clips in $DATA" >&2; exit 77; }
mkdir -p "$work"
grid_work=${TMPDIR:-/tmp}/talkhead-coarticulation-grid  # coarticulation-grid.sh's alignments and tracks
speakers=$(tail -n +2 "$root/models/coarticulation/clips.tsv" | cut -f2 | sort -u)
for s in $speakers; do
	[ -f "$work/without-$s.tsv" ] || "$root/corpus-tools/coarticulation-grid.sh" --without "$s" --no-visual-lead -o "$work/without-$s.tsv" >/dev/null
done
list=$work/pairs.tsv; : >"$list"
n=0; total=$(tail -n +2 "$root/models/coarticulation/clips.tsv" | wc -l)
while IFS=$'\t' read -r clip speaker; do
	[ "$clip" = clip ] && continue
	base=$(basename "$clip" .mpg); c="$work/$base"; n=$((n + 1))
	[ -t 2 ] && printf '\rvisual-lead.sh: clip %d of %d' "$n" "$total" >&2
	if [ ! -f "$c.real/landmarks.tsv" ]; then
		rm -rf "$c.real"; "$TH" corpus landmarks "$DATA/$clip" -o "$c.real" --no-pts --no-smooth -q
	fi
	if [ ! -f "$c.render/landmarks.tsv" ]; then
		"$TH" render -q --model "$DEFAULT" --transcript "$grid_work/$base.TextGrid" --audio "$DATA/$clip" --lang en-US \
			--head-motion off --blinks off --no-audio --coarticulation "$work/without-$speaker.tsv" --fps 25 --size 640x360 -o "$c.mp4"
		rm -rf "$c.render"; "$TH" corpus landmarks "$c.mp4" -o "$c.render" --no-pts --no-smooth -q
		rm -f "$c.mp4"
	fi
	printf '%s\t%s\n' "$c.real/landmarks.tsv" "$c.render/landmarks.tsv" >>"$list"
done <"$root/models/coarticulation/clips.tsv"
[ -t 2 ] && echo >&2
/usr/bin/python3 - "$list" <<'PY'
import sys
import numpy as np

def opening(path):  # the mean gap of the three inner-lip pairs along the face's vertical, per eye distance
    rows = [l.rstrip("\n").split("\t") for l in open(path)]
    h, rows = rows[0], [r for r in rows[1:] if r[2] != "lost"]
    P = lambda n: np.array([[float(r[h.index(n + "_x")]), float(r[h.index(n + "_y")])] for r in rows])
    t = np.array([float(r[1]) for r in rows])
    a = (P("RE0") + P("RE3")) / 2; b = (P("LE0") + P("LE3")) / 2  # ibug-68 names, as `corpus landmarks` writes
    d = b - a; iod = np.hypot(d[:, 0], d[:, 1]); x = d / iod[:, None]; y = np.stack([-x[:, 1], x[:, 0]], 1)
    o = sum(np.maximum(0, ((P(lo) - P(up)) * y).sum(1)) for up, lo in [("IM1", "IM7"), ("IM2", "IM6"), ("IM3", "IM5")]) / 3 / iod
    return t, o

def r(a, b):
    a = a - a.mean(); b = b - b.mean()
    return float((a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum()))

shifts = np.arange(-80, 81, 5)
rs = []
for line in open(sys.argv[1]):
    real_path, render_path = line.rstrip("\n").split("\t")
    tr, real = opening(real_path); ts, ren = opening(render_path)
    t = np.arange(0.2, tr[-1] - 0.2, 0.01); real = np.interp(t, tr, real)
    # The render shifted by s: what it shows at t + s drawn at t (s > 0: the render is late by s).
    rs.append([r(np.interp(t + s / 1000, ts, ren), real) for s in shifts])
m = np.mean(rs, 0); best = int(np.argmax(m))
print("shift of the render (ms)\tmean r over %d clips" % len(rs))
for s, v in zip(shifts, m): print(f"{s:+d}\t{v:.4f}")
print(f"visual lead: {-shifts[best] / 1000:+.3f} s (the render {shifts[best]} ms late: r {m[shifts == 0][0]:.3f} at 0, {m[best]:.3f} at best)")
PY
