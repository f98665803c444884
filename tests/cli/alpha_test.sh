#!/usr/bin/env bash
# Video with alpha (issue 33 §4): --background transparent writes VP9-with-alpha WebM and RGBA PNG frames
# whose alpha is opaque on the face, transparent away from it and feathered between; ffmpeg's libvpx-vp9
# decoder reads the alpha back. Formats without alpha are one-line errors; the output is deterministic.
set -euo pipefail
TH=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
trap 'echo "alpha_test.sh: failed at line $LINENO: $BASH_COMMAND" >&2' ERR
command -v ffmpeg >/dev/null || { echo "ffmpeg (tests only) is missing"; exit 1; }
"$TH" corpus synth -q -o "$T/c" --size 320x180 --emotions neutral
"$TH" build -q "$T/c/corpus.csv" -o "$T/face.thm"
say() { "$TH" say "Hello there, how are you?" --lang en-US --model "$T/face.thm" -q "$@"; }
say --background transparent -o "$T/a.webm" --frames "$T/f" --landmarks-out "$T/l.tsv"
# WebM: VP9 with its alpha mode, Vorbis sound, as many frames as the PNGs.
probe=$(ffprobe -v error -show_entries stream=codec_name:stream_tags=alpha_mode -of csv=p=0 "$T/a.webm")
echo "$probe"
grep -qx "vp9,1" <<<"$probe"
grep -qx "vorbis" <<<"$probe"
n=$(ls "$T/f" | wc -l)
test "$(ffprobe -v error -count_frames -select_streams v -show_entries stream=nb_read_frames -of csv=p=0 "$T/a.webm")" = "$n"
grep -qx rgba <<<"$(ffprobe -v error -show_entries stream=pix_fmt -of csv=p=0 "$T/f/frame_000010.png")"
# Frame 10's alpha, decoded from the WebM (libvpx-vp9 reads the alpha plane) and from the PNG, as bytes.
ffmpeg -v error -c:v libvpx-vp9 -i "$T/a.webm" -vf "select=eq(n\,10),alphaextract" -frames:v 1 -f rawvideo -pix_fmt gray "$T/webm.gray"
ffmpeg -v error -i "$T/f/frame_000010.png" -vf alphaextract -f rawvideo -pix_fmt gray "$T/png.gray"
test "$(stat -c %s "$T/webm.gray")" = $((320 * 180))
# The face's centre (the mean of frame 10's points), a corner, and the row through the centre.
read -r cx cy < <(awk -F'\t' 'NR == 12 { for (i = 3; i < NF; i += 2) { x += $i; y += $(i + 1); n++ } printf "%d %d\n", x / n, y / n }' "$T/l.tsv")
check() {
	od -An -v -tu1 -w320 "$1" | awk -v cx="$cx" -v cy="$cy" -v name="$1" '
		NR == 1 { corner = $1 }
		NR == cy + 1 { for (x = 1; x <= NF; x++) row[x - 1] = $x }
		END {
			if (row[cx] < 250) { print name ": centre alpha " row[cx]; exit 1 }
			if (corner > 3) { print name ": corner alpha " corner; exit 1 }
			soft = 0; zero = 0
			for (x = cx; x >= 0; x--) { if (row[x] > 10 && row[x] < 245) soft++; if (row[x] <= 3) zero++ }
			if (soft < 3) { print name ": a hard edge (" soft " soft pixels)"; exit 1 }
			if (zero < 10) { print name ": no transparent background left of the face"; exit 1 }
			print name ": centre " row[cx] ", corner " corner ", " soft " feathered pixels"
		}'
}
check "$T/png.gray"
check "$T/webm.gray"
# The WebM's alpha is the PNG's, within VP9's loss.
{ cmp -l "$T/png.gray" "$T/webm.gray" || true; } | awk 'function oct(s, v, i) { for (i = 1; i <= length(s); i++) v = v * 8 + substr(s, i, 1); return v }
	{ d = oct($2) - oct($3); if (d < 0) d = -d; s += d } END { m = s / (320 * 180); print "mean alpha difference " m; if (m > 2) exit 1 }'
# Deterministic: the same render twice is the same file (with --frames too: frames drawn in RGB for the
# PNGs are converted to YUV, which may differ from the frames drawn straight into YUV by a level).
say --background transparent -o "$T/b.webm" --frames "$T/f2"
cmp "$T/a.webm" "$T/b.webm"
# An opaque WebM (no alpha mode) by the extension alone.
say -o "$T/o.webm"
test -z "$(ffprobe -v error -show_entries stream_tags=alpha_mode -of csv=p=0 "$T/o.webm")"
grep -qx vp9 <<<"$(ffprobe -v error -show_entries stream=codec_name -of csv=p=0 "$T/o.webm")"  # not a pipe: grep -q would end it early (SIGPIPE)
# A live session rendered offline (talkhead live) with alpha too.
printf '%s\n' '{"frame": 0, "request": {"type": "say", "text": "Hello"}}' '{"type": "end", "frame": 30}' >"$T/session.jsonl"
"$TH" live "$T/session.jsonl" --model "$T/face.thm" --size 320x180 --background transparent -o "$T/live.webm" -q
grep -qx "vp9,1" <<<"$(ffprobe -v error -show_entries stream=codec_name:stream_tags=alpha_mode -of csv=p=0 "$T/live.webm")"
ffmpeg -v error -c:v libvpx-vp9 -i "$T/live.webm" -vf "select=eq(n\,10),alphaextract" -frames:v 1 -f rawvideo -pix_fmt gray "$T/live.gray"
od -An -v -tu1 "$T/live.gray" | tr -s ' ' '\n' | awk 'NF { n[$1 == 0 ? "zero" : $1 == 255 ? "one" : "soft"]++ } END { print "live alpha:", n["zero"], n["soft"], n["one"]; if (n["zero"] < 1000 || n["one"] < 1000 || n["soft"] < 100) exit 1 }'
# Errors: one line, non-zero, nothing written.
err() { local rc=0; "$TH" "$@" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" != 0; test "$(wc -l <"$T/e")" = 1; cat "$T/e"; }
err say "Hi" --model "$T/face.thm" --background transparent -o "$T/x.mp4" | grep -q "has no alpha channel"
err say "Hi" --model "$T/face.thm" --background transparent --format y4m -o - | grep -q "has no alpha channel"
err say "Hi" --model "$T/face.thm" --background transparent --format none | grep -q "needs --frames DIR"
err say "Hi" --model "$T/face.thm" --feather 3 -o "$T/x.webm" | grep -q "is for --background transparent"
err say "Hi" --model "$T/face.thm" --background green -o "$T/x.webm" | grep -q "takes opaque or transparent"
err say "Hi" --model "$T/face.thm" --format mp4 -o "$T/x.webm" | grep -q "ambiguous"
err say "Hi" --model "$T/face.thm" --crf 64 -o "$T/x.webm" | grep -q "crf"
err live "$T/session.jsonl" --model "$T/face.thm" --background transparent -o "$T/x.mp4" | grep -q "has no alpha channel"
# A --format against the output's extension is ambiguous for every pair (issue 46: one registry of formats).
err say "Hi" --model "$T/face.thm" --format y4m -o "$T/x.mp4" | grep -q "ambiguous"
test ! -e "$T/x.mp4" && test ! -e "$T/x.webm"
# live (and serve) parse how the face is drawn with render's own code (issue 46): another trajectory and
# dissolve draw other frames; a bad value is render's one-line error.
"$TH" live "$T/session.jsonl" --model "$T/face.thm" --size 320x180 --format y4m -o "$T/l1.y4m" -q
"$TH" live "$T/session.jsonl" --model "$T/face.thm" --size 320x180 --trajectory linear --dissolve hermite --format y4m -o "$T/l2.y4m" -q
! cmp -s "$T/l1.y4m" "$T/l2.y4m"
err live "$T/session.jsonl" --model "$T/face.thm" --trajectory bogus -o "$T/x.y4m" | grep -q "trajectory takes hermite, linear or monotone"
echo "alpha: ok"
