#!/usr/bin/env bash
# Driven by a real performance (issue 17, D55): each GRID clip drives the default face (head, brows, eyes
# and blinks from the clip; the mouth from the clip's sentence aligned to its audio), then `talkhead track`
# runs on the render and on the clip, and their head curves are correlated. Prints per clip: the Pearson r
# of the head roll, x and y between render and driver, blinks found in each, and the speed of
# `render --drive` (tracking + rendering, 640x360) against the clip's duration.
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
