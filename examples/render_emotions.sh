#!/usr/bin/env bash
# Renders "Que notícia excelente!" (the thesis's worked example, examples/que_noticia.TextGrid) with the
# default face for a few emotions. usage: examples/render_emotions.sh [OUT_DIR] [EMOTION...]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/examples}"; shift || true
emotions=("$@"); [ ${#emotions[@]} -gt 0 ] || emotions=(neutral joy anger sadness fear)
th="${TALKHEAD:-$root/${TALKHEAD_BUILD_DIR:-build}/talkhead}"
mkdir -p "$out"
for e in "${emotions[@]}"; do
	"$th" render --transcript "$root/examples/que_noticia.TextGrid" --emotion "$e" -o "$out/que_noticia_$e.mp4" -q
	echo "  $out/que_noticia_$e.mp4"
done
