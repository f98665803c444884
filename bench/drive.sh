#!/usr/bin/env bash
# Driven by a real performance (issue 17, D55): each GRID clip drives the default face (head, brows, eyes
# and blinks from the clip; the mouth from the clip's sentence aligned to its audio), then `talkhead track`
# runs on the render and on the clip, and their head curves are correlated. Prints per clip: the Pearson r
# of the head roll, x and y between render and driver, blinks found in each, and the speed of
# `render --drive` (tracking + rendering, 640x360) against the clip's duration.
# Then --drive-mouth (no transcript): the lip-opening r (talkhead compare, lag 0) of the render against the
# clip, on the default face and, with FRANCK_MODEL=F.thm FRANCK_CORPUS=DIR (examples/real-face/run.sh's
# franck.thm and franck-corpus/), on franck, with Braun's style check (braun-spec §6.2): per driver frame,
# the modified Hausdorff distance of the render's mouth to the nearest of the actor's exemplars against
# its distance to the driver's mouth (mouths centred, derotated, in eye distances).
#   bench/drive.sh [OUT]     (needs ../shared/data/grid; build first)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
DATA=${SHARED_DATA:-$root/../shared/data}
OUT=${1:-$(mktemp -d)}
[ -d "$DATA/grid" ] || { echo "drive.sh: no $DATA/grid" >&2; exit 77; }
mkdir -p "$OUT"
source "$root/examples/real-face/grid-words.sh"
printf 'clip\tr_roll\tr_x\tr_y\tdriver_roll_sd_deg\tblinks_driver\tblinks_render\tdrive_s\tclip_s\tx_real_time\n'
for clip in "$DATA"/grid/*.mpg; do
	base=$(basename "$clip" .mpg); name=${base##*_}
	"$TH" track "$clip" -o "$OUT/$base.driver.json" -q
	start=$(date +%s.%N)
	"$TH" render --drive "$clip" --text "$(grid_words "$name")" --lang en-US --size 640x360 -o "$OUT/$base.drive.mp4" -q
	end=$(date +%s.%N)
	"$TH" track "$OUT/$base.drive.mp4" -o "$OUT/$base.render.json" -q
	/usr/bin/python3 - "$OUT/$base.driver.json" "$OUT/$base.render.json" "$base" "$start" "$end" <<'PY'
import json, sys
import numpy as np
a, b = (json.load(open(p)) for p in sys.argv[1:3])
def curve(j, k):
    c = j["curves"]
    return np.array(c["head"][k]), c["rate"]
out = [sys.argv[3]]
for k in ("roll", "x", "y"):
    (u, ru), (v, rv) = curve(a, k), curve(b, k)
    t = np.arange(0, min(len(u) / ru, len(v) / rv), 0.01)
    uu = np.interp(t, np.arange(len(u)) / ru, u); vv = np.interp(t, np.arange(len(v)) / rv, v)
    out.append("%.3f" % np.corrcoef(uu, vv)[0, 1])
out.append("%.2f" % np.std(curve(a, "roll")[0]))
blinks = lambda j: sum(1 for e in j["events"] if e["type"] == "blink")
out += [str(blinks(a)), str(blinks(b))]
seconds = float(sys.argv[5]) - float(sys.argv[4]); duration = len(curve(a, "roll")[0]) / curve(a, "roll")[1]
out += ["%.2f" % seconds, "%.2f" % duration, "%.2f" % (duration / seconds)]
print("\t".join(out))
PY
done

mouth_table() { # model-label model-args...
	local label=$1; shift
	printf '\n--drive-mouth on %s\nclip\tlip_r_lag0\tlip_r_best\tlag_ms\tr_roll\tdrive_s\tx_real_time\n' "$label"
	for clip in "$DATA"/grid/*.mpg; do
		base=$(basename "$clip" .mpg)
		start=$(date +%s.%N)
		"$TH" render --drive "$clip" --drive-mouth "$@" --size 640x360 -o "$OUT/$base.$label.mouth.mp4" -q
		end=$(date +%s.%N)
		"$TH" compare "$OUT/$base.$label.mouth.mp4" "$clip" --json -q >"$OUT/$base.$label.compare.json"
		"$TH" track "$OUT/$base.$label.mouth.mp4" -o "$OUT/$base.$label.mouth.json" -q
		/usr/bin/python3 - "$OUT/$base.$label.compare.json" "$OUT/$base.driver.json" "$OUT/$base.$label.mouth.json" "$base" "$start" "$end" <<'PY'
import json, sys
import numpy as np
c = json.load(open(sys.argv[1]))
(a, ra), (b, rb) = ((np.array(j["curves"]["head"]["roll"]), j["curves"]["rate"]) for j in (json.load(open(p)) for p in sys.argv[2:4]))
t = np.arange(0, min(len(a) / ra, len(b) / rb) - 0.05, 0.01)
r = np.corrcoef(np.interp(t, np.arange(len(a)) / ra, a), np.interp(t, np.arange(len(b)) / rb, b))[0, 1]
s = float(sys.argv[6]) - float(sys.argv[5])
print("%s\t%.3f\t%.3f\t%.0f\t%.3f\t%.2f\t%.2f" % (sys.argv[4], c["r_lag0"], c["r_best"], c["best_lag_ms"], r, s, c["duration"] / s))
PY
	done | tee "$OUT/$label.mouth.tsv"
	awk -F'\t' '{ n++; r += $2; h += $5 } END { printf "mean\t%.3f\t\t\t%.3f\n", r / n, h / n }' "$OUT/$label.mouth.tsv"
}
mouth_table default
if [ -n "${FRANCK_MODEL:-}" ]; then
	mouth_table franck --model "$FRANCK_MODEL"
	# Braun's style check on the franck renders.
	printf '\nstyle (franck): clip\tframes\tMHD render-actor\tMHD render-driver\tcloser to the actor\n'
	for clip in "$DATA"/grid/*.mpg; do
		base=$(basename "$clip" .mpg)
		"$TH" corpus landmarks "$OUT/$base.franck.mouth.mp4" -o "$OUT/$base.render-lm" --no-pts -q
		"$TH" corpus landmarks "$clip" -o "$OUT/$base.driver-lm" --no-pts -q
		/usr/bin/python3 - "$OUT/$base.render-lm/landmarks.tsv" "$OUT/$base.driver-lm/landmarks.tsv" "$FRANCK_CORPUS/corpus.csv" "$base" <<'PY'
import sys
import numpy as np
def mouth(p):  # 68 x 2 -> the mouth centred, derotated by the outer eye corners, in eye distances
    e = p[45] - p[36]; d = np.hypot(*e); c, s = e / d
    m = p[48:68] @ np.array([[c, -s], [s, c]]) / d
    return m - m.mean(0)
def read_tsv(path):
    out = {}
    for line in open(path).read().splitlines()[1:]:
        f = line.split("\t")
        if f[2] != "lost": out[float(f[1])] = np.array(f[4:], float).reshape(68, 2)
    return out
def mhd(a, b):
    d = np.linalg.norm(a[:, None] - b[None], axis=2)
    return max(d.min(1).mean(), d.min(0).mean())
render, driver = read_tsv(sys.argv[1]), read_tsv(sys.argv[2])
actor = []
for line in open(sys.argv[3]):
    if line.startswith("#"): continue
    f = line.strip().split(",")
    actor.append(mouth(np.array([v.strip("()").split(";") for v in f[9:9 + 68]], float)))
dt, da, n, closer = [], [], 0, 0
for t, p in driver.items():
    near = min(render, key=lambda u: abs(u - t)) if render else None
    if near is None or abs(near - t) > 0.021: continue
    m = mouth(render[near]); to_actor = min(mhd(m, a) for a in actor); to_driver = mhd(m, mouth(p))
    da.append(to_actor); dt.append(to_driver); closer += to_actor < to_driver
print("%s\t%d\t%.4f\t%.4f\t%.0f %%" % (sys.argv[4], len(da), np.mean(da), np.mean(dt), 100 * closer / max(1, len(da))))
PY
	done
fi

# A driver whose head moves (GRID's speakers barely turn: roll sd 0.1–0.7°): 20 s of franck.mp4 (no audio)
# drives the default face and, when given, the franck model (--drive-mouth); head curves of the render
# against the driver's.
if [ -f "$DATA/franck/franck.mp4" ]; then
	ffmpeg -y -v error -ss 60 -t 20 -i "$DATA/franck/franck.mp4" -c:v libx264 -crf 18 -an "$OUT/franck20.mp4"
	"$TH" track "$OUT/franck20.mp4" -o "$OUT/franck20.driver.json" -q
	printf '\nfranck.mp4 60–80 s drives\tr_roll\tr_x\tr_y\tr_scale\tlip_r_lag0\tdrive_s\n'
	for label in default ${FRANCK_MODEL:+franck}; do
		args=(); [ "$label" = franck ] && args=(--model "$FRANCK_MODEL")
		start=$(date +%s.%N)
		"$TH" render --drive "$OUT/franck20.mp4" --drive-mouth "${args[@]}" --size 640x360 -o "$OUT/franck20.$label.mp4" -q
		end=$(date +%s.%N)
		"$TH" track "$OUT/franck20.$label.mp4" -o "$OUT/franck20.$label.json" -q
		lip=$("$TH" compare "$OUT/franck20.$label.mp4" "$OUT/franck20.mp4" --json -q | /usr/bin/python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["r_lag0"])')
		/usr/bin/python3 - "$OUT/franck20.driver.json" "$OUT/franck20.$label.json" "$label" "$lip" "$start" "$end" <<'PY'
import json, sys
import numpy as np
A, B = (json.load(open(p))["curves"] for p in sys.argv[1:3])
out = [sys.argv[3]]
for k in ("roll", "x", "y", "scale"):
    a, b = np.array(A["head"][k]), np.array(B["head"][k])
    t = np.arange(0, min(len(a) / A["rate"], len(b) / B["rate"]) - 0.05, 0.01)
    out.append("%.3f" % np.corrcoef(np.interp(t, np.arange(len(a)) / A["rate"], a), np.interp(t, np.arange(len(b)) / B["rate"], b))[0, 1])
print("\t".join(out + [sys.argv[4], "%.2f" % (float(sys.argv[6]) - float(sys.argv[5]))]))
PY
	done
fi
