#!/usr/bin/env bash
# Generation and model-build time and peak memory of the full synthetic corpus (23 x 34 = 782 images)
# at 1280x720 and at 1920x1080 (the thesis's size; its corrAAM took 3.9 min on a notebook).
# usage: bench/synth_corpus.sh [BUILD_DIR] [SIZES...]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"; shift || true
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(1280x720 1920x1080)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)"
for size in "${sizes[@]}"; do
	/usr/bin/time -f "%e %M" -o "$tmp/t1" "$build/talkhead" corpus synth -q -o "$tmp/c" --size "$size"
	/usr/bin/time -f "%e %M" -o "$tmp/t2" "$build/talkhead" build -q "$tmp/c/corpus.csv" -o "$tmp/m.thm"
	read -r s1 k1 <"$tmp/t1"; read -r s2 k2 <"$tmp/t2"
	corpus_mib=$(du -sm "$tmp/c" | cut -f1); model_mib=$(( $(stat -c %s "$tmp/m.thm") / 1048576 ))
	awk -v size="$size" -v s1="$s1" -v k1="$k1" -v c="$corpus_mib" -v s2="$s2" -v k2="$k2" -v m="$model_mib" 'BEGIN {
		printf "%-10s corpus synth: %6.1f s, peak %5.0f MiB, %4d MiB of PNG | build: %6.1f s (%.3f s/image), peak %5.0f MiB, model %5d MiB | total %6.1f s\n",
			size, s1, k1 / 1024, c, s2, s2 / 782, k2 / 1024, m, s1 + s2 }'
	rm -rf "$tmp/c" "$tmp/m.thm"
done
