#!/usr/bin/env bash
# talkhead serve (issue 16): latency and pace, measured side by side with and without a competing process
# on one core. Per run: a 29 s session with four say requests and three speak requests (audio with a TextGrid, with
# its text only (issue 49: aligned by the server), and alone (its phones recognised)).
#   say -> start frame:   from the request's arrival to the encoded frame where the mouth starts moving
#                         (the server's latency_ms; goal <= 200 ms), and as the client sees it (send to the
#                         utterance_started event)
#   speak -> frames:      the same for a speak request (goal <= 100 ms; with text <= 150 ms, alone <= 300 ms;
#                         streamed in 0.2-s PCM pieces with the text on the first, from the first piece's arrival)
#   late frames:          frames sent more than one frame after their time (goal: none at 30 fps, 1280x720)
# Then (issue 28):
#   capacity:             N sessions at once, each speaking (all at the same moments: the worst case); how
#                         many had no late frame; and how many a server with the default --max-load admits
#                         when 12 arrive a second apart and each speaks every 2.5 s
#   flood:                the paced session above beside one that floods (1 000 queued say, a 30 MB
#                         message, stops): its say latency and late frames, side by side with it alone
#   admission (issue 45):  a burst of 40 sessions opened at once, and a ramp of one a second, each speaking
#                         every 2.5 s, with the default --max-load: how many are admitted, the share of late
#                         frames of the worst admitted session (goal ≤ 1 %), and whether the first refusal
#                         came before the first late frame (the burst's clients start first and connect
#                         together 2 s later: starting 40 processes is not the server's load)
# usage: bench/serve.sh [BUILD_DIR] [--only capacity|flood|latency|admission]   (CLIENT=… another client)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build"
only=""
while [ $# -gt 0 ]; do
	case "$1" in
	--only) only=$2; shift 2 ;;
	*) build=$1; shift ;;
	esac
done
TH="$build/talkhead" CLIENT="${CLIENT:-$build/tests/talkhead_live_client}"
T=$(mktemp -d)
pids=()
trap 'for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$T"' EXIT
"$TH" say "Good morning, how can I help you today?" --lang en-US -q --size 160x90 --no-audio -o "$T/x.mp4" --save-audio "$T/a.wav" --save-transcript "$T/a.TextGrid"
/usr/bin/python3 - "$T" <<'PY'
import base64, json, sys
t = sys.argv[1]
json.dump({'type': 'speak', 'id': 'speak', 'lang': 'en-US', 'audio': base64.b64encode(open(f'{t}/a.wav', 'rb').read()).decode(),
           'transcript': open(f'{t}/a.TextGrid').read()}, open(f'{t}/speak.json', 'w'))
# Issue 49: the same sound with its text only (aligned by the server), and alone (its phones recognised).
a = base64.b64encode(open(f'{t}/a.wav', 'rb').read()).decode()
json.dump({'type': 'speak', 'id': 'text', 'lang': 'en-US', 'audio': a, 'text': 'Good morning, how can I help you today?'}, open(f'{t}/speak-text.json', 'w'))
json.dump({'type': 'speak', 'id': 'heard', 'lang': 'en-US', 'audio': a}, open(f'{t}/speak-heard.json', 'w'))
# Issue 49 part 2: the same sound streamed as raw PCM in 0.2-s pieces with its text on the first: sent as they
# would play (a TTS at real time) and all at once (a TTS faster than real time).
w = open(f'{t}/a.wav', 'rb').read()
pcm = w[w.index(b'data') + 8:]
step = 22050 * 2 // 5
pieces = [pcm[k:k + step] for k in range(0, len(pcm), step)]
for name in ('rt', 'burst'):
    for k, p in enumerate(pieces):
        req = {'type': 'speak', 'audio': base64.b64encode(p).decode()}
        if k == 0: req.update({'id': 'stream-' + name, 'lang': 'en-US', 'encoding': 'pcm_s16le', 'sample_rate': 22050, 'text': 'Good morning, how can I help you today?'})
        else: req['continue'] = 'stream-' + name
        if k + 1 < len(pieces): req['more'] = True
        json.dump(req, open(f'{t}/stream-{name}-{k}.json', 'w'))
open(f'{t}/stream-count', 'w').write(str(len(pieces)))
PY
streams=()
for k in $(seq 0 $(( $(cat "$T/stream-count") - 1 ))); do streams+=("$(( 29000 + 200 * k )):@$T/stream-rt-$k.json" "$(( 35000 + 5 * k )):@$T/stream-burst-$k.json"); done
run() {  # SIZE LOAD(0|1) NAME
	local size=$1 load=$2 name=$3 loader=0
	"$TH" serve --listen 127.0.0.1:0 --size "$size" >"$T/$name.out" 2>"$T/$name.err" &
	local server=$!
	pids+=("$server")
	for _ in $(seq 100); do grep -q serving "$T/$name.out" 2>/dev/null && break; sleep 0.1; done
	local port
	port=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/$name.out")
	if [ "$load" = 1 ]; then /usr/bin/python3 -c 'while True: pass' & loader=$!; pids+=("$loader"); fi
	"$CLIENT" "$port" "$T/$name" 41 \
		'1000:{"type":"say","id":"s1","text":"Hello, nice to meet you."}' \
		'5000:{"type":"say","id":"s2","text":"The weather is lovely today, is it not?"}' \
		'9000:{"type":"say","id":"s3","text":"I can talk for as long as you like."}' \
		'13000:{"type":"say","id":"s4","text":"Thank you, and goodbye!"}' \
		"17000:@$T/speak.json" "21000:@$T/speak-text.json" "25000:@$T/speak-heard.json" "${streams[@]}"
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
        except Exception: sent['speak'] = float(ms)  # a speak request (its id is not parsed from the long line)
        continue
    e = json.loads(text)
    if e['type'] == 'utterance_started' and 'latency_ms' in e:
        server[e['id']] = e['latency_ms']; client[e['id']] = float(ms) - sent.get(e['id'], float('nan'))
says = [server[k] for k in ('s1', 's2', 's3', 's4') if k in server]
csays = [client[k] for k in ('s1', 's2', 's3', 's4') if k in client]
stats = re.search(r'(\d+) frames, ([\d.]+) ms each to draw and encode, (\d+) late by more than a frame \(latest (\d+) ms', open(sys.argv[2]).read())
print(f"{sys.argv[3]:<26} say {statistics.median(says):6.1f} ms (max {max(says):6.1f}; client {statistics.median(csays):6.1f})"
      f"   speak {server.get('speak', float('nan')):6.1f} ms (with text {server.get('text', float('nan')):6.1f}, alone {server.get('heard', float('nan')):6.1f}; streamed with text: real time {server.get('stream-rt', float('nan')):6.1f}, burst {server.get('stream-burst', float('nan')):6.1f})   frames {stats.group(1)}, {stats.group(2)} ms each, {stats.group(3)} late (latest {stats.group(4)} ms)")
PY
}
serve_on() {  # NAME ARGS…: a server on a free port; sets $port, $server
	local name=$1; shift
	"$TH" serve --listen 127.0.0.1:0 "$@" >"$T/$name.out" 2>"$T/$name.err" &
	server=$!
	pids+=("$server")
	for _ in $(seq 100); do grep -q serving "$T/$name.out" 2>/dev/null && break; sleep 0.1; done
	port=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/$name.out")
}
late_report() {  # ERR: "K of N sessions without a late frame (latest …)"
	/usr/bin/python3 - "$1" <<'PY'
import re, sys
rows = re.findall(r'session (\d+): (\d+) frames, ([\d.]+) ms each to draw and encode, (\d+) late by more than a frame \(latest (\d+) ms', open(sys.argv[1]).read())
clean = sum(1 for r in rows if r[3] == '0')
late = sum(int(r[3]) for r in rows); frames = sum(int(r[1]) for r in rows)
work = sum(float(r[2]) for r in rows) / max(1, len(rows))
print(f"{clean:2d} of {len(rows):2d} sessions without a late frame; {late} of {frames} frames late (worst {max([int(r[4]) for r in rows] or [0])} ms); {work:.1f} ms per frame")
PY
}
capacity() {
	echo "capacity: N sessions at once for 12 s, each saying two sentences (--max-load 0: all admitted)"
	for size in 320x180 640x360; do
		for n in 2 4 6 8 10 12; do
			serve_on "cap-$size-$n" --size "$size" --max-sessions 64 --max-load 0
			local cs=()
			for i in $(seq "$n"); do
				"$CLIENT" "$port" "$T/cap-$size-$n-$i" 12 '1000:{"type":"say","text":"Hello, nice to meet you, how are you today?"}' \
					'6000:{"type":"say","text":"The weather is lovely, is it not?"}' >/dev/null 2>&1 &
				cs+=($!)
			done
			wait "${cs[@]}" || true
			kill -TERM "$server"; wait "$server" 2>/dev/null || true
			printf '  %-8s %2d sessions: %s\n' "$size" "$n" "$(late_report "$T/cap-$size-$n.err")"
		done
	done
	for size in 320x180 640x360 1280x720; do
		serve_on "adm-$size" --size "$size" --max-sessions 64
		local cs=()
		for i in $(seq 12); do
			local says=()
			for at in $(seq 500 2500 $(( (16 - i) * 1000 ))); do says+=("$at:{\"type\":\"say\",\"text\":\"Hello, nice to meet you, how are you today?\"}"); done
			"$CLIENT" "$port" "$T/adm-$size-$i" $((17 - i)) "${says[@]}" >/dev/null 2>&1 &
			cs+=($!)
			sleep 1
		done
		wait "${cs[@]}" || true
		kill -TERM "$server"; wait "$server" 2>/dev/null || true
		admitted=$(grep -c 'opened' "$T/adm-$size.err" || true)
		printf '  %-8s default --max-load 0.9, 12 arriving 1 s apart, each speaking: %d admitted, %d refused; %s\n' "$size" "$admitted" "$(grep -c 'session refused' "$T/adm-$size.err" || true)" \
			"$(late_report "$T/adm-$size.err")"
	done
}
flood() {
	echo "flood: a paced 640x360 session saying a sentence every 3 s for 20 s, alone and beside a flooding session"
	/usr/bin/python3 - "$T" <<'PY'
import sys
t = sys.argv[1]
with open(f'{t}/flood.args', 'w') as f:
    for i in range(1000): f.write(f'2000:{{"type":"say","id":"f{i}","text":"Flood number {i}."}}\n')
    f.write('8000:{"type":"stop"}\n')
    for i in range(1000): f.write(f'9000:{{"type":"say","id":"g{i}","text":"Again {i}."}}\n')
    f.write('14000:{"type":"stop"}\n')
    f.write(f'15000:@{t}/big.json\n')
with open(f'{t}/big.json', 'w') as f:
    f.write('{"type": "say", "id": "big", "text": "hi", "junk": [' + ','.join(['0'] * 15_000_000) + ']}')
PY
	mapfile -t floods <"$T/flood.args"
	for mode in alone flooded; do
		serve_on "flood-$mode" --size 640x360 --max-load 0 --max-queued-requests 2000 --max-queued-speech 3600
		local says=()
		for k in $(seq 0 5); do says+=("$((1000 + 3000 * k)):{\"type\":\"say\",\"id\":\"s$k\",\"text\":\"Hello, nice to meet you, how are you?\"}"); done
		"$CLIENT" "$port" "$T/paced-$mode" 20 "${says[@]}" &
		local a=$!
		sleep 0.3
		if [ "$mode" = flooded ]; then "$CLIENT" "$port" "$T/flooder" 19 "${floods[@]}" >/dev/null 2>&1 & fi
		wait $a
		sleep 0.5
		kill -TERM "$server"; wait "$server" 2>/dev/null || true
		/usr/bin/python3 - "$T/paced-$mode.events" "$T/flood-$mode.err" "$mode" <<'PY'
import json, re, statistics, sys
lat = [json.loads(l.split('\t', 1)[1])['latency_ms'] for l in open(sys.argv[1]) if '"utterance_started"' in l and 'latency_ms' in l]
row = re.search(r'session 1: (\d+) frames, ([\d.]+) ms each to draw and encode, (\d+) late by more than a frame \(latest (\d+) ms', open(sys.argv[2]).read())
print(f"  {sys.argv[3]:<8} say -> first frame {statistics.median(lat):6.1f} ms (max {max(lat):6.1f}, {len(lat)} says); paced session: {row.group(3)} of {row.group(1)} frames late (latest {row.group(4)} ms), {row.group(2)} ms per frame")
PY
	done
}
admission() {
	echo "admission: default --max-load 0.9, each session speaking every 2.5 s"
	for size in 640x360 320x180; do
		for mode in burst ramp; do
			local name="adm2-$size-$mode" n=40 gap=0 length=15
			[ "$mode" = ramp ] && n=24 gap=1 length=27
			"$TH" serve --listen 127.0.0.1:0 --size "$size" --max-sessions 64 >"$T/$name.out" 2> >(while IFS= read -r l; do printf '%s %s\n' "$(date +%s%N)" "$l"; done >"$T/$name.err") &
			server=$!
			pids+=("$server")
			for _ in $(seq 150); do grep -q serving "$T/$name.out" 2>/dev/null && break; sleep 0.1; done
			port=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/$name.out")
			local cs=() t0 when=()
			# The burst: the clients started first, all connecting at the same moment 2 s later (starting 40
			# processes takes the 2 cores for a while, which is not the server's doing).
			[ "$gap" = 0 ] && when=(--connect-at $(( $(date +%s%3N) + 2000 )))
			t0=$(( $(date +%s%N) + (gap == 0 ? 2000000000 : 0) ))
			for i in $(seq "$n"); do
				local says=() left=$(( length - (i - 1) * gap ))
				for at in $(seq 500 2500 $(( left * 1000 - 1000 ))); do says+=("$at:{\"type\":\"say\",\"text\":\"Hello, nice to meet you, how are you today?\"}"); done
				"$CLIENT" "${when[@]}" "$port" "$T/$name-$i" "$left" "${says[@]}" >/dev/null 2>&1 &
				cs+=($!)
				[ "$gap" = 0 ] || sleep "$gap"
			done
			wait "${cs[@]}" || true
			kill -TERM "$server"; wait "$server" 2>/dev/null || true
			sleep 0.3
			/usr/bin/python3 - "$T/$name.err" "$size" "$mode" "$t0" <<'PY'
import re, sys
lines = open(sys.argv[1]).read().splitlines()
t0 = int(sys.argv[4])
rows = [re.search(r'session (\d+): (\d+) frames, [\d.]+ ms each to draw and encode, (\d+) late', l) for l in lines]
rows = [(int(m.group(2)), int(m.group(3))) for m in rows if m]
refused = [int(l.split()[0]) for l in lines if 'session refused' in l]
late = [int(l.split()[0]) for l in lines if 'first late frame' in l]
worst = max([100 * l / f for f, l in rows if f] or [0])
bad = sum(1 for f, l in rows if f and l > 0.01 * f)
first_ref = f'{(refused[0] - t0) / 1e9:.1f} s' if refused else 'never'
first_late = f'{(late[0] - t0) / 1e9:.1f} s' if late else 'never'
order = 'before' if refused and (not late or refused[0] < late[0]) else ('after' if refused else 'n/a')
print(f"  {sys.argv[2]:<8} {sys.argv[3]:<5}: {len(rows):2d} admitted, {len(refused):2d} refused; {sum(l for f, l in rows)} of {sum(f for f, l in rows)} frames late, "
      f"worst session {worst:.1f} % late, {bad} over 1 %; first refusal at {first_ref}, first late frame at {first_late} (refusal {order})")
PY
		done
	done
}
echo "talkhead serve, 30 fps ($(nproc) cores)"
if [ -z "$only" ] || [ "$only" = latency ]; then
	echo "latency: 20 s sessions"
	run 640x360 0 "640x360"
	run 1280x720 0 "1280x720"
	run 1280x720 1 "1280x720 + one busy core"
fi
if [ -z "$only" ] || [ "$only" = capacity ]; then capacity; fi
if [ -z "$only" ] || [ "$only" = flood ]; then flood; fi
if [ -z "$only" ] || [ "$only" = admission ]; then admission; fi
