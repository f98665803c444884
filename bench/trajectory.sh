#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Trajectories between keyposes against real speakers (issue 10 §5, D56), without a tracker in the way.
# For each of the 11 GRID clips: the real speaker's inner-lip opening (`talkhead corpus landmarks` on the
# clip, smoothed as `compare` tracks), and the render's own feature points (`render --landmarks-out`, 100 frames/s, no
# head motion or blinks) with --trajectory hermite (the thesis: zero tangents), linear and monotone (a C¹
# Hermite spline, Fritsch–Carlson tangents). Prints per clip and on average the Pearson r of the opening
# (lag 0, 100 Hz) for:
#   model:    the keyposes of FRANCK_MODEL=F.thm (examples/real-face/run.sh's franck.thm, or any model with
#             the ibug-68 points of `corpus from-video`);
#   oracle-k: the real speaker's own opening at the synthesizer's keypose times, interpolated by each curve;
#   oracle-x: the real opening at each phone's extremum (the frame `corpus from-video` would pick, D32), at
#             that frame's time, plus the pause keyposes — the targets of an ideal corpus of this speaker;
#   oracle-c: one value per CDV, as any corpus with one exemplar per (emotion, CDV) has: the mean of the
#             other 10 speakers' opening at their keyposes of that CDV (z-scored per clip; leave one clip out),
#             at this clip's keypose times — real speech's least-squares target per CDV.
# The oracles ask which curve best joins correct targets; "model" asks it of the model's targets. Then a
# sweep between oracle-c and oracle-k (targets λ·real + (1−λ)·oracle-c) prints, against how well the targets
# match the real opening at the keyposes (key-r), where a curve through them overtakes linear.
#   bench/trajectory.sh [OUT]    (needs ../shared/data/grid; build first)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
DATA=${SHARED_DATA:-$root/../shared/data}
OUT=${1:-$(mktemp -d)}
MODEL=${FRANCK_MODEL:-}
[ -d "$DATA/grid" ] || { echo "trajectory.sh: no $DATA/grid" >&2; exit 77; }
[ -f "$MODEL" ] || { echo "trajectory.sh: set FRANCK_MODEL to an ibug-68 model (examples/real-face/run.sh writes out/real-face/franck.thm)" >&2; exit 77; }
mkdir -p "$OUT"
source "$root/examples/real-face/grid-words.sh"
for clip in "$DATA"/grid/*.mpg; do
	base=$(basename "$clip" .mpg); name=${base##*_}
	[ -f "$OUT/$base.TextGrid" ] || "$TH" align "$clip" --text "$(grid_words "$name")" --lang en-US -o "$OUT/$base.TextGrid" 2>/dev/null
	[ -f "$OUT/$base.real/landmarks.tsv" ] || "$TH" corpus landmarks "$clip" -o "$OUT/$base.real" --no-pts --sheet 4 -q
	for traj in hermite linear monotone; do
		"$TH" render -q --model "$MODEL" --transcript "$OUT/$base.TextGrid" --audio "$clip" --lang en-US --fps 100 \
			--head-motion off --blinks off --trajectory "$traj" --format y4m --no-audio -o /dev/null \
			--landmarks-out "$OUT/$base.$traj.tsv" --timeline-out "$OUT/$base.timeline.json"
	done
done
/usr/bin/python3 - "$OUT" "$DATA/grid" <<'PY'
import glob, json, os, sys
import numpy as np
out, grid = sys.argv[1:3]

def load(path, status):  # landmarks TSV (frame, time, status, confidence, x y …; an older --landmarks-out: frame, time, x y …)
    lines = [l.rstrip("\n").split("\t") for l in open(path)]
    rows = lines[1:]
    t = np.array([float(r[1]) for r in rows])
    status = lines[0][2:4] == ["status", "confidence"]
    skip = 4 if status else 2
    p = np.array([[float(x) for x in r[skip:]] for r in rows]).reshape(len(rows), -1, 2)
    ok = np.array([r[2] != "lost" for r in rows]) if status else np.ones(len(rows), bool)
    return t, p, ok

def opening(p):  # MouthMeasures::opening: inner-lip gap in the eye-line frame, per eye distance
    if p.shape[1] != 68:
        raise SystemExit("trajectory.sh: FRANCK_MODEL's points are not ibug-68 (use a model from corpus from-video)")
    d = p[:, 45] - p[:, 36]; iod = np.hypot(d[:, 0], d[:, 1]); c, s = d[:, 0] / iod, d[:, 1] / iod
    y = lambda i: (-s * p[:, i, 0] + c * p[:, i, 1]) / iod
    return sum(np.maximum(0, y(a) - y(b)) for a, b in ((67, 61), (66, 62), (65, 63))) / 3

def r(a, b):
    a = a - a.mean(); b = b - b.mean()
    return float((a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum()))

def curve(k, v, t, kind):  # the three curves on scalar keypose values, as the synthesizer draws them
    m = np.zeros(len(k))
    if kind == "monotone":  # Fritsch–Carlson, zero at turning points and at the ends
        for i in range(1, len(k) - 1):
            h0, h1 = k[i] - k[i - 1], k[i + 1] - k[i]
            if h0 <= 0 or h1 <= 0: continue
            d0, d1 = (v[i] - v[i - 1]) / h0, (v[i + 1] - v[i]) / h1
            if d0 * d1 > 0:
                w1, w2 = 2 * h1 + h0, h1 + 2 * h0
                m[i] = (w1 + w2) / (w1 / d0 + w2 / d1)
    res = np.empty(len(t))
    for n, x in enumerate(t):
        i = np.searchsorted(k, x, side="right") - 1
        if i < 0: res[n] = v[0]; continue
        if i >= len(k) - 1: res[n] = v[-1]; continue
        h = k[i + 1] - k[i]; u = (x - k[i]) / h
        if kind == "linear": res[n] = v[i] + (v[i + 1] - v[i]) * u; continue
        res[n] = (2*u**3 - 3*u**2 + 1) * v[i] + (u**3 - 2*u**2 + u) * h * m[i] + (-2*u**3 + 3*u**2) * v[i + 1] + (u**3 - u**2) * h * m[i + 1]
    return res

kinds = ("hermite", "linear", "monotone")
table = {}
series = ("model", "oracle-k", "oracle-x", "oracle-c")
print("clip\t" + "\t".join(f"{s}:{k}" for s in series for k in kinds))
keyed = {}  # per clip: t, real, keypose times, CDVs, the real and the model's opening at the keyposes, timeline
for clip in sorted(glob.glob(os.path.join(grid, "*.mpg"))):
    base = os.path.basename(clip)[:-4]
    tr, pr, ok = load(f"{out}/{base}.real/landmarks.tsv", True)
    t = np.arange(0, tr[-1], 0.01)
    real = np.interp(t, tr[ok], opening(pr)[ok])
    tl = json.load(open(f"{out}/{base}.timeline.json"))
    keys = np.array([q["time"] for q in tl["keyposes"]])
    ts, ps, _ = load(f"{out}/{base}.linear.tsv", False)
    z = (np.interp(keys, t, real) - real.mean()) / real.std()
    keyed[base] = dict(t=t, real=real, keys=keys, cdv=[q["cdv"] for q in tl["keyposes"]], z=z, model=np.interp(keys, ts, opening(ps)),
                  timeline=tl)

def per_cdv(base):  # oracle-c's values for this clip: the other clips' mean z-scored opening per CDV
    acc = {}
    for other, e in keyed.items():
        if other != base:
            for c, v in zip(e["cdv"], e["z"]): acc.setdefault(c, []).append(v)
    return np.array([np.mean(acc[c]) if c in acc else 0.0 for c in keyed[base]["cdv"]])
for base, e in keyed.items(): e["per_cdv"] = per_cdv(base)

for base, e in keyed.items():
    t, real, keys, tl = e["t"], e["real"], e["keys"], e["timeline"]
    row = []
    for k in kinds:
        ts, ps, _ = load(f"{out}/{base}.{k}.tsv", False)
        row.append(r(np.interp(t, ts, opening(ps)), real))
    row += [r(curve(keys, np.interp(keys, t, real), t, k), real) for k in kinds]
    kx, vx = [], []
    for ph in tl["phones"]:
        m = (t >= ph["start"]) & (t < ph["end"])
        if ph["cdv"] == "sil" or not m.any(): continue
        seg, st = real[m], t[m]
        j = int(np.argmax(np.abs(seg - seg.mean()))) if len(seg) > 2 else len(seg) // 2
        kx.append(st[j]); vx.append(seg[j])
    for q in tl["keyposes"]:  # the pause keyposes (rest, breath) where no phone is spoken
        if not any(p["start"] <= q["time"] < p["end"] and p["cdv"] != "sil" for p in tl["phones"]):
            kx.append(q["time"]); vx.append(float(np.interp(q["time"], t, real)))
    o = np.argsort(kx); kx, vx = np.array(kx)[o], np.array(vx)[o]
    row += [r(curve(kx, vx, t, k), real) for k in kinds]
    row += [r(curve(keys, e["per_cdv"], t, k), real) for k in kinds]
    table[base] = row
    print(base + "\t" + "\t".join(f"{x:.4f}" for x in row))
mean = np.mean(list(table.values()), axis=0)
print("mean\t" + "\t".join(f"{x:.4f}" for x in mean))
for s, off in ((s, 3 * i) for i, s in enumerate(series)):
    wins = lambda a, b: sum(v[off + a] > v[off + b] for v in table.values())
    print(f"{s}: hermite > linear on {wins(0, 1)}/{len(table)} clips, monotone > linear on {wins(2, 1)}/{len(table)}")
print("targets' match with the real opening at the keyposes (key-r) and each curve's lip r:")
print(f"  model: key-r {np.mean([r(e['model'], e['z']) for e in keyed.values()]):.3f}")
for lam in (0, 0.25, 0.5, 0.75, 1):
    rows, match = [], []
    for e in keyed.values():
        v = lam * e["z"] + (1 - lam) * e["per_cdv"]
        match.append(r(v, e["z"]))
        rows.append([r(curve(e["keys"], v, e["t"], k), e["real"]) for k in kinds])
    m = np.mean(rows, axis=0)
    wins = lambda a: sum(x[a] > x[1] for x in rows)
    print(f"  λ {lam:.2f}: key-r {np.mean(match):.3f}  " + "  ".join(f"{k} {v:.4f}" for k, v in zip(kinds, m))
          + f"  (over linear: hermite {wins(0)}/{len(rows)}, monotone {wins(2)}/{len(rows)})")
PY
