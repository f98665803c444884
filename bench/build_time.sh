#!/usr/bin/env bash
# Times `talkhead build` on a corpus and prints seconds per image and peak memory.
# usage: bench/build_time.sh [CORPUS] [BUILD_DIR]   (default: the IMM frontal database, 120 images 800x600)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
corpus="${1:-$root/../shared/data/imm-frontal/IMM-Frontal_Face_DB_SMALL}"
build="${2:-$root/build}"
[ -e "$corpus" ] || { echo "corpus not found: $corpus" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/time -f "%e %M" -o "$tmp/time" "$build/talkhead" build "$corpus" -o "$tmp/m.thm" 2>"$tmp/log"
read -r secs kib <"$tmp/time"
n=$(grep -o 'built [^:]*: [0-9]*' "$tmp/log" | grep -o '[0-9]*$')
size=$(stat -c %s "$tmp/m.thm")
echo "corpus: $corpus"
sed 's/^/  /' "$tmp/log"
awk -v s="$secs" -v n="$n" -v k="$kib" -v b="$size" 'BEGIN {
	printf "build: %d images in %.2f s = %.4f s/image on %d cores; peak memory %.0f MiB; model file %.1f MiB\n", n, s, s / n, '"$(nproc)"', k / 1024, b / 1048576 }'
