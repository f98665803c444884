#!/usr/bin/env bash
# Labels canonical at the model boundary (issue 11, D36). The same corpus with its CDVs written <k1> (as the
# thesis's CSV writes them), or with ASCII and emotion aliases, builds a model that renders exactly the
# frames of the canonical one, with no substitution (before, every bracketed keypose fell back to silence);
# an unknown label is one error line naming the CSV file and row; an unlabelled corpus still builds.
set -euo pipefail
TH=$1; DATA=$2; SRC=$3
TG=$DATA/transcripts/que_noticia.TextGrid   # k1 i1 t1 o s1 e l2 ɪ … with joy
VIS=$SRC/phonetics/visemes.tsv
for f in "$TG" "$VIS"; do [ -f "$f" ] || { echo "skipped: $f not found"; exit 77; }; done
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
# A small face: the synthetic corpus (canonical labels) at 160x90, two emotions, all 34 visemes.
"$TH" corpus synth -q -o "$T/a" --size 160x90 --emotions neutral,joy
# The same images (linked) with the labels rewritten: b = <CDV>; c = ASCII aliases and emotion aliases.
mkdir "$T/b" "$T/c"
for f in "$T"/a/*.png; do ln -s "$f" "$T/b/"; ln -s "$f" "$T/c/"; done
# (The unlabelled closed-eyes row, emotion "-", keeps its label as written.)
awk -F, -v OFS=, '/^#/ || $2 == "-" { print; next } { $8 = "<" $8 ">"; print }' "$T/a/corpus.csv" >"$T/b/corpus.csv"
awk -F'\t' -v OFS=, '
	FNR == NR { if ($0 !~ /^#/ && $1 != "label") ascii[$1] = $4; next }
	/^#/ { print; next }
	{ FS = ","; $0 = $0 } $2 == "-" { print; next }
	{ $8 = ascii[$8]; $2 = ($2 == "joy" ? "Happiness" : toupper($2)); print }' "$VIS" "$T/a/corpus.csv" >"$T/c/corpus.csv"
grep -q '^joy_k1.png,joy,.*,<k1>,-,(' "$T/b/corpus.csv"
grep -q '^neutral_sh1.png,NEUTRAL,.*,sh1,-,(' "$T/c/corpus.csv"
grep -q '^joy_E.png,Happiness,.*,E,-,(' "$T/c/corpus.csv"
! grep -q ',ʃ1,' "$T/c/corpus.csv"
for v in a b c; do
	"$TH" build -q "$T/$v/corpus.csv" -o "$T/$v.thm"
	"$TH" render --model "$T/$v.thm" --transcript "$TG" --emotion joy --format y4m -o "$T/$v.y4m" 2>"$T/$v.err"
	if grep -q substituted "$T/$v.err"; then echo "model $v: $(cat "$T/$v.err")"; exit 1; fi
done
# The models store the same (canonical) keys, so they are the same file, and render the same frames.
cmp "$T/a.thm" "$T/b.thm"
cmp "$T/a.thm" "$T/c.thm"
cmp "$T/a.y4m" "$T/b.y4m"
cmp "$T/a.y4m" "$T/c.y4m"
# Unknown labels: exit 1, one line naming the file and row, no model written.
err() { local rc=0; "$TH" build -q "$1" -o "$T/x.thm" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" = 1; test "$(wc -l <"$T/e")" = 1; test ! -e "$T/x.thm"; cat "$T/e"; }
awk -F, -v OFS=, 'NR == 5 { $8 = "<x9>" } { print }' "$T/b/corpus.csv" >"$T/b/bad-cdv.csv"
err "$T/b/bad-cdv.csv" | grep -q "^talkhead: error: $T/b/bad-cdv.csv:5: unknown viseme '<x9>' (known: p1 p2 "
awk -F, -v OFS=, 'NR == 7 { $2 = "grumpy" } { print }' "$T/c/corpus.csv" >"$T/c/bad-emotion.csv"
err "$T/c/bad-emotion.csv" | grep -q "^talkhead: error: $T/c/bad-emotion.csv:7: unknown emotion 'grumpy' (known: neutral, joy, "
# Unlabelled rows (emotion "-", the image stem as CDV, as IMM and iBUG corpora are read) still build.
mkdir "$T/d"
for f in "$T"/a/*.png; do ln -s "$f" "$T/d/"; done
awk -F, -v OFS=, '/^#/ { print; next } { $2 = "-"; $8 = $1; sub(/\.png$/, "", $8); print }' "$T/a/corpus.csv" >"$T/d/corpus.csv"
"$TH" build -q "$T/d/corpus.csv" -o "$T/d.thm"
echo "labels ok"
