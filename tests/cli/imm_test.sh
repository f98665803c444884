#!/usr/bin/env bash
# IMM frontal end to end: build on 11 of the 12 people, inspect (PNGs), reconstruct the 12th held out.
set -euo pipefail
TH=$1; DATA=$2/imm-frontal/IMM-Frontal_Face_DB_SMALL
if [ ! -d "$DATA/asf" ]; then echo "IMM data not found in $DATA: skipped"; exit 77; fi
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
"$TH" build "$DATA" --exclude '12_*' -o "$T/imm11.thm" 2>"$T/build.log"
cat "$T/build.log"
grep -q "110 images 800x600, 73 points (imm-73)" "$T/build.log"
"$TH" inspect "$T/imm11.thm" -o "$T/png" | tee "$T/inspect.log"
grep -q "samples    110" "$T/inspect.log"
for f in baseface_mesh modes_face modes_cheeks_lips modes_lips explained_variance contact_sheet; do
	test -s "$T/png/$f.png" || { echo "missing $f.png"; exit 1; }
done
"$TH" inspect "$T/imm11.thm" -q --recon "$DATA" --include '12_*' | tee "$T/recon.log"
test "$(grep -c '^12_' "$T/recon.log")" = 10
# Held-out person: the mean PSNR per region must be sensible (a face model generalises a little) but
# clearly below the training-image reconstruction (≥ 45 dB).
awk '/^mean/ { for (i = 1; i <= NF; i++) if ($i == "|") { psnr = $(i + 3); if (psnr < 18 || psnr > 40) bad = 1; print "region", $(i + 1), "PSNR", psnr } }
     END { exit bad }' "$T/recon.log"
# Training images come back at ≥ 45 dB with all components kept.
"$TH" inspect "$T/imm11.thm" -q --recon "$DATA" --include '01_0[1-3]*' | tee "$T/train.log"
awk '/^mean/ { for (i = 1; i <= NF; i++) if ($i == "|") { psnr = $(i + 3); if (psnr < 45) bad = 1 } } END { exit bad }' "$T/train.log"
