#!/usr/bin/env bash
# Driven by a real performance (issue 17, D55): talkhead track on a synthetic video with known head motion
# and blinks, a face lost for 2 s (bridged, a warning), a video with no face (an error), replay with
# render --controls on another model, and render --drive with a GRID clip.
set -euo pipefail
TH=$1; SHARED=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
err() { local rc=0; "$TH" "$@" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" != 0; test "$(wc -l <"$T/e")" = 1 || { cat "$T/e"; false; }; cat "$T/e"; }
PY=/usr/bin/python3

# Known motion: roll 6 sin(2π 0.3 t) degrees, x 0.15 sin(2π 0.2 t), y 0.08 sin(2π 0.45 t + 1) eye
# distances, blinks at 1.0, 2.5 and 4.1 s, drawn blinks off.
$PY - "$T/truth.json" <<'PY'
import json, math, sys
rate = 25; n = 6 * rate + 1; t = [i / rate for i in range(n)]
json.dump({"drawn_blinks": False, "events": [{"type": "blink", "time": b} for b in (1.0, 2.5, 4.1)],
           "curves": {"rate": rate, "start": 0, "head": {"roll": [6 * math.sin(2 * math.pi * 0.3 * s) for s in t],
                                                          "x": [0.15 * math.sin(2 * math.pi * 0.2 * s) for s in t],
                                                          "y": [0.08 * math.sin(2 * math.pi * 0.45 * s + 1) for s in t]}}}, open(sys.argv[1], "w"))
PY
"$TH" say "Bom dia, como vai você? Hoje o dia está lindo. Amanhã vamos passear no parque, se não chover." \
	--controls "$T/truth.json" --size 640x360 -o "$T/synth.mp4" -q
"$TH" track "$T/synth.mp4" -o "$T/tracked.json" -q
test "$(head -c 8 "$T/tracked.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a   # the plot, a PNG
# The rotation within 1°, the blinks within one frame (1/30 s), the translation's shape (relative to the
# first second's neutral: an offset is allowed).
$PY - "$T/tracked.json" <<'PY'
import json, math, sys
import numpy as np
j = json.load(open(sys.argv[1])); c = j["curves"]; rate = c["rate"]
roll = np.array(c["head"]["roll"]); t = np.arange(len(roll)) / rate
err = np.abs(roll - 6 * np.sin(2 * np.pi * 0.3 * t))
print("roll: max error %.2f deg, mean %.2f" % (err.max(), err.mean()))
assert err.max() < 1.0, err.max()
for k, truth in (("x", 0.15 * np.sin(2 * np.pi * 0.2 * t)), ("y", 0.08 * np.sin(2 * np.pi * 0.45 * t + 1))):
    v = np.array(c["head"][k]); r = np.corrcoef(v, truth)[0, 1]; spread = np.ptp(v) / np.ptp(truth)
    print("%s: r %.3f, range %.2f of the truth's" % (k, r, spread))
    assert r > 0.97 and 0.85 < spread < 1.15
blinks = [e["time"] for e in j["events"] if e["type"] == "blink"]
print("blinks", blinks)
assert len(blinks) == 3 and all(abs(a - b) <= 1 / 30 for a, b in zip(blinks, (1.0, 2.5, 4.1))), blinks
assert j["drawn_blinks"] is False
PY

# Replayed on the same face by render --controls, then tracked again: the same head motion.
"$TH" say "Bom dia, como vai você? Hoje o dia está lindo. Amanhã vamos passear no parque, se não chover." \
	--controls "$T/tracked.json" --size 640x360 -o "$T/replay.mp4" -q
"$TH" track "$T/replay.mp4" -o "$T/replay.json" -q
$PY - "$T/tracked.json" "$T/replay.json" <<'PY'
import json, sys
import numpy as np
a, b = (np.array(json.load(open(p))["curves"]["head"]["roll"]) for p in sys.argv[1:3])
n = min(len(a), len(b)); d = np.abs(a[:n] - b[:n]).max(); r = np.corrcoef(a[:n], b[:n])[0, 1]
print("replay: roll r %.3f, max difference %.2f deg" % (r, d)); assert r > 0.98 and d < 1.0
PY

# The face lost for 2 s (2–4 s covered): bridged, with one warning, and the bridge stays between its ends.
ffmpeg -v error -i "$T/synth.mp4" -vf "drawbox=enable='between(t,2,4)':x=0:y=0:w=iw:h=ih:color=gray:t=fill" -c:a copy "$T/lost.mp4"
"$TH" track "$T/lost.mp4" -o "$T/lost.json" -q 2>"$T/lost.err"
cat "$T/lost.err"
grep -Eq "lost.mp4: no usable face from 2\.0[0-9] s to 4\.0[0-9] s \(2\.0 s\): the head and face are bridged over it" "$T/lost.err"
$PY - "$T/lost.json" <<'PY'
import json, sys
import numpy as np
c = json.load(open(sys.argv[1]))["curves"]; roll = np.array(c["head"]["roll"]); rate = c["rate"]
i, j = int(2.0 * rate) + 1, int(4.0 * rate)
lo, hi = sorted((roll[i - 2], roll[j + 2]))
assert ((roll[i:j] >= lo - 0.3) & (roll[i:j] <= hi + 0.3)).all(), (lo, hi, roll[i:j])
print("bridged: roll from %.2f to %.2f" % (roll[i - 2], roll[j + 2]))
PY

# No face: one error line, nothing written. Bad options: one line each.
ffmpeg -v error -f lavfi -i testsrc=size=320x240:rate=25:duration=2 -pix_fmt yuv420p "$T/noface.mp4"
err track "$T/noface.mp4" -o "$T/n.json" | grep -q "noface.mp4: no face found in any of 50 frames"
test ! -e "$T/n.json" && test ! -e "$T/n.png"
err track "$T/synth.mp4" -o "$T/n.json" --parts head,ears | grep -q "track: --parts takes head, brows, eyes and mouth, not 'ears'"
err track "$T/missing.mp4" -o "$T/n.json" | grep -q "missing.mp4: video file not found"
err render --transcript /dev/null --parts head -o "$T/n.mp4" | grep -q "render: --parts, --drive-model, --neutral-frames, --neutral-seconds and --max-turn go with --drive VIDEO"
err render --drive "$T/noface.mp4" --text "hello" -o "$T/n.mp4" | grep -q "the --drive video has no audio: give --audio"
test ! -e "$T/n.mp4"

G=$SHARED/grid
if [ ! -d "$G" ]; then echo "skipped the rest: no shared data in $SHARED (grid/)"; exit 77; fi
# Another model: a face made from a GRID clip (ibug-68), replaying the synthetic video's head motion.
"$TH" corpus from-video "$G/bbaf2n.mpg" --text "bin blue at f two now" --lang en-US -o "$T/gc" -q
"$TH" build -q "$T/gc/corpus.csv" -o "$T/grid.thm"
"$TH" say --model "$T/grid.thm" "Bom dia, como vai você? Hoje o dia está lindo. Amanhã vamos passear no parque, se não chover." \
	--controls "$T/tracked.json" -o "$T/other.mp4" -q
"$TH" track "$T/other.mp4" -o "$T/other.json" -q
$PY - "$T/tracked.json" "$T/other.json" <<'PY'
import json, sys
import numpy as np
(a, ra), (b, rb) = ((np.array(j["curves"]["head"]["roll"]), j["curves"]["rate"]) for j in (json.load(open(p)) for p in sys.argv[1:3]))
t = np.arange(0, min(len(a) / ra, len(b) / rb) - 0.05, 0.01)
u, v = np.interp(t, np.arange(len(a)) / ra, a), np.interp(t, np.arange(len(b)) / rb, b)
r = np.corrcoef(u, v)[0, 1]; d = np.abs(u - v).max()
print("another model: roll r %.3f, max difference %.2f deg" % (r, d)); assert r > 0.95 and d < 1.5
PY
# A GRID clip drives the default face: its audio, its head's roll (r against the clip's own track).
"$TH" render --drive "$G/bbaf2n.mpg" --text "bin blue at f two now" --lang en-US --size 640x360 -o "$T/driven.mp4" 2>"$T/driven.log"
cat "$T/driven.log"
grep -q "bbaf2n.mpg drives the face: 75 frames, 1 blink(s)" "$T/driven.log"
ffprobe -v error -show_entries stream=codec_type -of csv=p=0 "$T/driven.mp4" | sort | tr '\n' ' ' | grep -q "audio video"
"$TH" track "$G/bbaf2n.mpg" -o "$T/driver.json" -q
"$TH" track "$T/driven.mp4" -o "$T/driven.json" -q
$PY - "$T/driver.json" "$T/driven.json" <<'PY'
import json, sys
import numpy as np
(a, ra), (b, rb) = ((np.array(j["curves"]["head"]["roll"]), j["curves"]["rate"]) for j in (json.load(open(p)) for p in sys.argv[1:3]))
t = np.arange(0, min(len(a) / ra, len(b) / rb) - 0.05, 0.01)
r = np.corrcoef(np.interp(t, np.arange(len(a)) / ra, a), np.interp(t, np.arange(len(b)) / rb, b))[0, 1]
print("driven by bbaf2n: roll r %.3f" % r); assert r > 0.8
PY
# --drive-mouth: the mouth from the clip too (no transcript); its lip opening follows the clip's (goal
# r ≥ 0.8 over the 11 clips in bench/drive.sh, bounded looser here on one clip).
"$TH" render --drive "$G/lwbsza.mpg" --drive-mouth --size 640x360 -o "$T/mouth.mp4" 2>"$T/mouth.log"
cat "$T/mouth.log"
grep -Eq "the mouth: [0-9]+ keyposes" "$T/mouth.log"
"$TH" compare "$T/mouth.mp4" "$G/lwbsza.mpg" --json -q | $PY -c 'import json, sys; r = json.load(sys.stdin)["r_lag0"]; print("lip opening r", r); assert r > 0.7'
err render --drive "$G/lwbsza.mpg" --drive-mouth --text "lay white" -o "$T/n.mp4" | grep -q "render: --drive-mouth takes the mouth from the video: give no --transcript or --text"
err render --drive-mouth -o "$T/n.mp4" | grep -q "render: --drive-mouth goes with --drive VIDEO"
err render --drive "$G/lwbsza.mpg" --transcript /dev/null -o "$T/n.mp4" --controls "$T/tracked.json" | grep -q "has curves and --drive gives them too: give one"
test ! -e "$T/n.mp4"
echo "drive ok"
