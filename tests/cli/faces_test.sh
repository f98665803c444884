#!/usr/bin/env bash
# Issue 48 (D91): the real faces that ship, from the clips in models/faces alone (no ../shared): listed by
# `talkhead faces`, built on first use into the cache — byte for byte what `corpus from-video --takes` and
# `build` make of the same take list —, built once, built again when their recipe changes, and chosen with
# --face in say, render, inspect and batch; unknown names and --face with --model refused.
set -euo pipefail
TH=$1; SRC=$2; DATA=$3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
export XDG_CACHE_HOME=$T/cache
FACES=$T/cache/talkhead/models/faces

"$TH" faces --format tsv >"$T/list"
cat "$T/list"
grep -qP '^synthetic\t1280x720\t23 recorded\tGPL-3.0-or-later\t' "$T/list"
grep -qP '^grid-s4\t720x576\t1 recorded \(neutral\), 22 from action units\tCC BY 4.0\tno \(built on first use\)\tGRID' "$T/list"
grep -qP '^crema-1001\t480x360\t6 recorded \(neutral, anger, hate, fear, joy, distress\), 17 from action units\tODbL 1.0 \+ DbCL 1.0\tno' "$T/list"
"$TH" faces | grep -q '^name  *size  *emotions'

# Refusals: one line, nothing written, nothing built.
set +e
"$TH" say "Hello" --lang en-US --face nobody -o "$T/x.mp4" 2>"$T/err"; rc=$?
set -e
[ $rc = 1 ] && [ "$(wc -l <"$T/err")" = 1 ] && grep -q "no face named 'nobody' ships with talkhead (the faces: grid-s4, crema-1001, synthetic)" "$T/err"
set +e
"$TH" render --transcript "$DATA/transcripts/que_noticia.TextGrid" --face crema-1001 --model "$T/m.thm" -o "$T/x.mp4" 2>"$T/err"; rc=$?
set -e
[ $rc = 2 ] && grep -q "give --face NAME or --model M.thm, not both" "$T/err"
[ ! -e "$T/x.mp4" ] && [ ! -e "$FACES" ]
set +e
"$TH" serve --listen 127.0.0.1:0 --face nobody 2>"$T/err"; rc=$?
set -e
[ $rc = 1 ] && grep -q "no face named 'nobody'" "$T/err"
set +e
"$TH" serve --listen 127.0.0.1:0 --face grid-s4 --model "$T/m.thm" 2>"$T/err"; rc=$?
set -e
[ $rc = 2 ] && grep -q "serve: give --face NAME or --model M.thm, not both" "$T/err"
[ ! -e "$FACES" ]

# First use builds the face once, saying so; the second run finds it.
"$TH" say "Don't forget a jacket" --lang en-US --face crema-1001 --emotion joy --format y4m -o "$T/a.y4m" --no-audio 2>"$T/log1"
cat "$T/log1"
grep -q "the face 'crema-1001' is built once from its 6 clips" "$T/log1"
head -c 80 "$T/a.y4m" | grep -q "W480 H360"
"$TH" say "Don't forget a jacket" --lang en-US --face crema-1001 --emotion joy --format y4m -o "$T/b.y4m" --no-audio 2>"$T/log2"
! grep -q "built once" "$T/log2"
cmp "$T/a.y4m" "$T/b.y4m"
"$TH" faces --format tsv | grep -qP '^crema-1001\t.*\tyes\t'

# What the commands build from the same take list: the same bytes.
"$TH" corpus from-video --takes "$SRC/models/faces/crema-1001/takes.tsv" --lang en-US -o "$T/corpus" -q 2>/dev/null
"$TH" build "$T/corpus/corpus.csv" -o "$T/crema.thm" -q
cmp "$T/crema.thm" "$FACES/crema-1001.thm"
echo "crema-1001: the cache's model is the commands' model, byte for byte"
"$TH" inspect --face crema-1001 | grep -q "^frame      480x360"

# A changed recipe (another talkhead's, other clips): built again.
echo "an older recipe" >"$FACES/crema-1001.recipe"
"$TH" faces --format tsv | grep -qP '^crema-1001\t.*\tno \(built on first use\)\t'
"$TH" faces --build crema-1001 2>"$T/log3"
grep -q "built once" "$T/log3"
cmp "$T/crema.thm" "$FACES/crema-1001.thm"

# The GRID face through batch (a face column), beside the CREMA one; a row with a face and a model is refused.
printf 'text,face,emotion,size\nBin blue at F two now,grid-s4,neutral,360x288\nPlace red by G nine soon,crema-1001,anger,240x180\n' >"$T/m.csv"
"$TH" batch "$T/m.csv" -o "$T/batch" -q
test "$(ls "$T/batch"/*.mp4 | wc -l)" = 2
"$TH" inspect --face grid-s4 | grep -q "^frame      720x576"
"$TH" render --transcript "$DATA/transcripts/que_noticia.TextGrid" --face grid-s4 --size 360x288 --format y4m -o "$T/g.y4m" -q
head -c 80 "$T/g.y4m" | grep -q "W360 H288"
printf 'text,face,model\nHello,grid-s4,%s\n' "$FACES/grid-s4.thm" >"$T/bad.csv"
set +e
"$TH" batch "$T/bad.csv" -o "$T/bad" -q 2>"$T/err"; rc=$?
set -e
cat "$T/err"
[ $rc = 1 ] && grep -q "face: a row names its face or its model, not both" "$T/err" && [ ! -e "$T/bad" ]
echo "faces ok"
