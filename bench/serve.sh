#!/usr/bin/env bash
# talkhead serve (issue 16): latency and pace, measured side by side with and without a competing process
# on one core. Per run: a 20 s session with four say requests and one speak request (audio + TextGrid).
#   say -> start frame:   from the request's arrival to the encoded frame where the mouth starts moving
#                         (the server's latency_ms; goal <= 200 ms), and as the client sees it (send to the
#                         utterance_started event)
#   speak -> frames:      the same for a speak request (goal <= 100 ms)
#   late frames:          frames sent more than one frame after their time (goal: none at 30 fps, 1280x720)
# usage: bench/serve.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
TH="$build/talkhead" CLIENT="$build/tests/talkhead_live_client"
T=$(mktemp -d)
pids=()
trap 'for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$T"' EXIT
"$TH" say "Good morning, how can I help you today?" --lang en-US -q --size 160x90 --no-audio -o "$T/x.mp4" --save-audio "$T/a.wav" --save-transcript "$T/a.TextGrid"
/usr/bin/python3 - "$T" <<'PY'
import base64, json, sys
t = sys.argv[1]
json.dump({'type': 'speak', 'id': 'speak', 'lang': 'en-US', 'audio': base64.b64encode(open(f'{t}/a.wav', 'rb').read()).decode(),
           'transcript': open(f'{t}/a.TextGrid').read()}, open(f'{t}/speak.json', 'w'))
PY
run() {  # SIZE LOAD(0|1) NAME
	local size=$1 load=$2 name=$3 loader=0
	"$TH" serve --listen 127.0.0.1:0 --size "$size" >"$T/$name.out" 2>"$T/$name.err" &
	local server=$!
	pids+=("$server")
	for _ in $(seq 100); do grep -q serving "$T/$name.out" 2>/dev/null && break; sleep 0.1; done
	local port
	port=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/$name.out")
	if [ "$load" = 1 ]; then /usr/bin/python3 -c 'while True: pass' & loader=$!; pids+=("$loader"); fi
	"$CLIENT" "$port" "$T/$name" 20 \
		'1000:{"type":"say","id":"s1","text":"Hello, nice to meet you."}' \
		'5000:{"type":"say","id":"s2","text":"The weather is lovely today, is it not?"}' \
		'9000:{"type":"say","id":"s3","text":"I can talk for as long as you like."}' \
		'13000:{"type":"say","id":"s4","text":"Thank you, and goodbye!"}' \
		"17000:@$T/speak.json"
	[ "$loader" = 0 ] || kill "$loader"
	sleep 0.5
	kill "$server"; wait "$server" 2>/dev/null || true
	/usr/bin/python3 - "$T/$name.events" "$T/$name.err" "$name" <<'PY'
import json, re, statistics, sys
sent, server, client = {}, {}, {}
for line in open(sys.argv[1]):
    ms, text = line.rstrip('\n').split('\t', 1)
    if text.startswith('>'):
        try: sent[json.loads(text[1:])['id']] = float(ms)
        except Exception: sent['speak'] = float(ms)
        continue
    e = json.loads(text)
    if e['type'] == 'utterance_started' and 'latency_ms' in e:
        server[e['id']] = e['latency_ms']; client[e['id']] = float(ms) - sent.get(e['id'], float('nan'))
says = [server[k] for k in ('s1', 's2', 's3', 's4') if k in server]
csays = [client[k] for k in ('s1', 's2', 's3', 's4') if k in client]
stats = re.search(r'(\d+) frames, ([\d.]+) ms each to draw and encode, (\d+) late by more than a frame \(latest (\d+) ms', open(sys.argv[2]).read())
print(f"{sys.argv[3]:<26} say {statistics.median(says):6.1f} ms (max {max(says):6.1f}; client {statistics.median(csays):6.1f})"
      f"   speak {server.get('speak', float('nan')):6.1f} ms   frames {stats.group(1)}, {stats.group(2)} ms each, {stats.group(3)} late (latest {stats.group(4)} ms)")
PY
}
echo "talkhead serve, 30 fps, 20 s sessions ($(nproc) cores)"
run 640x360 0 "640x360"
run 1280x720 0 "1280x720"
run 1280x720 1 "1280x720 + one busy core"
