#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Coarticulation against real speakers (issue 32, D62), every number leave-one-speaker-out.
# Tracks and aligns every GRID clip of the shared data (../shared/data/grid: 11 clips, 10 speakers; and
# av-candidates: s1, s4, s10, s30, s33, s34, s2), then for each of the 11 clips of grid/ learns a
# coarticulation model from the other speakers' clips (`talkhead corpus coarticulation`) and renders the
# clip's sentence with FRANCK_MODEL (an ibug-68 model of a real face, e.g. examples/real-face/run.sh's)
# and with the default face, without and with `--coarticulation` (100 frames/s, no head motion or blinks,
# the feature points from --landmarks-out). Prints per face and way:
#   lip r      Pearson r of the inner-lip opening against the real speaker's (mean over clips, weakest);
#   bilabials  /p b m/ whose lips shut (gap ≤ 10 % of the render's open range) within ±40 ms of the real
#              speaker's closure;
#   silent     RMS frame-to-frame change (25 fps) of the opening inside pauses (≥ 0.1 s from speech), in
#              units of each mouth's 90th percentile in speech — the real speakers' figure last.
#   bench/coarticulation.sh [OUT]    (needs ../shared/data; build first; ~8 min the first time, cached)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
DATA=${SHARED_DATA:-$root/../shared/data}
OUT=${1:-${TMPDIR:-/tmp}/talkhead-coarticulation}
MODEL=${FRANCK_MODEL:-}
[ -d "$DATA/grid" ] || { echo "coarticulation.sh: no $DATA/grid" >&2; exit 77; }
[ -f "$MODEL" ] || { echo "coarticulation.sh: set FRANCK_MODEL to an ibug-68 model (examples/real-face/run.sh writes out/real-face/franck.thm)" >&2; exit 77; }
DEFAULT=${DEFAULT_MODEL:-$root/build/models/default.thm}
mkdir -p "$OUT/clips"
source "$root/examples/real-face/grid-words.sh"
AV="$DATA/av-candidates"
printf 'landmarks\ttranscript\tspeaker\n' >"$OUT/all.tsv"
for clip in "$DATA"/grid/*.mpg "$AV"/grid-s1-osalinasv/*.mpg "$AV"/grid-s4hq-vid2speech/*.mpg "$AV"/grid-newspk-drpato/*.mpg "$AV"/grid-misc/*.mpg; do
	[ -f "$clip" ] || continue
	base=$(basename "$clip" .mpg); name=${base##*_}
	case "$clip" in "$DATA"/grid/*) speaker=grid-$base; [ "$base" = pwij3p ] || [ "$base" = id2_vcd_swwp2s ] && speaker=s2 ;;
		*) speaker=${base%%_*}; speaker=${speaker%hq} ;; esac
	c="$OUT/clips/$base"
	if [ ! -f "$c.TextGrid" ]; then
		"$TH" align "$clip" --text "$(grid_words "$name")" --lang en-US -o "$c.TextGrid" 2>/dev/null || { echo "coarticulation.sh: $base: not aligned, left out" >&2; continue; }
	fi
	[ -f "$c.real/landmarks.tsv" ] || "$TH" corpus landmarks "$clip" -o "$c.real" --no-pts --sheet 4 -q
	printf '%s\t%s\t%s\n' "clips/$base.real/landmarks.tsv" "clips/$base.TextGrid" "$speaker" >>"$OUT/all.tsv"
done
"$TH" corpus coarticulation --clips "$OUT/all.tsv" --lang en-US -o "$OUT/all.model.tsv"
for clip in "$DATA"/grid/*.mpg; do
	base=$(basename "$clip" .mpg); c="$OUT/clips/$base"
	speaker=grid-$base; [ "$base" = pwij3p ] || [ "$base" = id2_vcd_swwp2s ] && speaker=s2
	awk -F'\t' -v s="$speaker" 'NR == 1 || $3 != s' "$OUT/all.tsv" >"$OUT/held-$base.tsv"
	"$TH" corpus coarticulation --clips "$OUT/held-$base.tsv" --lang en-US -o "$OUT/held-$base.model.tsv" -q
	for face in franck default; do
		m=$MODEL; [ $face = default ] && m=$DEFAULT
		common=(--model "$m" --transcript "$c.TextGrid" --audio "$clip" --lang en-US --fps 100 --head-motion off --blinks off --format y4m --no-audio -o /dev/null)
		"$TH" render -q "${common[@]}" --landmarks-out "$c.$face.thesis.tsv" --timeline-out "$c.timeline.json"
		"$TH" render -q "${common[@]}" --landmarks-out "$c.$face.coarticulation.tsv" --coarticulation "$OUT/held-$base.model.tsv"
	done
done
/usr/bin/python3 - "$OUT" "$DATA/grid" <<'PY'
import glob, json, os, sys
import numpy as np
out, grid = sys.argv[1:3]

def table(path):
    rows = [l.rstrip("\n").split("\t") for l in open(path)]
    return rows[0], rows[1:]

def opening(path):  # inner-lip gap per eye distance (eye centres), by point names: ibug-68 or ch-unicamp-56
    h, rows = table(path)
    t = np.array([float(r[1]) for r in rows])
    ok = np.array([len(h) < 3 or h[2] != "status" or r[2] != "lost" for r in rows])
    first = 4 if h[2] == "status" else 2  # the landmarks TSV (D78: status, confidence), or an older render's
    if h[first] == "x0":  # an older landmarks.tsv of `corpus landmarks`: x y of the 68 iBUG points by number
        p = np.array([[float(x) if x else np.nan for x in r[4:]] for r in rows]).reshape(len(rows), -1, 2)
        P = lambda i: p[:, i]
        pairs, eyes = [(61, 67), (62, 66), (63, 65)], ((36, 39), (42, 45))
    else:
        col = lambda n: np.array([float(r[h.index(n)]) if r[h.index(n)] else np.nan for r in rows])
        P = lambda n: np.stack([col(n + "_x"), col(n + "_y")], 1)
        if "IM1_x" in h: pairs, eyes = [("IM1", "IM7"), ("IM2", "IM6"), ("IM3", "IM5")], (("RE0", "RE3"), ("LE0", "LE3"))
        else: pairs, eyes = [("RM4", "RM5"), ("CIUM", "CILM"), ("LM4", "LM5")], (("REYE1", "REYE3"), ("LEYE1", "LEYE3"))
    a = (P(eyes[0][0]) + P(eyes[0][1])) / 2; b = (P(eyes[1][0]) + P(eyes[1][1])) / 2
    d = b - a; iod = np.hypot(d[:, 0], d[:, 1]); x = d / iod[:, None]; y = np.stack([-x[:, 1], x[:, 0]], 1)
    o = sum(np.maximum(0, ((P(lo) - P(up)) * y).sum(1)) for up, lo in pairs) / 3 / iod
    return t[ok], o[ok]

def r(a, b):
    a = a - a.mean(); b = b - b.mean()
    return float((a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum()))

ways = [(f, w) for f in ("franck", "default") for w in ("thesis", "coarticulation")]
lip = {k: [] for k in ways}; shut = {k: [0, 0] for k in ways}; still = {k: [] for k in ways + ["real"]}
print("clip\t" + "\t".join(f"{f}:{w}" for f, w in ways))
for clip in sorted(glob.glob(os.path.join(grid, "*.mpg"))):
    base = os.path.basename(clip)[:-4]; c = f"{out}/clips/{base}"
    tr, real_o = opening(f"{c}.real/landmarks.tsv")
    t = np.arange(0, tr[-1], 0.01); real = np.interp(t, tr, real_o)
    phones = json.load(open(f"{c}.timeline.json"))["phones"]
    speech = np.zeros(len(t), bool)
    for p in phones:
        if p["cdv"] != "sil": speech |= (t >= p["start"]) & (t < p["end"])
    pause = np.array([not any(p["cdv"] != "sil" and p["start"] - 0.1 <= x < p["end"] + 0.1 for p in phones) for x in tr])
    def silent(tt, oo):
        v = np.interp(tr, tt, oo) / np.percentile(np.interp(t, tt, oo)[speech], 90)
        d = np.diff(v); m = pause[1:] & pause[:-1]
        return np.sqrt(np.mean(d[m] ** 2)) if m.any() else np.nan
    still["real"].append(silent(t, real))
    row = []
    for k in ways:
        ts, o = opening(f"{c}.{k[0]}.{k[1]}.tsv")
        ren = np.interp(t, ts, o); row.append(r(ren, real)); lip[k].append(row[-1]); still[k].append(silent(ts, o))
        lo, hi = ren.min(), np.percentile(ren[speech], 95)
        for p in phones:
            if p["cdv"] not in ("p1", "p2"): continue
            m = (t >= p["start"] - 0.04) & (t <= p["end"] + 0.04)
            tc = t[m][np.argmin(real[m])]
            w = (t >= tc - 0.04) & (t <= tc + 0.04)
            shut[k][1] += 1; shut[k][0] += bool(ren[w].min() <= lo + 0.1 * (hi - lo) + 1e-9)
    print(base + "\t" + "\t".join(f"{x:.3f}" for x in row))
for k in ways:
    print(f"{k[0]:7s} {k[1]:14s} lip r {np.mean(lip[k]):.3f} (weakest {np.min(lip[k]):.3f}); bilabials shut {shut[k][0]}/{shut[k][1]}"
          f" ({100 * shut[k][0] / max(1, shut[k][1]):.0f} %); silent {np.nanmean(still[k]):.4f}")
print(f"real speakers' silent {np.nanmean(still['real']):.4f}")
PY
