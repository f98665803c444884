#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# A contact sheet of a face's six expressions (neutral, joy, distress, anger, fear, hate) to look at (issue
# 31): each at rest (a silence keypose) and saying an open vowel (/a/'s keypose), from the neutral images by
# action units (shape, skin and the mouth's sample, D61, D71) and, where the model has the emotion's own
# images, from those. Blinks and head motion off; each tile is the face's box from the rendered points.
# usage: bench/expression_sheet.sh OUT.png [--model M.thm] [--lang L]
#   (docs/images/default-face-expressions.png is this with the default face; a face from research data
#   — franck, GRID — is for looking at, not for committing)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
th="${TALKHEAD:-$root/${TALKHEAD_BUILD_DIR:-build}/talkhead}"
[ -x "$th" ] || { echo "expression_sheet.sh: $th not built (scripts/build)" >&2; exit 1; }
out=""; model=(); lang=pt-BR
while [ $# -gt 0 ]; do
	case "$1" in
		--model) model=(--model "$2"); shift ;;
		--lang) lang="$2"; shift ;;
		*) out="$1" ;;
	esac
	shift
done
[ -n "$out" ] || { echo "usage: bench/expression_sheet.sh OUT.png [--model M.thm] [--lang L]" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# 0–0.5 s silence (its keypose at 0.25 s), 0.5–1.0 s /a/ (0.75 s), then silence: frames 7 and 22 at 30 fps.
printf '0.0\t0.5\t_\n0.5\t1.0\ta\n1.0\t1.5\t_\n' >"$tmp/t.tsv"
emotions=(neutral joy distress anger fear hate)
for e in "${emotions[@]}"; do
	for src in au corpus; do
		d="$tmp/$e.$src"
		"$th" render --transcript "$tmp/t.tsv" --lang "$lang" --notation ipa "${model[@]}" --emotion "$e" --emotion-source "$src" \
			--pauses thesis --blinks off --head-motion off --fps 30 --format none --frames "$d" --landmarks-out "$d.tsv" 2>"$d.log"
		# a corpus render of an emotion the model lacks is neutral: left out of the sheet
		if [ "$src" = corpus ] && [ "$e" != neutral ] && grep -q "$e .* -> neutral\|no $e images" "$d.log"; then rm -rf "$d"; fi
	done
done
/usr/bin/python3 - "$tmp" "$out" "${emotions[@]}" <<'PY'
import os, sys
import numpy as np
from PIL import Image, ImageDraw
tmp, out, emotions = sys.argv[1], sys.argv[2], sys.argv[3:]
def tile(e, src, frame):
    d = f"{tmp}/{e}.{src}"
    if not os.path.isdir(d): return None
    lines = [l.rstrip("\n").split("\t") for l in open(d + ".tsv")]
    first = 4 if lines[0][2:4] == ["status", "confidence"] else 2  # the landmarks TSV (D78), or an older render's
    xy = np.array([float(v) for v in lines[1:][frame][first:]]).reshape(-1, 2)
    x0, y0 = xy.min(0); x1, y1 = xy.max(0); m = 0.12 * (x1 - x0)
    im = Image.open(f"{d}/frame_{frame:06d}.png").convert("RGB")
    top = max(0, int(y0 - 2.2 * m)); bottom = min(im.height, int(y1 + m))
    height = bottom - top; cx = 0.5 * (x0 + x1); width = int(round(0.8 * height))
    left = int(min(max(0, cx - width / 2), im.width - width))
    return im.crop((left, top, left + width, bottom))
rows = [("at rest, from the neutral images by action units", "au", 7), ("at rest, from the corpus images", "corpus", 7),
        ("/a/, from the neutral images by action units", "au", 22), ("/a/, from the corpus images", "corpus", 22)]
tiles = [[tile(e, src, f) for e in emotions] for _, src, f in rows]
ref = next(t for r in tiles for t in r if t is not None)
w = 240; h = int(round(ref.height * w / ref.width))
keep = [i for i, r in enumerate(tiles) if any(t is not None for t in r[1:])]  # a corpus row needs an emotion of its own
sheet = Image.new("RGB", (w * len(emotions), h * len(keep)), (255, 255, 255))
draw = ImageDraw.Draw(sheet)
for k, i in enumerate(keep):
    for j, t in enumerate(tiles[i]):
        if t is not None: sheet.paste(t.resize((w, h), Image.LANCZOS), (j * w, k * h))
        if k == 0: draw.text((j * w + 4, 2), emotions[j], fill=(255, 255, 255))
    draw.text((4, k * h + 14), rows[i][0], fill=(255, 255, 255))
sheet.save(out)
print(f"wrote {out}: {len(keep)} rows × {len(emotions)} expressions")
PY
