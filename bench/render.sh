#!/usr/bin/env bash
# Render speed: a 10-second pt-BR utterance with the default face at 1280x720 and at 1920x1080, 30 fps:
# frames per second end to end, multiple of real time, time of each stage, peak memory. Then a 10-minute
# utterance at 1280x720 for peak memory (it must stay flat as the utterance grows).
# usage: bench/render.sh [BUILD_DIR] [--long]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 "$root/bench/make_utterance.py" 10 "$tmp/u10.tsv"
echo "machine: $(nproc) cores; model: $build/models/default.thm"
"$build/talkhead" inspect -q >/dev/null  # warm the page cache with the model
run() {  # run LABEL SIZE TRANSCRIPT
	/usr/bin/time -f "%e %M" -o "$tmp/time" "$build/talkhead" render --transcript "$3" --emotion joy --size "$2" -o "$tmp/out.mp4" --timing 2>"$tmp/log"
	read -r secs kib <"$tmp/time"
	frames=$(grep -o '^rendered [^:]*: [0-9]*' "$tmp/log" | grep -o '[0-9]*$')
	dur=$(grep -o '([0-9.]* s of' "$tmp/log" | grep -o '[0-9.]*')
	awk -v l="$1" -v s="$secs" -v f="$frames" -v d="$dur" -v k="$kib" 'BEGIN {
		printf "%-22s %5d frames in %6.2f s: %6.1f frames/s, %5.2fx real time, peak %5.0f MiB\n", l, f, s, f / s, d / s, k / 1024 }'
	sed -n 's/^timing: /    stages: /p' "$tmp/log"
}
run "10 s at 1280x720" 1280x720 "$tmp/u10.tsv"
run "10 s at 1920x1080" 1920x1080 "$tmp/u10.tsv"
if [ "${2:-}" = "--long" ]; then
	/usr/bin/python3 "$root/bench/make_utterance.py" 600 "$tmp/u600.tsv"
	run "10 min at 1280x720" 1280x720 "$tmp/u600.tsv"
fi
# The encoder is the limit: x264 alone (ffmpeg, libx264 veryfast, CRF 20, the same frames as y4m) against
# the whole render to MP4, alternating, median of 5. Ratio = render throughput / x264-alone throughput.
"$build/talkhead" render --transcript "$tmp/u10.tsv" --emotion joy --size 1280x720 --format y4m -o "$tmp/frames.y4m" -q
if command -v ffmpeg >/dev/null; then
	for i in 1 2 3 4 5; do
		/usr/bin/time -f "%e" -o "$tmp/t" ffmpeg -v error -y -i "$tmp/frames.y4m" -c:v libx264 -preset veryfast -crf 20 -pix_fmt yuv420p "$tmp/x.mp4"
		cat "$tmp/t" >>"$tmp/x264"
		/usr/bin/time -f "%e" -o "$tmp/t" "$build/talkhead" render --transcript "$tmp/u10.tsv" --emotion joy --size 1280x720 -o "$tmp/out.mp4" -q
		cat "$tmp/t" >>"$tmp/ours"
	done
	x=$(sort -n "$tmp/x264" | sed -n 3p); o=$(sort -n "$tmp/ours" | sed -n 3p)
	awk -v x="$x" -v o="$o" 'BEGIN { printf "720p, 324 frames: x264 alone %.2f s, whole render %.2f s: %.2fx the encoder'"'"'s throughput (goal >= 0.9)\n", x, o, x / o }'
fi
