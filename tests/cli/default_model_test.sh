#!/usr/bin/env bash
# The embedded default face: built from the full synthetic corpus (782 images + the closed-eyes one); every training image
# reconstructs at >= 45 dB per region in the shape-free frame with all components; inspect finds it
# without arguments.
set -euo pipefail
TH=$1; BUILD=$2
MODEL=$BUILD/models/default.thm; CORPUS=$BUILD/models/default-corpus/corpus.csv
if [ ! -f "$MODEL" ]; then echo "default model not built ($MODEL; TALKHEAD_BUILD_DEFAULT_MODEL=OFF?): skipped"; exit 77; fi
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
"$TH" inspect | tee "$T/summary"
grep -q "samples    783" "$T/summary"
grep -q "ch-unicamp-56: 56 points" "$T/summary"
"$TH" inspect -q --recon "$CORPUS" >"$T/recon.log"
test "$(grep -c '\.png' "$T/recon.log")" = 783
awk '/\.png/ { for (i = 1; i <= NF; i++) if ($i == "|") { if ($(i + 2) < 45) { print "below 45 dB: " $0; bad = 1 } n++ } }
     END { print n " region reconstructions checked"; exit bad }' "$T/recon.log"
grep '^mean' "$T/recon.log"
