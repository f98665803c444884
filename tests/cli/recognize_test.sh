#!/usr/bin/env bash
# Issue 49 part 1 (D95): a talking head from speech audio alone — `visemes --audio` prints the recognised
# phones with a confidence column; `render --audio` alone renders them and says the timing was recognised;
# --text still wins; silence is a still face and a warning; nothing, a missing model and a transcript with
# --audio on visemes are one clear line each, with no output. The speech is grid-s4's shipped GRID clip.
set -euo pipefail
TH=$1; SRC=$2
command -v ffmpeg >/dev/null || { echo "ffmpeg not installed: skipped"; exit 77; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
G=$SRC/models/faces/grid-s4
ff() { ffmpeg -nostdin -v error -y "$@"; }
ff -i "$G/s4hq_pbbc4a.mpg" -vn -ac 1 -ar 22050 "$T/speech.wav"

# visemes --audio: the phones, their CDVs and keyposes, and a confidence per phone.
"$TH" visemes --audio "$T/speech.wav" -o "$T/v.tsv" 2>"$T/v.err"
cat "$T/v.err"
head -1 "$T/v.tsv" | grep -qx $'start\tend\tphone\tcdv\tkeypose\tconfidence'
test "$(awk -F'\t' 'NR > 1 && $3 != "_"' "$T/v.tsv" | wc -l)" -ge 10
awk -F'\t' 'NR > 1 && ($6 < 0 || $6 > 1) { exit 1 }' "$T/v.tsv"
grep -qE 'recognised from the audio \(no timing given\): [0-9]+ phones, speech [0-9.]+–[0-9.]+ s, mean confidence (0\.9|1\.0)' "$T/v.err"
# The same twice (deterministic), and as JSON with a confidence member.
"$TH" visemes --audio "$T/speech.wav" -o "$T/v2.tsv" 2>/dev/null
cmp "$T/v.tsv" "$T/v2.tsv"
"$TH" visemes --audio "$T/speech.wav" --out-format json 2>/dev/null | grep -q '"confidence": '

# render --audio alone: a video as long as the audio, its lips from the recognised phones.
"$TH" render --audio "$T/speech.wav" --lang en-US -o "$T/r.mp4" --size 320x180 --timeline-out "$T/r.json" 2>"$T/r.err"
cat "$T/r.err"
grep -q 'recognised from the audio (no timing given)' "$T/r.err"
test -s "$T/r.mp4"
d=$(ffprobe -v error -show_entries format=duration -of csv=p=0 "$T/r.mp4")
awk -v d="$d" 'BEGIN { exit !(d > 2.9 && d < 3.2) }'
grep -q '"cdv": "p1"\|"cdv": "p2"' "$T/r.json"
# --text wins: aligned, not recognised.
"$TH" render --audio "$T/speech.wav" --text "place blue by c four again" --lang en-US -o "$T/t.mp4" --size 320x180 2>"$T/t.err"
! grep -q 'recognised from the audio' "$T/t.err"
grep -q 'aligned' "$T/t.err"
# --dialog (Rhubarb's): a hint — aligned when it matches; when it does not, recognised with a warning.
"$TH" visemes --audio "$T/speech.wav" -o "$T/heard.tsv" 2>/dev/null
"$TH" render --audio "$T/speech.wav" --dialog "place blue by c four again" --lang en-US -o "$T/d.mp4" --size 320x180 2>"$T/d.err"
grep -q 'aligned' "$T/d.err"
"$TH" render --audio "$T/speech.wav" --dialog "My grandmother baked fresh bread every Sunday morning." --lang en-US -o "$T/d2.mp4" --size 320x180 \
	--timeline-out "$T/d2.json" 2>"$T/d2.err"
cat "$T/d2.err"
grep -q "warning: .*the text does not match the audio.*the dialog was a hint; the phones were recognised from the audio instead" "$T/d2.err"
grep -q 'recognised from the audio (no timing given)' "$T/d2.err"
test -s "$T/d2.mp4"
# Another language: en-US's phones, said in one line.
"$TH" visemes --audio "$T/speech.wav" --lang pt-BR -o /dev/null 2>"$T/pt.err"
grep -q "the phones are en-US's" "$T/pt.err"

# A batch row with audio alone is rendered from it, as render --audio is.
printf 'audio,emotion,muted,size,lang\nspeech.wav,joy,yes,160x90,en-US\n' >"$T/m.csv"
"$TH" batch "$T/m.csv" -o "$T/b" -q
test "$(grep -c ',ok,' "$T/b/key.csv")" = 1
"$TH" render --audio "$T/speech.wav" --emotion joy --no-audio --size 160x90 --lang en-US -o "$T/b1.mp4" -q
test -s "$(ls "$T/b"/*.mp4 | head -1)"

# Silence: a still face and a warning, exit 0.
ff -f lavfi -i anullsrc=r=16000:cl=mono -t 2 "$T/quiet.wav"
"$TH" render --audio "$T/quiet.wav" -o "$T/q.mp4" --size 320x180 2>"$T/q.err"
grep -q 'warning: .*quiet.wav: no speech in the audio: it is silent.*the face stays still' "$T/q.err"
test -s "$T/q.mp4"

# A melody of steady notes is not speech: its phones are left out (a still face), with a warning.
ff -f lavfi -i "sine=f=440:d=6" -f lavfi -i "sine=f=660:d=6" -filter_complex "[0][1]amix=2,volume='if(lt(mod(t,0.6),0.35),1,0.02)':eval=frame" \
	-ar 22050 -ac 1 "$T/melody.wav"
"$TH" visemes --audio "$T/melody.wav" -o "$T/melody.tsv" 2>"$T/melody.err"
cat "$T/melody.err"
grep -q 'warning: .*melody.wav: [0-9]* phones left out where the sound does not change as speech does' "$T/melody.err"
test "$(awk -F'\t' 'NR > 1 && $3 != "_"' "$T/melody.tsv" | wc -l)" = 0

# Bad input: one line naming the file, non-zero exit, no output.
: >"$T/empty.wav"
if "$TH" render --audio "$T/empty.wav" -o "$T/e.mp4" 2>"$T/e.err"; then echo "an empty file rendered"; exit 1; fi
cat "$T/e.err"
test "$(wc -l <"$T/e.err")" = 1
grep -q 'empty.wav' "$T/e.err"
test ! -e "$T/e.mp4"
if TALKHEAD_SPHINX_MODEL="$T/nowhere" "$TH" visemes --audio "$T/speech.wav" -o "$T/m.tsv" 2>"$T/m.err"; then echo "no model, yet phones"; exit 1; fi
cat "$T/m.err"
grep -q 'install the Debian package pocketsphinx-en-us' "$T/m.err"
test ! -e "$T/m.tsv"
if "$TH" visemes "$G/s4_pbbc4a.align" --audio "$T/speech.wav" 2>"$T/u.err"; then echo "both taken"; exit 1; fi
grep -q 'give a TRANSCRIPT or --audio, not both' "$T/u.err"
echo "recognise ok"
