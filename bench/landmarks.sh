#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Landmark tracking on the franck video (issue 10 §1): speed (goal: 4800 frames in <= 200 s on 2 cores),
# and what one-euro smoothing does: frame-to-frame jitter of the rigid points (eye corners, nose) before and
# after, and the lag of the inner-lip opening behind the unsmoothed track (cross-correlation peak, sub-frame).
#   bench/landmarks.sh [BUILD_DIR] [--duration T]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
B=${1:-$root/build}
shift || true
TH=$B/talkhead
V=$root/../shared/data/franck/franck.mp4
[ -f "$V" ] || { echo "no $V (the shared data folder)"; exit 0; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
t0=$(date +%s.%N)
"$TH" corpus landmarks "$V" -o "$T/smooth" --no-pts --sheet 0 -q "$@"
t1=$(date +%s.%N)
"$TH" corpus landmarks "$V" -o "$T/raw" --no-pts --sheet 0 -q --no-smooth "$@"
frames=$(($(wc -l <"$T/smooth/landmarks.tsv") - 1))
/usr/bin/python3 - "$T/raw/landmarks.tsv" "$T/smooth/landmarks.tsv" "$t0" "$t1" "$frames" <<'PY'
import sys
import numpy as np
def load(p):
    rows = [l.rstrip("\n").split("\t") for l in open(p)][1:]
    ok = np.array([r[2] != "lost" for r in rows])
    pts = np.array([[float(v) if v else np.nan for v in r[4:]] for r in rows]).reshape(len(rows), 68, 2)
    return ok, pts
ok_r, raw = load(sys.argv[1]); ok_s, sm = load(sys.argv[2])
t0, t1, frames = float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
iod = np.linalg.norm(raw[:, 45] - raw[:, 36], axis=1)
rigid = [36, 39, 42, 45, 27, 28, 29, 30, 31, 33, 35]
def jitter(p):
    acc = np.linalg.norm(p[:-2, rigid] - 2 * p[1:-1, rigid] + p[2:, rigid], axis=2) / iod[1:-1, None]
    vel = np.linalg.norm(p[1:, rigid] - p[:-1, rigid], axis=2) / iod[1:, None]
    return np.nanmean(acc), np.nanmean(vel)
def opening(p):
    g = (np.linalg.norm(p[:, 61] - p[:, 67], axis=1) + np.linalg.norm(p[:, 62] - p[:, 66], axis=1) + np.linalg.norm(p[:, 63] - p[:, 65], axis=1)) / 3
    return g / np.linalg.norm(p[:, 45] - p[:, 36], axis=1)
ar, vr = jitter(raw); as_, vs = jitter(sm)
o_r, o_s = opening(raw), opening(sm)
m = np.isfinite(o_r) & np.isfinite(o_s)
a, b = o_r[m] - o_r[m].mean(), o_s[m] - o_s[m].mean()
lags = range(-5, 6)
c = [np.dot(a[max(0, -k):len(a) - max(0, k)], b[max(0, k):len(b) - max(0, -k)]) for k in lags]
k = int(np.argmax(c)); lag = lags[k]
if 0 < k < len(c) - 1:
    lag += 0.5 * (c[k - 1] - c[k + 1]) / (c[k - 1] - 2 * c[k] + c[k + 1])
fps = 24.0
print(f"frames                 {frames}, face in {ok_s.sum()} ({100 * ok_s.mean():.1f} %)")
print(f"tracking time          {t1 - t0:.1f} s = {frames / (t1 - t0):.0f} frames/s = {frames / fps / (t1 - t0):.1f}x real time (goal: <= 200 s)")
print(f"rigid-point jitter     acceleration {ar:.4f} -> {as_:.4f} eye distances/frame^2 ({ar / as_:.1f}x less); speed {vr:.4f} -> {vs:.4f}")
print(f"inner-lip opening lag  {1000 * lag / fps:+.1f} ms behind the unsmoothed track (correlation {np.corrcoef(a, b)[0, 1]:.4f})")
PY
