#!/usr/bin/env bash
# Issue 46: the library speaks in fields, not in the command line's flags. A library message names a field
# as {{field}} (base/error.h) and each front end words it (the CLI as its flag, serve as a request's
# member); the emotion's label "neutral" is spelt only where phonetics/emotions.tsv is read. Fails on the
# first string literal in src/ outside src/cli/ and src/python/ that spells a talkhead flag, and on a
# "neutral" literal outside the emotion table's reader (batch's report word for the neutral valence is
# not an emotion label). Other programs' flags that a message quotes (espeak-ng --voices, whisper
# --word_timestamps) are theirs.
set -euo pipefail
SRC=${1:?usage: library_words_test.sh SRC_DIR}
fail=0
flags=$(grep -rnE --include='*.cpp' --include='*.h' '"([^"\\]|\\.)*--[a-z][a-z0-9-]*' "$SRC" |
	grep -v -e "^$SRC/cli/" -e "^$SRC/python/" |
	grep -v -e 'espeak-ng --voices' -e 'whisper --word_timestamps' || true)
# Only string literals, not comments: a line whose flag sits after // is a comment.
flags=$(printf '%s\n' "$flags" | awk -F: 'NF { line=$0; sub(/^[^:]*:[^:]*:/, "", line); c=index(line, "//"); f=match(line, /"[^"]*--[a-z]/); if (f && (c == 0 || f < c)) print }')
if [ -n "$flags" ]; then echo "CLI flags spelt in the library (name the field as {{field}}):"; echo "$flags"; fail=1; fi
neutral=$(grep -rn --include='*.cpp' --include='*.h' '"neutral"' "$SRC" | grep -v -e "^$SRC/phonetics/emotion.cpp:" -e 'pair("neutral", pt ?' || true)
if [ -n "$neutral" ]; then echo "\"neutral\" spelt outside the emotion table's reader (Emotion(), Emotion::neutralLabel()):"; echo "$neutral"; fail=1; fi
# And the one writer of corpus rows (corpus/corpus.h chUnicampCsvRow): no hand-written corpus CSV.
hand=$(grep -rn --include='*.cpp' 'csv << .*\.cdv\b' "$SRC" || true)
if [ -n "$hand" ]; then echo "a corpus row written by hand (use chUnicampCsvRow):"; echo "$hand"; fail=1; fi
[ $fail = 0 ] && echo "library words: no flag, no neutral literal, no hand-written corpus row"
exit $fail
