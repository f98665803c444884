#!/usr/bin/env bash
# Issue 15: a full disk is an error naming the file and the reason, with a non-zero exit and nothing left
# behind — never a truncated or empty file with exit 0. Every writer is pointed at a small tmpfs: render's
# MP4, y4m, PNG frames and landmarks, say's speech, inspect's pictures, corpus synth, build's model and
# batch. Needs mount (root); skips (77) with a message where mounting is not allowed.
set -euo pipefail
TH=$1
T=$(mktemp -d)
D=$T/full
mkdir -p "$D"
if ! mount -t tmpfs -o size=256k tmpfs "$D" 2>/dev/null; then
	rm -rf "$T"
	echo "skipped: cannot mount a small tmpfs here (needs root and mount permission)"
	exit 77
fi
trap 'umount "$D" 2>/dev/null; rm -rf "$T"' EXIT
# Fill what is left but 64 KB (so each writer gets going, then fails).
dd if=/dev/zero of="$D/filler" bs=4k count=48 status=none
# expect_full NAME -- COMMAND…: exit 1, one error line naming a path under $D and "No space left on device",
# and nothing but the filler left in $D.
expect_full() {
	local name=$1; shift 2
	local rc=0
	"$@" >"$T/$name.out" 2>"$T/$name.err" || rc=$?
	if [ $rc != 1 ]; then echo "$name: exit $rc, expected 1"; cat "$T/$name.err"; exit 1; fi
	grep -q "^talkhead: error: $D/.*No space left on device" "$T/$name.err" || { echo "$name: no disk-full error naming the file:"; cat "$T/$name.err"; exit 1; }
	test "$(grep -c . "$T/$name.err")" = 1 || { echo "$name: more than one line on stderr:"; cat "$T/$name.err"; exit 1; }
	local left; left=$(ls -A "$D" | grep -v '^filler$' || true)
	if [ -n "$left" ]; then echo "$name: left behind in $D: $left"; exit 1; fi
	echo "$name: $(cut -c1-160 "$T/$name.err")"
}
S="Bom dia, como vai você hoje? Vamos ver o resultado amanhã."
expect_full mp4 -- "$TH" say "$S" --size 640x360 -o "$D/out.mp4" -q
expect_full y4m -- "$TH" say "$S" --size 640x360 --format y4m -o "$D/out.y4m" -q
expect_full frames -- "$TH" say "$S" --size 640x360 --frames "$D/frames" -o "$T/ok.mp4" -q
test ! -e "$T/ok.mp4"  # the video beside failed frames is not kept either
test -z "$(ls -A "$T" | grep '^\.tmp-' || true)"
expect_full landmarks -- "$TH" say "$(printf '%s ' $S $S $S $S $S $S)" --size 160x90 --landmarks-out "$D/points.tsv" -o "$T/ok2.mp4" -q
expect_full speech -- "$TH" say "$(printf '%s ' $S $S $S)" --size 160x90 --save-audio "$D/speech.wav" -o "$T/ok3.mp4" -q
test ! -e "$T/ok3.mp4"  # written before the render: the video is not made
# The other way round: the video fails, so the speech and the sidecar written beside it are not kept.
expect_full video -- "$TH" say "$S" --size 640x360 -o "$D/out.mp4" --save-audio "$T/speech.wav" --timeline-out "$T/t.json" -q
test ! -e "$T/speech.wav" && test ! -e "$T/t.json" && test -z "$(ls -A "$T" | grep '^\.tmp-' || true)"
expect_full inspect -- "$TH" inspect -q -o "$D/pictures"
expect_full synth -- "$TH" corpus synth -o "$D/corpus" --size 256x256 --emotions neutral,joy -q
# build: a model of a few synthetic images is larger than what is left.
"$TH" corpus synth -o "$T/corpus" --size 256x256 --emotions neutral -q
expect_full build -- "$TH" build "$T/corpus/corpus.csv" -o "$D/m.thm" -q
printf 'text,size,muted\n"%s %s %s",1280x720,yes\n' "$S" "$S" "$S" >"$T/m.csv"
# batch: its first stimulus fails (the row's error line), the run says so; key and orders are small and
# may be written — nothing else.
rc=0; "$TH" batch "$T/m.csv" -o "$D/stimuli" --progress none 2>"$T/batch.err" || rc=$?
test $rc = 1 && grep -q "No space left on device" "$T/batch.err" || { echo "batch: exit $rc"; cat "$T/batch.err"; exit 1; }
test -z "$(find "$D/stimuli" -name '*.mp4' -o -name '.tmp-*' 2>/dev/null)" || { echo "batch: left behind: $(ls -A "$D/stimuli")"; exit 1; }
echo "disk full: ok"
