#!/usr/bin/env bash
# Issue 32 (D62): a coarticulation model learned from real speakers (five GRID clips of five speakers,
# tracked and aligned here), its damaged or missing file one clear error, and a render with it on the
# default face: every /p b m/ shuts the lips, the same input gives the same frames, and with
# --coarticulation off the thesis's path is untouched. Issue 48 (D90): the shipped model
# (models/coarticulation/grid.tsv) is read and used by default, with no shared data.
set -euo pipefail
TH=$1; SHARED=$2
PY=/usr/bin/python3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
err() { local rc=0; "$TH" "$@" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" != 0; test "$(wc -l <"$T/e")" = 1 || { cat "$T/e"; false; }; cat "$T/e"; }

# Bad model files (no shared data needed): missing, not a model, cut short; no output written.
TG=$(dirname "$0")/../../examples/que_noticia.TextGrid
err render --transcript "$TG" --coarticulation "$T/none.tsv" -o "$T/x.mp4" | grep -q "none.tsv: cannot open the coarticulation model"
echo "hello" >"$T/bad.tsv"
err render --transcript "$TG" --coarticulation "$T/bad.tsv" -o "$T/x.mp4" | grep -q "bad.tsv:1: not a talkhead coarticulation model"
printf 'talkhead-coarticulation\t1\nlambda\t10\n' >"$T/cut.tsv"
err render --transcript "$TG" --coarticulation "$T/cut.tsv" -o "$T/x.mp4" | grep -q "cut.tsv: no intercept line"
test ! -e "$T/x.mp4"
printf '{"frame": 0, "request": {"type": "say", "text": "Bob met Pam."}}\n{"type": "end", "frame": 60}\n' >"$T/session.jsonl"
err live "$T/session.jsonl" --coarticulation "$T/bad.tsv" -o "$T/x.y4m" -q | grep -q "bad.tsv:1: not a talkhead coarticulation model"
err serve --listen 127.0.0.1:0 --coarticulation "$T/none.tsv" | grep -q "none.tsv: cannot open the coarticulation model"
test ! -e "$T/x.y4m"

# The shipped model by default (render, live): the same frames as naming it, and not the thesis's.
common=(--transcript "$TG" --size 320x180 --head-motion off --blinks off --format y4m -q)
"$TH" render "${common[@]}" -o "$T/default.y4m" --timeline-out "$T/default.json"
"$TH" render "${common[@]}" --coarticulation on -o "$T/on.y4m"
"$TH" render "${common[@]}" --coarticulation "$(dirname "$0")/../../models/coarticulation/grid.tsv" --pauses still -o "$T/file.y4m"
"$TH" render "${common[@]}" --coarticulation off -o "$T/off.y4m" --timeline-out "$T/off.json"
"$TH" render "${common[@]}" --coarticulation off --pauses natural -o "$T/off-natural.y4m"
cmp "$T/default.y4m" "$T/on.y4m"
cmp "$T/default.y4m" "$T/file.y4m"
cmp "$T/off.y4m" "$T/off-natural.y4m"  # off: the thesis's path, Natural pauses
! cmp -s "$T/default.y4m" "$T/off.y4m"
# The shipped model predicts each phone's opening: the timeline says so only with it.
grep -q '"mouth_opening"' "$T/default.json"
! grep -q '"mouth_opening"' "$T/off.json"
"$TH" live "$T/session.jsonl" --size 320x180 --blinks off --head-motion off -q -o "$T/live-default.y4m" >/dev/null
"$TH" live "$T/session.jsonl" --size 320x180 --blinks off --head-motion off -q --coarticulation on -o "$T/live-on.y4m" >/dev/null
"$TH" live "$T/session.jsonl" --size 320x180 --blinks off --head-motion off -q --coarticulation off -o "$T/live-off.y4m" >/dev/null
cmp "$T/live-default.y4m" "$T/live-on.y4m"
! cmp -s "$T/live-default.y4m" "$T/live-off.y4m"

# A batch: a row with no coarticulation column's value is the shipped model's, "off" the thesis's.
printf 'transcript,coarticulation,muted,size\n%s,,yes,160x90\n%s,on,yes,160x90\n%s,off,yes,160x90\n' "$TG" "$TG" "$TG" >"$T/m.csv"
"$TH" batch "$T/m.csv" -o "$T/batch" --seed 1 -q
sha() { awk -F, -v r="$1" '$2 == r { print $4 }' "$T/batch/key.csv"; }
test -n "$(sha 1)" && test "$(sha 1)" = "$(sha 2)" && test "$(sha 1)" != "$(sha 3)"

G=$SHARED/grid
if [ ! -d "$G" ]; then echo "skipped: no shared data in $SHARED (grid/)"; exit 77; fi
source "$(dirname "$0")/../../examples/real-face/grid-words.sh"
printf 'landmarks\ttranscript\tspeaker\n' >"$T/clips.tsv"
for b in bbaf2n brbk7n lbax4n lrwp9a sbia1a; do
	"$TH" align "$G/$b.mpg" --text "$(grid_words "$b")" --lang en-US -o "$T/$b.TextGrid" 2>/dev/null
	"$TH" corpus landmarks "$G/$b.mpg" -o "$T/$b" --no-pts --sheet 4 -q
	printf '%s/landmarks.tsv\t%s.TextGrid\t%s\n' "$b" "$b" "$b" >>"$T/clips.tsv"
done
"$TH" corpus coarticulation --clips "$T/clips.tsv" --lang en-US -o "$T/model.tsv" 2>"$T/summary"
cat "$T/summary"
grep -q "keyposes of 5 clips; fit r 0\.[4-9].*held-out speakers' keypose openings r 0\.[3-9]" "$T/summary"
# A list naming a missing file: one line naming the list and its line.
printf 'landmarks\ttranscript\nnone.tsv\tbbaf2n.TextGrid\n' >"$T/missing.tsv"
err corpus coarticulation --clips "$T/missing.tsv" --lang en-US -o "$T/m.tsv" | grep -q "missing.tsv:2: no such file: .*none.tsv"
test ! -e "$T/m.tsv"

# A GRID sentence on the default face with the model: bilabials shut at their keyposes, and twice the same.
c=$G/pwij3p.mpg
"$TH" align "$c" --text "$(grid_words pwij3p)" --lang en-US -o "$T/s.TextGrid" 2>/dev/null
common=(--transcript "$T/s.TextGrid" --audio "$c" --lang en-US --fps 100 --head-motion off --blinks off --format y4m --no-audio)
"$TH" render -q "${common[@]}" --coarticulation "$T/model.tsv" -o "$T/a.y4m" --landmarks-out "$T/a.tsv" --timeline-out "$T/a.json"
"$TH" render -q "${common[@]}" --coarticulation "$T/model.tsv" -o "$T/b.y4m"
cmp "$T/a.y4m" "$T/b.y4m"
"$TH" render -q "${common[@]}" --coarticulation off -o "$T/thesis.y4m"
"$TH" render -q "${common[@]}" --coarticulation off --pauses natural -o "$T/natural.y4m"
cmp "$T/thesis.y4m" "$T/natural.y4m"  # off: the thesis's path, Natural pauses
! cmp -s "$T/a.y4m" "$T/thesis.y4m"
$PY - "$T/a.tsv" "$T/a.json" <<'EOF'
import json, sys
import numpy as np
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])]
h, rows = rows[0], rows[1:]
t = np.array([float(r[1]) for r in rows])
col = lambda n: np.array([float(r[h.index(n)]) for r in rows])
P = lambda n: np.stack([col(n + "_x"), col(n + "_y")], 1)
iod = np.hypot(*(0.5 * (P("LEYE1") + P("LEYE3")) - 0.5 * (P("REYE1") + P("REYE3"))).T)
gap = sum(np.maximum(0, P(lo)[:, 1] - P(up)[:, 1]) for up, lo in (("RM4", "RM5"), ("CIUM", "CILM"), ("LM4", "LM5"))) / 3 / iod
lo, hi = gap.min(), np.percentile(gap, 95)
keys = json.load(open(sys.argv[2]))["keyposes"]
bilabials = [k["time"] for k in keys if k["cdv"] in ("p1", "p2")]
assert bilabials, "the sentence has bilabials"
for at in bilabials:
    g = np.interp(at, t, gap)
    assert g <= lo + 0.1 * (hi - lo) + 1e-9, f"bilabial at {at:.3f} s: gap {g:.4f}, open range {lo:.4f}–{hi:.4f}"
print(f"{len(bilabials)} bilabials shut; open range {lo:.4f}-{hi:.4f}")
EOF

# A live session (serve's, replayed offline by `talkhead live`) with the model: the same requests give the
# same frames, and they differ from the session without it (the mouths are the model's).
live=(live "$T/session.jsonl" --size 320x180 --blinks off --head-motion off -q)
"$TH" "${live[@]}" --coarticulation "$T/model.tsv" -o "$T/live-a.y4m" >/dev/null
"$TH" "${live[@]}" --coarticulation "$T/model.tsv" -o "$T/live-b.y4m" >/dev/null
"$TH" "${live[@]}" --coarticulation off -o "$T/live-thesis.y4m" >/dev/null
cmp "$T/live-a.y4m" "$T/live-b.y4m"
! cmp -s "$T/live-a.y4m" "$T/live-thesis.y4m"
echo "live session with the model: deterministic, and not the thesis's mouths"
echo "coarticulation: ok"
