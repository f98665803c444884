#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The mouth against real speakers (issues 32 and 48, D62, D90), every number on held-out speakers.
# The 11 clips of ../shared/data/grid (10 speakers, named by open-av/grid/labels-for-shared-grid) are the
# evaluation set: none is in the shipped model's clips (models/coarticulation/clips.tsv: s1, s4, s10, s30,
# s33, s34). A clip of s1 or s4 is scored with a model learned from the same list without that speaker
# (corpus-tools/coarticulation-grid.sh --without); every other clip's speaker is in no training clip, so it
# is scored with the shipped model — the render with no flags. Each sentence (aligned from its words) is
# rendered with the default face and, when FRANCK_MODEL names an ibug-68 model of a real face
# (examples/real-face/run.sh writes out/real-face/franck.thm), with franck, two ways: `thesis`
# (--coarticulation off: one target per phone) and `learned` (the default). Then:
#   points     the render's own feature points (--landmarks-out, 100 frames/s): what it meant to draw;
#   pixels     the rendered video (640x360, 25 fps, as the real clips) tracked by dlib (`corpus landmarks`),
#              as the real speaker is tracked: what a viewer gets.
# Per face, way and measure:
#   lip r      Pearson r of the inner-lip opening against the real speaker's (mean over clips, weakest);
#   range      p95 − p5 of the inner-lip opening in eye distances (mean over clips), the real speakers' last;
#   bilabials  /p b m/ whose lips shut (gap ≤ 10 % of the render's open range) within ±40 ms of the real
#              speaker's closure;
#   silent     RMS frame-to-frame change (25 fps) of the opening inside pauses (≥ 0.1 s from speech), in
#              units of each mouth's 90th percentile in speech — the real speakers' figure last.
#   bench/coarticulation.sh [OUT]    (needs ../shared/data; build first; ~25 min the first time, tracks cached)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
DATA=${SHARED_DATA:-$root/../shared/data}
OUT=${1:-${TMPDIR:-/tmp}/talkhead-coarticulation}
MODEL=${FRANCK_MODEL:-}
[ -d "$DATA/grid" ] && [ -d "$DATA/open-av/grid/labels-for-shared-grid" ] || { echo "coarticulation.sh: no $DATA/grid or its speaker labels" >&2; exit 77; }
DEFAULT=${DEFAULT_MODEL:-$root/build/models/default.thm}
# FACES: which faces (default: the synthetic default face, franck when FRANCK_MODEL is set, and the real
# faces that ship — `--face NAME`, built on first use; grid-s4 is the speaker of one evaluation clip, lwbsza).
if [ -n "${FACES:-}" ]; then read -r -a faces <<<"$FACES"; else
	faces=(default); [ -f "$MODEL" ] && faces+=(franck) || echo "coarticulation.sh: FRANCK_MODEL not set: no franck" >&2
	faces+=(grid-s4 crema-1001)
fi
# WAYS: how each clip's speech is given (default: thesis learned) — thesis (render --audio --text: the words aligned by the render, --coarticulation
# off), learned (the same, the default), words (GRID's official word alignment, the default mouth),
# audio (the audio alone: its phones recognised, issue 49), served (the audio alone as serve's `speak` with
# no timing recognises it: its first utterance within 1 s, bench_stream --heard; D97).
read -r -a ways <<<"${WAYS:-thesis learned}"
mkdir -p "$OUT/clips"
source "$root/examples/real-face/grid-words.sh"
speaker_of() {  # grid/ clip base name → its GRID speaker
	local f; f=$(ls "$DATA/open-av/grid/labels-for-shared-grid/"*"_${1##*_}.align"); f=$(basename "$f"); echo "${f%%_*}"
}
# The shipped model and its companion for recognised phones (D106), rebuilt from their recipe: the same bytes.
for kind in "" recognised; do
	"$root/corpus-tools/coarticulation-grid.sh" ${kind:+--$kind} -o "$OUT/shipped${kind:+-$kind}.tsv" >/dev/null 2>&1
	m=models/coarticulation/grid${kind:+-$kind}.tsv
	cmp -s "$OUT/shipped${kind:+-$kind}.tsv" "$root/$m" && echo "$m: rebuilt from its recipe, identical" ||
		echo "$m: rebuilt from its recipe, DIFFERENT (see $OUT/shipped${kind:+-$kind}.tsv)"
done
printf 'clip\tspeaker\tmodel\n' >"$OUT/clips.tsv"
trained=$(cut -f2 "$root/models/coarticulation/clips.tsv" | sort -u)
for clip in "$DATA"/grid/*.mpg; do
	base=$(basename "$clip" .mpg); name=${base##*_}; c="$OUT/clips/$base"; s=$(speaker_of "$base")
	if [ ! -f "$c.TextGrid" ]; then
		"$TH" align "$clip" --text "$(grid_words "$name")" --lang en-US -o "$c.TextGrid" 2>/dev/null
	fi
	[ -f "$c.real/landmarks.tsv" ] || "$TH" corpus landmarks "$clip" -o "$c.real" --no-pts -q
	# The clip's true phones (its aligned words), where the bilabials are scored.
	[ -f "$c.timeline.json" ] || "$TH" visemes "$c.TextGrid" --lang en-US --out-format json -o "$c.timeline.json"
	# The model: the shipped one, or the same clips without this speaker (and its companion for recognised
	# phones, D106: without-S-recognised.tsv).
	model=on
	if grep -qx "$s" <<<"$trained"; then
		model="$OUT/without-$s.tsv"
		[ -f "$model" ] || "$root/corpus-tools/coarticulation-grid.sh" --without "$s" -o "$model" >/dev/null 2>&1
		[ -f "${model%.tsv}-recognised.tsv" ] || "$root/corpus-tools/coarticulation-grid.sh" --recognised --without "$s" -o "${model%.tsv}-recognised.tsv" >/dev/null 2>&1
	fi
	printf '%s\t%s\t%s\n' "$base" "$s" "$model" >>"$OUT/clips.tsv"
	for face in "${faces[@]}"; do
		case $face in default) fm=(--model "$DEFAULT") ;; franck) fm=(--model "$MODEL") ;; *) fm=(--face "$face") ;; esac
		for way in "${ways[@]}"; do
			co=(); [ "$way" = thesis ] && co=(--coarticulation off); [ "$way" != thesis ] && [ "$model" != on ] && co=(--coarticulation "$model")
			# Recognised phones are planned with the companion (D106): a held-out one by name; the served way's
			# phones come as a transcript, so its shipped companion is named too (serve picks it by itself).
			heard=$root/models/coarticulation/grid-recognised.tsv; [ "$model" != on ] && heard=${model%.tsv}-recognised.tsv
			[ "$way" = audio ] && [ "$model" != on ] && co=(--coarticulation "$heard")
			[ "$way" = served ] && co=(--coarticulation "$heard")
			# thesis and learned: the words aligned to the audio by the render itself (render --audio A --text T,
			# as a user does: its timing is talkhead's estimate, which the model's visual lead corrects, D104).
			speech=(--text "$(grid_words "$name")")
			[ "$way" = words ] && speech=(--transcript "$(ls "$DATA/open-av/grid/labels-for-shared-grid/"*"_${name}.align")")
			[ "$way" = audio ] && speech=()
			if [ "$way" = served ]; then
				mkdir -p "$OUT/served"
				[ -f "$OUT/served/$base.tsv" ] || "$root/build/bench/bench_stream" --heard "$OUT/served" "$clip" >/dev/null
				speech=(--transcript "$OUT/served/$base.tsv")
			fi
			common=("${fm[@]}" "${speech[@]}" --audio "$clip" --lang en-US --head-motion off --blinks off --no-audio "${co[@]}")
			"$TH" render -q "${common[@]}" --fps 100 --format y4m -o /dev/null --landmarks-out "$c.$face.$way.points.tsv"
			"$TH" render -q "${common[@]}" --fps 25 --size 640x360 -o "$c.$face.$way.mp4"
			rm -rf "$c.$face.$way.pixels"
			"$TH" corpus landmarks "$c.$face.$way.mp4" -o "$c.$face.$way.pixels" --no-pts -q
		done
	done
done
WAYS="${ways[*]}" /usr/bin/python3 - "$OUT" "${faces[@]}" <<'PY'
import json, os, sys
import numpy as np
out, faces = sys.argv[1], sys.argv[2:]
way_names = os.environ["WAYS"].split()

def table(path):
    rows = [l.rstrip("\n").split("\t") for l in open(path)]
    return rows[0], rows[1:]

def opening(path):  # inner-lip gap per eye distance (eye centres), by point names: ibug-68 or ch-unicamp-56
    h, rows = table(path)
    t = np.array([float(r[1]) for r in rows])
    ok = np.array([len(h) < 3 or h[2] != "status" or r[2] != "lost" for r in rows])
    col = lambda n: np.array([float(r[h.index(n)]) if r[h.index(n)] else np.nan for r in rows])
    P = lambda n: np.stack([col(n + "_x"), col(n + "_y")], 1)
    if "IM1_x" in h: pairs, eyes = [("IM1", "IM7"), ("IM2", "IM6"), ("IM3", "IM5")], (("RE0", "RE3"), ("LE0", "LE3"))
    else: pairs, eyes = [("RM4", "RM5"), ("CIUM", "CILM"), ("LM4", "LM5")], (("REYE1", "REYE3"), ("LEYE1", "LEYE3"))
    a = (P(eyes[0][0]) + P(eyes[0][1])) / 2; b = (P(eyes[1][0]) + P(eyes[1][1])) / 2
    d = b - a; iod = np.hypot(d[:, 0], d[:, 1]); x = d / iod[:, None]; y = np.stack([-x[:, 1], x[:, 0]], 1)
    o = sum(np.maximum(0, ((P(lo) - P(up)) * y).sum(1)) for up, lo in pairs) / 3 / iod
    ok &= np.isfinite(o)
    return t[ok], o[ok]

def r(a, b):
    a = a - a.mean(); b = b - b.mean()
    return float((a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum()))

ways = [(f, w, m) for f in faces for w in way_names for m in ("points", "pixels")]
lip = {k: [] for k in ways}; rng = {k: [] for k in ways + ["real"]}; shut = {k: [0, 0] for k in ways}; still = {k: [] for k in ways + ["real"]}
clips = [l.rstrip("\n").split("\t") for l in open(f"{out}/clips.tsv")][1:]
print("clip\tspeaker\tmodel\t" + "\t".join(f"{f}:{w}:{m}" for f, w, m in ways))
for base, speaker, model in clips:
    c = f"{out}/clips/{base}"
    tr, real_o = opening(f"{c}.real/landmarks.tsv")
    t = np.arange(0, tr[-1], 0.01); real = np.interp(t, tr, real_o)
    rng["real"].append(np.percentile(real_o, 95) - np.percentile(real_o, 5))
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
        path = f"{c}.{k[0]}.{k[1]}.points.tsv" if k[2] == "points" else f"{c}.{k[0]}.{k[1]}.pixels/landmarks.tsv"
        ts, o = opening(path)
        ren = np.interp(t, ts, o); row.append(r(ren, real)); lip[k].append(row[-1]); still[k].append(silent(ts, o))
        sel = (ts >= tr[0]) & (ts <= tr[-1])
        rng[k].append(np.percentile(o[sel], 95) - np.percentile(o[sel], 5))
        lo, hi = ren.min(), np.percentile(ren[speech], 95)
        for p in phones:
            if p["cdv"] not in ("p1", "p2"): continue
            m = (t >= p["start"] - 0.04) & (t <= p["end"] + 0.04)
            tc = t[m][np.argmin(real[m])]
            w = (t >= tc - 0.04) & (t <= tc + 0.04)
            shut[k][1] += 1; shut[k][0] += bool(ren[w].min() <= lo + 0.1 * (hi - lo) + 1e-9)
    print(f"{base}\t{speaker}\t{'shipped' if model == 'on' else 'without ' + speaker}\t" + "\t".join(f"{x:.3f}" for x in row))
print()
for k in ways:
    print(f"{k[0]:10s} {k[1]:8s} {k[2]:6s} lip r {np.mean(lip[k]):.3f} (weakest {np.min(lip[k]):.3f}); range {np.mean(rng[k]):.3f}"
          f" ({np.mean(rng[k]) / np.mean(rng['real']):.2f}x real); bilabials shut {shut[k][0]}/{shut[k][1]}"
          f" ({100 * shut[k][0] / max(1, shut[k][1]):.0f} %); silent {np.nanmean(still[k]):.4f}")
print(f"real speakers: range {np.mean(rng['real']):.3f}; silent {np.nanmean(still['real']):.4f}")
PY
