#!/usr/bin/env bash
# talkhead render end to end: MP4 (H.264 + AAC) decoded back, y4m, frames, landmarks, determinism, errors.
set -euo pipefail
TH=$1; DATA=$2; SHARED=$3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
trap 'echo "render_test.sh: failed at line $LINENO: $BASH_COMMAND" >&2' ERR
# A small face: the synthetic corpus at 320x180, two emotions, all visemes.
"$TH" corpus synth -q -o "$T/c" --size 320x180 --emotions neutral,joy
"$TH" build -q "$T/c/corpus.csv" -o "$T/face.thm"
TG=$DATA/transcripts/que_noticia.TextGrid   # 1.30 s
# 2.0 s of audio (a 220 Hz tone, 44.1 kHz mono WAV).
/usr/bin/python3 - "$T/tone.wav" <<'PY'
import math, struct, sys, wave
w = wave.open(sys.argv[1], "wb"); w.setnchannels(1); w.setsampwidth(2); w.setframerate(44100)
w.writeframes(b"".join(struct.pack("<h", int(8000 * math.sin(2 * math.pi * 220 * i / 44100))) for i in range(88200))); w.close()
PY
probe() { ffprobe -v error -count_frames -select_streams "$2" -show_entries stream="$3" -of csv=p=0 "$1"; }
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --audio "$T/tone.wav" --emotion joy -o "$T/a.mp4" --landmarks-out "$T/a.tsv"
# Video: H.264, 30 fps, round(2.0 × 30) = 60 frames; audio: AAC, 2.0 s; durations within one frame.
test "$(probe "$T/a.mp4" v:0 codec_name,nb_read_frames,r_frame_rate)" = "h264,30/1,60"
test "$(probe "$T/a.mp4" a:0 codec_name)" = "aac"
vd=$(probe "$T/a.mp4" v:0 duration); ad=$(probe "$T/a.mp4" a:0 duration)
awk -v v="$vd" -v a="$ad" 'BEGIN { d = v - a; if (d < 0) d = -d; if (d > 1 / 30 || a < 1.99 || a > 2.05) { print "durations " v " " a; exit 1 } }'
test -z "$(ffmpeg -v warning -i "$T/a.mp4" -f null - 2>&1)"   # decodes with no warnings
# --fps 29.97 is 30000/1001 exactly: round(2.0 × 30000/1001) = 60 frames, frame 59 at 59 × 1001/30000 s;
# 30.0 is 30; say takes the same options.
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --audio "$T/tone.wav" --fps 29.97 -o "$T/ntsc.mp4" --landmarks-out "$T/ntsc.tsv"
test "$(probe "$T/ntsc.mp4" v:0 nb_read_frames,r_frame_rate)" = "30000/1001,60"
test "$(tail -1 "$T/ntsc.tsv" | cut -f1,2)" = "59	1.968633"
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --fps 30.0 --format y4m -o "$T/thirty.y4m"
head -c 40 "$T/thirty.y4m" | grep -q " F30:1 "
# Another aspect (square, portrait) keeps the face's proportions: the eye distance over the eyes-to-mouth
# distance of the output landmarks equals the 16:9 render's within 1 % (crop and pad); stretch does not.
ratio() { /usr/bin/python3 - "$1" <<'PY'
import sys
rows = [l.rstrip('\n').split('\t') for l in open(sys.argv[1])]
h, r = rows[0], rows[20]
assert h[:4] == ['frame', 'time', 'status', 'confidence'] and r[2] == 'drawn', h[:4]  # the landmarks TSV (D78)
P = lambda n: (float(r[h.index(n + '_x')]), float(r[h.index(n + '_y')]))
mid = lambda a, b: ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
d = lambda a, b: ((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** .5
re, le, m = mid(P('REYE1'), P('REYE3')), mid(P('LEYE1'), P('LEYE3')), mid(P('RM2'), P('LM2'))
print(d(re, le) / d(mid(re, le), m))
PY
}
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --size 640x360 -o "$T/wide.mp4" --landmarks-out "$T/wide.tsv"
wide=$(ratio "$T/wide.tsv")
for case in 480x480:face 480x480:crop 480x480:pad 360x640:face 360x640:crop 360x640:pad 360x640:stretch; do
	size=${case%:*}; fit=${case#*:}
	"$TH" render -q --model "$T/face.thm" --transcript "$TG" --size "$size" --fit "$fit" -o "$T/$fit.mp4" --landmarks-out "$T/$fit.tsv"
	test "$(probe "$T/$fit.mp4" v:0 width,height | tr , x)" = "$size"
	r=$(ratio "$T/$fit.tsv")
	if [ "$fit" = stretch ]; then want=far; else want=near; fi
	awk -v a="$r" -v b="$wide" -v w="$want" -v c="$case" 'BEGIN { e = a / b - 1; if (e < 0) e = -e
		if ((w == "near" && e > 0.01) || (w == "far" && e < 0.1)) { print c ": ratio " a " vs 16:9 " b; exit 1 } }'
done
# The default fit keeps the whole face in a portrait frame (issue 47; the even crop cutting a face is a
# unit test's: Render.theDefaultFitKeepsTheWholeFaceForEverySourceAspect).
/usr/bin/python3 - "$T/face.tsv" <<'PY'
import sys
rows = [l.rstrip('\n').split('\t') for l in open(sys.argv[1])]
h = rows[0]
for axis, size in (('_x', 360), ('_y', 640)):
    v = [float(r[i]) for r in rows[1:] for i, n in enumerate(h) if n.endswith(axis)]
    assert min(v) >= 0 and max(v) <= size, (axis, min(v), max(v))
PY
# A transcript covering a small part of a long audio renders the whole audio and says how much is silent face.
/usr/bin/python3 -c "import wave; w = wave.open('$T/long.wav', 'wb'); w.setnchannels(1); w.setsampwidth(2); w.setframerate(16000); w.writeframes(bytes(2 * 16000 * 30)); w.close()"
"$TH" render --model "$T/face.thm" --transcript "$TG" --audio "$T/long.wav" --fps 5 -o "$T/long.mp4" 2>"$T/long.err"
grep -q "warning: $T/long.wav: the transcript covers 1.3 s of 30.0 s of audio; the face holds its last keypose, silent, for the other 28.7 s" "$T/long.err"
test "$(probe "$T/long.mp4" v:0 nb_read_frames)" = 150
# Landmarks: a header and one row per frame with 4 + 2 × 56 columns (frame, time, status, confidence: D78).
test "$(wc -l <"$T/a.tsv")" = 61
awk -F'\t' 'NR > 1 && (NF != 116 || $3 != "drawn") { print "bad landmark row " NR; exit 1 }' "$T/a.tsv"
# Determinism: the same inputs give the same file.
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --audio "$T/tone.wav" --emotion joy -o "$T/b.mp4" --threads 1
cmp "$T/a.mp4" "$T/b.mp4"
# No audio: the transcript sets the duration (1.30 s → 39 frames); y4m stream and PNG frames.
"$TH" render -q --model "$T/face.thm" --transcript "$TG" -o "$T/n.mp4" --fps 25
test "$(probe "$T/n.mp4" v:0 nb_read_frames)" = 33   # round(1.3 × 25) = 32.5 → 33
test -z "$(ffprobe -v error -select_streams a -show_entries stream=index -of csv=p=0 "$T/n.mp4")"
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --format y4m -o - --size 160x90 >"$T/s.y4m"
head -c 64 "$T/s.y4m" | head -1 | grep -q '^YUV4MPEG2 W160 H90 F30:1 Ip A1:1 C420jpeg XCOLORRANGE=LIMITED$'
test "$(grep -c FRAME "$T/s.y4m")" = 39
test "$(stat -c %s "$T/s.y4m")" = $(( $(head -1 "$T/s.y4m" | wc -c) + 39 * (6 + 160 * 90 * 3 / 2) ))
! grep -q swscaler "$T/o" 2>/dev/null
# The YUV frames (drawn straight into YUV for y4m and MP4) read back as the RGB frames (--frames), so the
# range and chroma siting are what readers assume (a range mix-up gives ~27 dB); and the thesis's warp
# order (--warp keypose) draws the same frames as the direct warp.
psnr() { ffmpeg -v info -i "$1" -i "$2" -lavfi "[0:v]format=rgb24[a];[1:v]format=rgb24[b];[a][b]psnr" -f null - 2>&1 | grep -o 'average:[0-9.inf]*' | cut -d: -f2; }
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --format y4m -o "$T/d.y4m"
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --format y4m -o "$T/k.y4m" --warp keypose
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --format y4m -o "$T/r.y4m" --frames "$T/rgb"
awk -v p="$(psnr "$T/d.y4m" "$T/rgb/frame_%06d.png")" 'BEGIN { if (p != "inf" && p < 35) { print "y4m vs PNG frames: " p " dB"; exit 1 } }'
awk -v p="$(psnr "$T/d.y4m" "$T/k.y4m")" 'BEGIN { if (p != "inf" && p < 40) { print "direct vs keypose warp: " p " dB"; exit 1 } }'
"$TH" render -q --model "$T/face.thm" --transcript "$TG" -o "$T/f.mp4" --frames "$T/frames" --no-audio --audio "$T/tone.wav"
test "$(ls "$T/frames" | wc -l)" = 60
# Real speech in another container: GRID's MPEG-1 clip carries MP2 audio; English words via espeak-ng.
if [ -f "$SHARED/grid/id2_vcd_swwp2s.mpg" ]; then
	"$TH" render -q --model "$T/face.thm" --lang en-US --unknown nearest --transcript "$SHARED/grid/swwp2s.align" --audio "$SHARED/grid/id2_vcd_swwp2s.mpg" -o "$T/g.mp4"
	n=$(probe "$T/g.mp4" v:0 nb_read_frames); [ "$n" -ge 88 ] && [ "$n" -le 91 ]   # the clip's ~3 s of MP2 audio
fi
# A model of odd size renders one pixel smaller (4:2:0 video needs even sizes).
"$TH" corpus synth -q -o "$T/odd" --size 201x113 --emotions neutral --visemes sil,a,u,p1,i1
"$TH" build -q "$T/odd/corpus.csv" -o "$T/odd.thm"
"$TH" render -q --model "$T/odd.thm" --transcript "$TG" -o "$T/odd.mp4"
test "$(ffprobe -v error -select_streams v:0 -show_entries stream=width,height -of csv=p=0 "$T/odd.mp4")" = "200,112"
# Errors: one line, non-zero exit, no output file.
err() { local rc=0; "$TH" "$@" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" != 0; test "$(wc -l <"$T/e")" = 1; cat "$T/e"; }
err render --model "$T/face.thm" --transcript "$TG" --emotion grumpy -o "$T/x.mp4" | grep -q "unknown emotion 'grumpy'"
/usr/bin/python3 -c "import wave; w=wave.open('$T/short.wav','wb'); w.setnchannels(1); w.setsampwidth(2); w.setframerate(16000); w.writeframes(b'\0\0'*8000); w.close()"
err render --model "$T/face.thm" --transcript "$TG" --audio "$T/short.wav" -o "$T/x.mp4" | grep -q "the transcript (1.300 s) is longer than the audio (0.500 s) by 0.800 s"
err render --model "$T/none.thm" --transcript "$TG" -o "$T/x.mp4" | grep -q "$T/none.thm: cannot open model"
err render --model "$T/face.thm" --transcript "$TG" --trajectory cubic -o "$T/x.mp4" | grep -q "trajectory takes hermite, linear or monotone"
! test -e "$T/x.mp4"
# --trajectory monotone: the same keyposes, other frames between (D56).
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --format y4m -o "$T/m.y4m" --trajectory monotone --landmarks-out "$T/m.tsv"
"$TH" render -q --model "$T/face.thm" --transcript "$TG" --format y4m -o "$T/h.y4m" --landmarks-out "$T/h.tsv"
test "$(stat -c %s "$T/m.y4m")" = "$(stat -c %s "$T/h.y4m")"
! cmp -s "$T/m.tsv" "$T/h.tsv"
err render --model "$T/face.thm" --transcript "$TG" -o "$T/no/such/dir/x.mp4" | grep -q "does not exist"
/usr/bin/python3 -c "import wave; w=wave.open('$T/empty.wav','wb'); w.setnchannels(1); w.setsampwidth(2); w.setframerate(16000); w.close()"
err render --model "$T/face.thm" --transcript "$TG" --audio "$T/empty.wav" -o "$T/x.mp4" | grep -q "$T/empty.wav"
# A damaged cached appearance (read on demand, while the writer thread is busy): one line naming the model.
/usr/bin/python3 - "$T/face.thm" "$T/bad.thm" <<'PY'
import sys
d = bytearray(open(sys.argv[1], "rb").read())
i = d.find(b"\0\0\0appearances") + len(b"\0\0\0appearances") + 4 + 8 + 5000  # sample 0 of the face region
d[i] ^= 0x40
open(sys.argv[2], "wb").write(d)
PY
awk '!/^#/ { print; exit }' "$T/c/corpus.csv" | grep -q '^neutral_p1.png,neutral,'
{ for i in $(seq 0 20); do printf '%d.0\t%d.5\ta\n%d.5\t%d.9\tp\n%d.9\t%d.0\ti\n' $i $i $i $i $i $((i + 1)); done; } >"$T/long.tsv"
err render --model "$T/bad.thm" --transcript "$T/long.tsv" --emotion neutral -o "$T/x.mp4" | grep -q "$T/bad.thm: corrupt model file: checksum mismatch in the cached appearance of sample 0"
test ! -e "$T/x.mp4"
test -z "$(ls -A "$T" | grep '^\.tmp-' || true)"
echo "render ok"
