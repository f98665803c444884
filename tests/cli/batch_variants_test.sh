#!/usr/bin/env bash
# Issue 14: render-time component reductions and side-by-side stimuli (the thesis's Appendix C test).
# Fewer face components ⇒ a stimulus further from the full one (PSNR falls monotonically); "all" is the
# full stimulus byte for byte; a side-by-side stimulus holds exactly the two variants (lossless crf 0),
# on sides balanced over the rows and recorded in the key; the sidecar has word onsets; bad versus and
# components columns are manifest errors naming row and column.
set -euo pipefail
TH=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
command -v ffmpeg >/dev/null || { echo "ffmpeg (tests only) is missing"; exit 1; }
cat >"$T/m.csv" <<'CSV'
text,components,versus:components,muted,size,crf,condition
Bom dia.,,,yes,160x90,0,full
Bom dia.,all,,yes,160x90,0,all
Bom dia.,face=200,,yes,160x90,0,face-200
Bom dia.,face=40,,yes,160x90,0,face-40
Bom dia.,face=8,,yes,160x90,0,face-8
Bom dia.,face=1,,yes,160x90,0,face-1
Bom dia.,face=1,all,yes,160x90,0,sbs-1
Bom dia.,face=40,all,yes,160x90,0,sbs-40
Bom dia.,lips=2,default,no,160x90,0,sbs-lips
Bom dia.,face=8,default,yes,160x90,0,sbs-8
CSV
"$TH" batch "$T/m.csv" -o "$T/o" --seed 9 --progress json 2>"$T/log"
test "$(grep -c '"type": "stimulus"' "$T/log")" = 10
grep -q '"type": "summary", "stimuli": 10, "in_shard": 10, "rendered": 10, "complete": 0, "failed": 0' "$T/log"
file() { awk -F, -v c="$1" 'NR > 1 && $NF == c { print $5 }' "$T/o/key.csv"; }
side() { awk -F, -v c="$1" 'NR > 1 && $NF == c { print $6 "," $7 }' "$T/o/key.csv"; }
psnr() { ffmpeg -v info -i "$1" -i "$2" -lavfi "[0:v][1:v]psnr" -f null - 2>&1 | grep -o 'average:[0-9.inf]*' | cut -d: -f2; }
full=$T/o/$(file full)
cmp "$full" "$T/o/$(file all)"
# PSNR against the full stimulus falls as the face keeps fewer components.
last=inf
for c in face-200 face-40 face-8 face-1; do
	p=$(psnr "$full" "$T/o/$(file $c)")
	echo "$c: $p dB"
	awk -v p="$p" -v l="$last" 'BEGIN { if (p == "inf" || (l != "inf" && p + 0 >= l + 0)) exit 1 }'
	last=$p
done
# Side by side: 160 + 16 + 160 wide; each half is exactly one variant (left/right as the key says).
sbs=$T/o/$(file sbs-1)
test "$(ffprobe -v error -select_streams v:0 -show_entries stream=width,height -of csv=p=0 "$sbs")" = "336,90"
half() { ffmpeg -v error -i "$1" -vf "crop=160:90:$2:0" -f rawvideo -pix_fmt yuv420p - | sha256sum; }
whole() { ffmpeg -v error -i "$1" -f rawvideo -pix_fmt yuv420p - | sha256sum; }
for row in 1:face-1 40:face-40 8:face-8; do
	s=sbs-${row%%:*}
	sbs=$T/o/$(file $s)
	if [ "$(side $s)" = "row,versus" ]; then rowx=0 versusx=176; else rowx=176 versusx=0; fi
	test "$(half "$sbs" $rowx)" = "$(whole "$T/o/$(file ${row#*:})")"
	test "$(half "$sbs" $versusx)" = "$(whole "$full")"
done
# The sides are balanced: 2 of the 4 side-by-side rows have the versus variant on the left.
test "$(grep -c ',versus,row,' "$T/o/key.csv")" = 2
test "$(grep -c ',row,versus,' "$T/o/key.csv")" = 2
# A side-by-side stimulus with sound has its row's speech.
ffprobe -v error -show_entries stream=codec_type -of csv=p=0 "$T/o/$(file sbs-lips)" | grep -q audio
# The sidecar has the words.
grep -q '"word": "Bom"' "$T/o/$(file full | sed 's/mp4$/json/')"
# Manifest errors, all at once, naming row and column; nothing rendered.
cat >"$T/bad.csv" <<'CSV'
text,components,versus:components,versus:text
Bom dia.,face=x,lips=0,Boa noite.
Bom dia.,nose=3,,
CSV
set +e
"$TH" batch "$T/bad.csv" -o "$T/bad" 2>"$T/err"; rc=$?
set -e
cat "$T/err"
test $rc = 1
grep -q "bad.csv:1:versus:text: the two sides of a side-by-side stimulus share the speech" "$T/err"
grep -q "bad.csv:2:components: --components 'face=x'" "$T/err"
grep -q "bad.csv:2:versus:components: --components 'lips=0'" "$T/err"
test ! -e "$T/bad"
# Regions are checked against the model before anything renders.
printf 'text,components\nBom dia.,nose=3\n' >"$T/bad2.csv"
set +e
"$TH" batch "$T/bad2.csv" -o "$T/bad2" 2>"$T/err2"; rc=$?
set -e
test $rc = 1
grep -q "bad2.csv:2:components: the model has no region 'nose' (regions: face, cheeks_lips, lips)" "$T/err2"
test ! -e "$T/bad2"
echo "batch variants OK"
