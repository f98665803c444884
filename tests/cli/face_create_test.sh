#!/usr/bin/env bash
# Issue 48 part 3 (D92): `talkhead face create` — a face model from videos in one command, with a report that
# names what it covers; refusals (no face, several faces, too short, too dark, too blurred) in one line with
# nothing written. The videos are the shipped faces' clips (models/faces) and videos made from them with
# ffmpeg; franck (../shared/data) when present.
set -euo pipefail
TH=$1; SRC=$2; DATA=${3:-}
command -v ffmpeg >/dev/null || { echo "ffmpeg not installed: skipped"; exit 77; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
G=$SRC/models/faces/grid-s4; C=$SRC/models/faces/crema-1001
ff() { ffmpeg -nostdin -v error -y "$@"; }

# A GRID clip with its word alignment: frames by phones; the report names coverage, refusals and advice.
"$TH" face create "$G/s4hq_pbbc4a.mpg" --transcript "$G/s4_pbbc4a.align" -o "$T/g.thm" 2>"$T/g.log"
cat "$T/g.log"
grep -qE '^s4hq_pbbc4a.mpg \(neutral, frames by phones\): 75 frames seen \(3.0 s\), face in 75; usable [0-9]+ — refused: ' "$T/g.log"
grep -qE '^visemes covered: 1[0-9] of 34 \(' "$T/g.log"
grep -q '^to make it better: record 57 s more of varied speech' "$T/g.log"
grep -qE '^wrote .*/g.thm: [0-9]+ images' "$T/g.log"
"$TH" say "Hello" --lang en-US --model "$T/g.thm" --format y4m -o "$T/g.y4m" -q --no-audio
head -c 80 "$T/g.y4m" | grep -q "W720 H576"

# Two takes in two emotions, frames by mouth shape (no text): the colour match and the emotions reported.
"$TH" face create "$C/1001_DFA_NEU_XX.flv" "$C/1001_DFA_HAP_XX.flv:joy" -o "$T/c.thm" 2>"$T/c.log"
cat "$T/c.log"
grep -q '^1001_DFA_HAP_XX.flv (joy, frames by mouth shape)' "$T/c.log"
grep -q 'its colours matched to the baseface' "$T/c.log"
"$TH" inspect "$T/c.thm" | grep -qE "^  joy +[0-9]+ own"

# Refusals: one line naming the video and what is wrong; exit 1; no model.
refused() {  # NAME EXPECTED-TEXT
	set +e
	"$TH" face create "$T/$1.mp4" -o "$T/$1.thm" 2>"$T/$1.err"; local rc=$?
	set -e
	cat "$T/$1.err"
	[ $rc = 1 ] && [ "$(wc -l <"$T/$1.err")" = 1 ] && grep -q "$1.mp4: $2" "$T/$1.err" && [ ! -e "$T/$1.thm" ] && [ ! -e "$T/$1.thm.corpus.tmp" ]
}
ff -f lavfi -i color=black:s=360x288:d=3:r=25 "$T/black.mp4"
refused black "no face found in any of 75 frames"
ff -i "$C/1001_DFA_NEU_XX.flv" -i "$G/s4hq_pbbc4a.mpg" -filter_complex "[0:v]fps=25[a];[1:v]fps=25,scale=450:360[b];[a][b]hstack" -r 25 -t 2.5 "$T/two.mp4"
refused two "several faces"
ff -i "$C/1001_DFA_NEU_XX.flv" -t 1 "$T/short.mp4"
refused short "too short: a face in 1.0 s of video"
ff -i "$C/1001_DFA_NEU_XX.flv" -vf "lutyuv=y=val*0.2" "$T/dark.mp4"
refused dark "too dark"
ff -i "$C/1001_DFA_NEU_XX.flv" -vf "gblur=sigma=4" "$T/blurred.mp4"
refused blurred "too blurred"
set +e
"$TH" face create "$T/black.mp4" 2>"$T/err"; rc=$?
set -e
[ $rc = 2 ] && grep -q "give -o ME.thm or --name NAME (one of them)" "$T/err"

# --name: kept in the cache, listed by `talkhead faces` as yours, used with --face; a shipped face's name or
# a path refused.
export XDG_CACHE_HOME=$T/cache
"$TH" face create "$G/s4hq_pbbc4a.mpg" --transcript "$G/s4_pbbc4a.align" --name me -q
"$TH" faces --format tsv | grep -qP '^me\t720x576\t1 recorded \(neutral\), 22 from action units\tyours\tyes\tface create: s4hq_pbbc4a.mpg$'
"$TH" say "Hello" --lang en-US --face me --format y4m -o "$T/me.y4m" -q --no-audio
head -c 80 "$T/me.y4m" | grep -q "W720 H576"
for bad in grid-s4 synthetic "a/b"; do
	set +e
	"$TH" face create "$G/s4hq_pbbc4a.mpg" --name "$bad" 2>"$T/err"; rc=$?
	set -e
	[ $rc = 1 ] && grep -qE "choose another|cannot name a face" "$T/err"
done
test "$(ls "$T/cache/talkhead/models/faces/own")" = "$(printf 'me.info\nme.thm')"

# franck: 20 s by mouth shape, every viseme covered, his own blinks.
if [ -n "$DATA" ] && [ -f "$DATA/franck/franck.mp4" ]; then
	"$TH" face create "$DATA/franck/franck.mp4" --duration 20 -o "$T/f.thm" 2>"$T/f.log"
	cat "$T/f.log"
	grep -q '^franck.mp4 (neutral, frames by mouth shape): 480 frames seen (20.0 s)' "$T/f.log"
	grep -q '^visemes covered: 34 of 34' "$T/f.log"
	grep -q "^blinks: the person's own shut eyes" "$T/f.log"
else
	echo "franck (../shared/data/franck/franck.mp4) not found: that part skipped"
fi
echo "face create ok"
