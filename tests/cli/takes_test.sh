#!/usr/bin/env bash
# Issue 31, route 1: one expressive model from several takes of one person, each in its emotion — bad
# take lists (one line, non-zero, no output), three takes cut from franck (stand-ins for recorded emotions,
# one of them with its lighting changed), the colours matched between takes, one model of every emotion,
# each emotion drawn from its own take, and no colour jump at an emotion change.
set -euo pipefail
TH=$1; SHARED=$2
PY=/usr/bin/python3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
err() { local rc=0; "$TH" "$@" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" != 0; test "$(wc -l <"$T/e")" = 1 || { cat "$T/e"; false; }; cat "$T/e"; }

# Bad take lists first (no shared data needed).
ffmpeg -v error -f lavfi -i testsrc=size=320x240:rate=25:duration=2 -pix_fmt yuv420p "$T/noface.mp4"
printf 'video\temotion\nmissing.mp4\tjoy\n' >"$T/missing.tsv"
err corpus from-video --takes "$T/missing.tsv" -o "$T/x" | grep -q "missing.tsv:2: no such video file: .*missing.mp4"
# A name longer than the system allows (a fuzz finding: the check threw the library's own exception).
printf 'video\temotion\n%s.mp4\tjoy\n' "$(printf 'x%.0s' $(seq 300))" >"$T/long.tsv"
err corpus from-video --takes "$T/long.tsv" -o "$T/x" | grep -q "long.tsv:2: no such video file: .*(File name too long)"
printf 'video\temotion\nnoface.mp4\tglee\n' >"$T/glee.tsv"
err corpus from-video --takes "$T/glee.tsv" -o "$T/x" | grep -q "glee.tsv:2: unknown emotion 'glee'"
printf 'video\n noface.mp4\n' >"$T/nocol.tsv"
err corpus from-video --takes "$T/nocol.tsv" -o "$T/x" | grep -q "nocol.tsv.*emotion"
err corpus from-video --take "$T/noface.mp4:joy" --take "$T/noface.mp4:anger" -o "$T/x" | grep -q "noface.mp4: no face found"
err corpus from-video --take "$T/noface.mp4" -o "$T/x" | grep -q "take takes VIDEO:EMOTION"
err corpus from-video --take "$T/noface.mp4:joy" --emotion anger -o "$T/x" | grep -q "emotion is per take"
test ! -e "$T/x"

F=$SHARED/franck/franck.mp4
if [ ! -f "$F" ]; then echo "skipped: no shared data in $SHARED (franck/)"; exit 77; fi
# Three takes of franck (recorded neutral: the labels are stand-ins): 0–25 s neutral, 25–50 s "joy" with its
# lighting changed (brighter and warmer, as between two recording sessions), 50–75 s "anger".
ffmpeg -v error -ss 25 -t 25 -i "$F" -vf "eq=brightness=0.06:gamma_r=1.15" -c:v libx264 -crf 12 -an "$T/joy.mp4"
printf 'video\temotion\tstart\tduration\n%s\tneutral\t0\t25\njoy.mp4\tjoy\t-\t-\n%s\tanger\t50\t25\n' "$F" "$F" >"$T/takes.tsv"
"$TH" corpus from-video --takes "$T/takes.tsv" -o "$T/fc" 2>"$T/fc.log"
cat "$T/fc.log"
grep -q "^# talkhead corpus from-video: 3 takes" "$T/fc/corpus.csv"
grep -q '^# baseface: frames/take1_frame_' "$T/fc/corpus.csv"
# Issue 47: the person's own shut eyes (the base take's, franck's eyes lowered at 9.7 s), an unlabelled row
# for blinks, named by `# closed-eyes:`; the model built from it keeps it.
shut=$(sed -n 's/^# closed-eyes: //p' "$T/fc/corpus.csv")
test -n "$shut" && grep -q "^$shut,-,.*,closed-eyes," "$T/fc/corpus.csv"
grep -q "^blinks: the person's own shut eyes, frame " "$T/fc.log"
for e in neutral joy anger; do
	n=$(grep -v '^#' "$T/fc/corpus.csv" | cut -d, -f2 | grep -cx "$e" || true)
	echo "$e: $n frames"
	test "$n" -ge 30
done
test -s "$T/fc/contact.png" && test -s "$T/fc/landmarks-take2.tsv"
# The brightened take is matched back: its faces' mean colour as near the neutral take's (it was ~15
# brighter before) as that of the anger take, cut from the same video unchanged, give or take 2 levels —
# franck's own light drifts, and which frames each take gives decides how far apart they are (D73: 3.6
# levels for the unchanged take, on the cheeks).
$PY - "$T/fc" <<'EOF'
import sys, os, numpy as np
from skimage import io
from skimage.draw import polygon
d = sys.argv[1]
rows = [l.rstrip('\n').split(',') for l in open(os.path.join(d, 'corpus.csv')) if not l.startswith('#')]
means = {}
for r in rows:
    pts = np.array([[float(v) for v in p.strip('()').split(';')] for p in r[10:78]])
    img = io.imread(os.path.join(d, r[0]))[..., :3].astype(float)
    # the cheeks and nose: inside the jaw line below the eyes, above the mouth
    rr, cc = polygon([pts[29, 1], pts[2, 1], pts[14, 1]], [pts[29, 0], pts[2, 0], pts[14, 0]], img.shape[:2])
    means.setdefault(r[1], []).append(img[rr, cc].mean(axis=0))
m = {e: np.mean(v, axis=0) for e, v in means.items()}
for e in m: print(f'   {e}: mean face colour {m[e].round(1)}, spread over its frames {np.std(means[e], axis=0).max():.1f}')
diff = np.abs(m['joy'] - m['neutral']).max(); floor = np.abs(m['anger'] - m['neutral']).max()
print(f'   brightened take {diff:.1f} levels from the neutral one, unchanged take {floor:.1f}')
assert diff <= max(floor, 3) + 2, f'the brightened take still differs by {diff:.1f} levels (the unchanged one by {floor:.1f})'
EOF
grep -q '^# take 2: joy.mp4, joy, .*gain' "$T/fc/corpus.csv"

# One model of every recorded emotion; each emotion's keyposes come from its own take.
"$TH" build -q "$T/fc/corpus.csv" -o "$T/takes.thm"
# Issue 47: inspect says, per recorded emotion, where each of the 34 CDVs comes from (counts that add up).
"$TH" inspect "$T/takes.thm" >"$T/inspect.txt"
for e in neutral joy anger; do
	line=$(grep -E "^  $e +[0-9]+ own, +[0-9]+ by action units, +[0-9]+ from another sample" "$T/inspect.txt") || { echo "no coverage line for $e"; cat "$T/inspect.txt"; exit 1; }
	awk '{ n = $2 + $4 + $8; if (n != 34) { print "counts add up to " n ": " $0; exit 1 } }' <<<"$line"
done
for e in joy anger; do
	"$TH" render --model "$T/takes.thm" --transcript "$SHARED/grid/swwp2s.align" --emotion "$e" --format y4m -o "$T/$e.y4m" 2>"$T/$e.log" || { cat "$T/$e.log"; false; }
	if grep -qi "substitut.*$e.*neutral\|$e.*falls back" "$T/$e.log"; then cat "$T/$e.log"; echo "$e is not drawn from its own take"; false; fi
done
# An emotion no take has: from the neutral frames by its action units, and said so.
"$TH" render --model "$T/takes.thm" --transcript "$SHARED/grid/swwp2s.align" --emotion fear --format y4m -o "$T/fear.y4m" 2>"$T/fear.log"
grep -q "fear from the neutral images by its action units (the model has no fear images)" "$T/fear.log" || { cat "$T/fear.log"; false; }
# An emotion change (neutral → joy at 1 s, a 0.3-s ramp): the face's colour does not jump. Speech moves the
# face box's mean luma by as much as a colour step would (franck's neutral exemplars, taken seconds apart,
# differ by up to 2 levels), so the change is measured against the same sentence rendered in each emotion
# alone: over the frames the dissolve mixes the two takes (an emotion event acts on the keyposes, so that
# is where the ramp's keyposes are, not at the event's instant), the change's largest frame-to-frame step
# exceeds either take's own at those frames by less than a grey level. And the measure can fail: the same
# model with the joy take's frames 15 levels brighter (a take whose colours were not matched) is caught.
printf '{"events": [{"type": "emotion", "time": 0, "emotion": "neutral", "intensity": 1, "ramp": 0}, {"type": "emotion", "time": 1.0, "emotion": "joy", "intensity": 1, "ramp": 0.3}]}\n' >"$T/change.json"
for e in neutral joy; do printf '{"events": [{"type": "emotion", "time": 0, "emotion": "%s", "intensity": 1, "ramp": 0}]}\n' "$e" >"$T/only-$e.json"; done
cp -r "$T/fc" "$T/unmatched"
$PY - "$T/unmatched/frames" <<'EOF'
import glob, os, sys, numpy as np
from skimage import io
for f in glob.glob(os.path.join(sys.argv[1], 'take2_*.png')):
    im = io.imread(f).astype(int); im[..., :3] = np.clip(im[..., :3] + 15, 0, 255)
    io.imsave(f, im.astype(np.uint8), check_contrast=False)
EOF
"$TH" build -q "$T/unmatched/corpus.csv" -o "$T/unmatched.thm"
for m in takes unmatched; do
	for c in change only-neutral only-joy; do
		"$TH" render --model "$T/$m.thm" --transcript "$SHARED/grid/swwp2s.align" --controls "$T/$c.json" --format y4m -o "$T/$m-$c.y4m" \
			--landmarks-out "$T/$m-$c.tsv" -q
	done
done
$PY - "$T" <<'EOF'
import sys, numpy as np
def face_luma(stem):
    data = open(stem + '.y4m', 'rb').read()
    head = data[:data.index(b'\n')].split()
    w = int([h for h in head if h.startswith(b'W')][0][1:]); h = int([h for h in head if h.startswith(b'H')][0][1:])
    frames, at = [], data.index(b'\n') + 1
    while at < len(data):
        at = data.index(b'\n', at) + 1
        frames.append(np.frombuffer(data, np.uint8, w * h, at).reshape(h, w).astype(float)); at += w * h * 3 // 2
    lm = [l.rstrip('\n').split('\t')[2:] for l in open(stem + '.tsv')][1:]  # x y from the 5th column (status, confidence before)
    out = []
    for k, f in enumerate(frames):
        xs = [float(v) for v in lm[k][2::2]]; ys = [float(v) for v in lm[k][3::2]]  # lm[k] starts at status
        x0, x1, y0, y1 = int(np.percentile(xs, 20)), int(np.percentile(xs, 80)), int(np.percentile(ys, 20)), int(np.percentile(ys, 60))
        out.append(f[y0:y1, x0:x1].mean())
    return np.array(out)
def steps(model):
    c, n, j = (face_luma(f'{sys.argv[1]}/{model}-{s}') for s in ('change', 'only-neutral', 'only-joy'))
    mixed = np.flatnonzero((np.abs(c - n) > 0.05) & (np.abs(c - j) > 0.05))
    assert len(mixed) >= 3, f'{model}: the change mixes only {len(mixed)} frames'
    ks = np.arange(mixed.min() - 1, mixed.max() + 1)  # the steps into, through and out of the dissolve
    dc, dn, dj = (np.abs(np.diff(x)) for x in (c, n, j))
    around, within = dc[ks].max(), np.maximum(dn[ks], dj[ks]).max()
    print(f'   {model}: frames {mixed.min()}..{mixed.max()} mix the takes; face luma step there {around:.2f}, each take alone {within:.2f}')
    return around, within
# What counts as a jump: the change may add at most one grey level per frame to what speech alone moves
# there. The matched takes still differ by a few levels (franck's own light drifts: 3.6 between two
# unchanged takes, above), and a 0.3-s ramp spreads that over ~8 frames, a fraction of a level each; a
# take left 15 levels brighter adds ~3 a frame. A bound of whole levels, not hundredths, so the assertion
# holds for the reason above and not for one CPU's rounding (issue 44: 0.45 against 0.21 here, 0.62
# against 0.63 on the machine where a 0.05 margin was written).
JUMP = 1.0
around, within = steps('takes')
assert around <= within + JUMP, f'the colour jumps at the emotion change: {around - within:.2f} levels a frame more than speech alone'
around, within = steps('unmatched')
assert around > within + JUMP, 'a take 15 levels brighter went unnoticed: the measure cannot fail'
EOF
echo "takes tests passed"
