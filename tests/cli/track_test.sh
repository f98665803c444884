#!/usr/bin/env bash
# Faces from real video (issue 10 §1, §3, §4): corpus landmarks on stills and a franck excerpt, corpus
# from-video by shape and by phones, build from it, compare, and bad input (one line, non-zero, no output).
set -euo pipefail
TH=$1; SHARED=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
err() { local rc=0; "$TH" "$@" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" != 0; test "$(wc -l <"$T/e")" = 1 || { cat "$T/e"; false; }; cat "$T/e"; }

# Bad input first (no shared data needed): a video with no face, a missing file, a missing dlib model.
ffmpeg -v error -f lavfi -i testsrc=size=320x240:rate=25:duration=2 -pix_fmt yuv420p "$T/noface.mp4"
err corpus landmarks "$T/noface.mp4" -o "$T/x" | grep -q "noface.mp4: no face found in any of 50 frames"
test ! -e "$T/x"
err corpus landmarks "$T/missing.mp4" -o "$T/x" | grep -q "missing.mp4: not found"
err corpus from-video "$T/noface.mp4" -o "$T/x" | grep -q "no face found"
test ! -e "$T/x"
err compare "$T/noface.mp4" "$T/noface.mp4" | grep -q "no face found"
printf 'not a video' >"$T/bad.mp4"
err corpus landmarks "$T/bad.mp4" -o "$T/x" | grep -q "bad.mp4: cannot open video"
test ! -e "$T/x"

F=$SHARED/franck; G=$SHARED/grid
if [ ! -d "$F" ] || [ ! -d "$G" ]; then echo "skipped: no shared data in $SHARED (franck/, grid/)"; exit 77; fi
err corpus landmarks "$F" -o "$T/x" --model "$T/none.dat" | grep -q "none.dat: dlib's 68-point face landmark model is missing (install the Debian package libdlib-data"
test ! -e "$T/x"

# Stills: 11 faces, 68 points each, a .pts per image, nothing lost.
"$TH" corpus landmarks "$F" -o "$T/stills" -q
test "$(ls "$T/stills"/*.pts | wc -l)" = 11
test "$(grep -c 'n_points: 68' "$T/stills"/franck_01829.pts)" = 1
test "$(awk -F'\t' 'NR > 1 && $3 != "lost"' "$T/stills/landmarks.tsv" | wc -l)" = 11
test -s "$T/stills/contact.png"

# A 10-s excerpt: every frame tracked, smoothing lowers the rigid points' jitter.
"$TH" corpus landmarks "$F/franck.mp4" --start 20 --duration 10 -o "$T/ex" 2>"$T/ex.log"
cat "$T/ex.log"
test "$(ls "$T/ex"/*.pts | wc -l)" = 240
test "$(awk -F'\t' 'NR > 1 && $3 == "lost"' "$T/ex/landmarks.tsv" | wc -l)" = 0
head -2 "$T/ex/landmarks.tsv" | tail -1 | grep -q $'^480\t20.000000\tdetected\t'
sed -E 's/.*jitter ([0-9.]+) raw -> ([0-9.]+).*/\1 \2/' "$T/ex.log" | awk '{ if (!($2 < 0.7 * $1)) { print "smoothed jitter " $2 " not below raw " $1; exit 1 } }'

# Corpus by mouth shape from a 60-s excerpt; the model builds; closed-lip visemes have smaller gaps than [a].
"$TH" corpus from-video "$F/franck.mp4" --duration 60 -o "$T/fc" -q
test -s "$T/fc/contact.png"
test "$(grep -vc '^#' "$T/fc/corpus.csv")" -ge 34
grep -q '^# baseface: frames/frame_' "$T/fc/corpus.csv"
gap() { # inner-lip gap (mean of the 3 pairs) / eye distance, of the first row with this CDV
	grep -v '^#' "$T/fc/corpus.csv" | awk -F',' -v cdv="$1" '$8 == cdv { for (i = 0; i < 68; i++) { split(substr($(10 + i), 2, length($(10 + i)) - 2), p, ";"); x[i] = p[1]; y[i] = p[2] }
		d = 0; n = split("61:67 62:66 63:65", pairs, " "); for (k = 1; k <= n; k++) { split(pairs[k], ab, ":"); d += sqrt((x[ab[1]] - x[ab[2]])^2 + (y[ab[1]] - y[ab[2]])^2) }
		printf "%.4f\n", d / 3 / sqrt((x[45] - x[36])^2 + (y[45] - y[36])^2); exit }'
}
echo "gaps: p1 $(gap p1) p2 $(gap p2) a $(gap a)"
awk -v p1="$(gap p1)" -v p2="$(gap p2)" -v a="$(gap a)" 'BEGIN { if (!(p1 < a && p2 < a && a > 0.05)) { print "closed-lip visemes are not closer than [a]"; exit 1 } }'
"$TH" build -q "$T/fc/corpus.csv" -o "$T/franck.thm"
"$TH" inspect "$T/franck.thm" | grep -q "scheme     ibug-68: 68 points"

# Corpus by phones from a GRID clip with its own audio and text (aligned inside); it builds too.
"$TH" corpus from-video "$G/bbaf2n.mpg" --text "bin blue at f two now" --lang en-US -o "$T/gc" -q
grep -v '^#' "$T/gc/corpus.csv" | cut -d, -f8 | sort -u | tr '\n' ' ' | tee "$T/gc.cdvs"; echo
grep -q ' p1 \| p2 ' "$T/gc.cdvs"   # the [b] of "bin" and "blue"
"$TH" build -q "$T/gc/corpus.csv" -o "$T/grid.thm"
err corpus from-video "$F/franck.mp4" --text "hello" -o "$T/x" | grep -q "franck.mp4: has no audio track"

# compare: a clip against itself is r = 1, LMD 0; against another speaker much lower.
"$TH" compare --json "$G/bbaf2n.mpg" "$G/bbaf2n.mpg" | tee "$T/self.json"
grep -q '"r_lag0": 1.0000' "$T/self.json"
grep -q '"lmd": 0.0000' "$T/self.json"
grep -q '"coverage_real": 1.0000' "$T/self.json"
"$TH" compare --json "$G/bbaf2n.mpg" "$G/swiz3n.mpg" | tee "$T/other.json"
sed -E 's/.*"r_lag0": ([-0-9.]+).*/\1/' "$T/other.json" | awk '{ if (!($1 < 0.5)) { print "another speaker correlates at " $1; exit 1 } }'
echo "track tests passed"
