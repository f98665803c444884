#!/usr/bin/env bash
# talkhead say: time to the first frame of a one-sentence input streamed as y4m (goal <= 150 ms), and the
# total time against the speech's duration. usage: bench/say.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$build/talkhead" inspect -q >/dev/null  # page cache warm
/usr/bin/python3 - "$build/talkhead" <<'PY'
import subprocess, sys, time
th = sys.argv[1]
text = "Que notícia excelente! Vamos ver o resultado amanhã."
t0 = time.perf_counter()
p = subprocess.Popen([th, "say", text, "--format", "y4m", "-o", "-", "-q"], stdout=subprocess.PIPE)
header = p.stdout.readline()
w = int(header.split(b" W")[1].split()[0]); h = int(header.split(b" H")[1].split()[0])
first = None; frames = 0
while True:
    line = p.stdout.readline()
    if not line: break
    data = p.stdout.read(w * h * 3 // 2)
    frames += 1
    if first is None: first = time.perf_counter() - t0
p.wait()
total = time.perf_counter() - t0
print(f"say, one sentence, y4m stream: first frame after {first * 1000:.0f} ms (goal <= 150 ms); "
      f"{frames} frames ({frames / 30:.2f} s of speech) in {total:.2f} s = {frames / 30 / total:.2f}x real time")
PY
/usr/bin/time -f "%e" -o "$tmp/t" "$build/talkhead" say "Que notícia excelente! Vamos ver o resultado amanhã." -o "$tmp/s.mp4" --timing -q 2>"$tmp/log" || true
sed -n 's/^timing: /say to MP4 stages: /p' "$tmp/log"
echo "say to MP4 total: $(cat "$tmp/t") s"
