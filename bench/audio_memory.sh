#!/usr/bin/env bash
# Peak memory of a render against the length of its audio: a 3-s transcript over 10 s and over one hour of
# silent audio (16 kHz WAV), 640x360 at 5 fps so the hour renders quickly. The audio is decoded as the
# video advances, so the hour should cost what the 10 s cost (goal: within 10 %); the render also warns
# that most of the hour is a silent face.
# usage: bench/audio_memory.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 - "$tmp" <<'PY'
import sys, wave
for name, secs in (("short", 10), ("hour", 3600)):
    w = wave.open(f"{sys.argv[1]}/{name}.wav", "wb"); w.setnchannels(1); w.setsampwidth(2); w.setframerate(16000)
    zero = b"\0" * 32000
    for _ in range(secs): w.writeframes(zero)
    w.close()
PY
printf '0\t0.5\t_\n0.5\t1.0\ta\n1.0\t1.5\tp\n1.5\t2.5\ta\n2.5\t3.0\t_\n' >"$tmp/t.tsv"
for a in short hour; do
	/usr/bin/time -f "%e %M" -o "$tmp/time" "$build/talkhead" render --transcript "$tmp/t.tsv" --audio "$tmp/$a.wav" --size 640x360 --fps 5 \
		-o "$tmp/$a.mp4" 2>"$tmp/$a.log"
	read -r secs kib <"$tmp/time"
	printf '%-6s audio: %6.1f s wall, peak %6.1f MiB\n' "$a" "$secs" "$(echo "$kib / 1024" | bc -l)"
	eval "peak_$a=$kib"
	grep -h "warning" "$tmp/$a.log" || true
done
awk -v s="$peak_short" -v h="$peak_hour" 'BEGIN { printf "one hour / 10 s peak memory: %.3f (goal <= 1.10)\n", h / s }'
