#!/usr/bin/env bash
# talkhead corpus synth from the command line: format, determinism, seed, errors.
set -euo pipefail
TH=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
sub=(--emotions joy,anger,sadness --visemes a,f1,p1,sh1 --size 640x360)
"$TH" corpus synth -q -o "$T/a" "${sub[@]}"
"$TH" corpus synth -q -o "$T/b" "${sub[@]}" --threads 1
"$TH" corpus synth -q -o "$T/c" "${sub[@]}" --seed 2
# 3 × 4 images + the CSV; CH-Unicamp format: 9 + 56 columns, emotion and CDV labels canonical.
test "$(ls "$T/a" | wc -l)" = 13
test "$(wc -l <"$T/a/corpus.csv")" = 12
awk -F, '{ if (NF != 65) { print "bad column count " NF; exit 1 } }' "$T/a/corpus.csv"
grep -q '^distress_sh1.png,distress,_,_,ʃ,i,_,ʃ1,-,(' "$T/a/corpus.csv"
grep -q '^joy_f1.png,joy,_,_,f,i,_,f1,-,(' "$T/a/corpus.csv"
# Same seed: byte-identical, whatever the thread count.
diff -r "$T/a" "$T/b"
# Another seed: the same labels, other jitter (points and pixels differ).
diff <(cut -d, -f1-9 "$T/a/corpus.csv") <(cut -d, -f1-9 "$T/c/corpus.csv")
! cmp -s "$T/a/corpus.csv" "$T/c/corpus.csv"
! cmp -s "$T/a/joy_a.png" "$T/c/joy_a.png"
# The corpus builds into a model that reconstructs its training images.
"$TH" build -q "$T/a/corpus.csv" -o "$T/m.thm"
"$TH" inspect -q "$T/m.thm" --recon "$T/a/corpus.csv" >"$T/recon.log"
awk '/^[a-z].*\.png/ { for (i = 1; i <= NF; i++) if ($i == "|") if ($(i + 2) < 45) { print "low PSNR: " $0; bad = 1 } } END { exit bad }' "$T/recon.log"
# Errors: one line, exit 2 for usage, nothing written.
err() { local rc=0; "$TH" "$@" >"$T/out" 2>"$T/err" || rc=$?; test "$rc" = 2; test "$(wc -l <"$T/err")" = 1; cat "$T/err"; }
err corpus synth -o "$T/x" --emotions joy,grumpy | grep -q "unknown emotion 'grumpy'"
err corpus synth -o "$T/x" --visemes zz | grep -q "unknown viseme 'zz'"
err corpus synth -o "$T/x" --size 99999x2 | grep -q -- "--size must be"
err corpus frobnicate | grep -q "unknown subcommand"
test ! -e "$T/x"
echo "synth corpus ok"
