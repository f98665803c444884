#!/usr/bin/env bash
# talkhead serve, second round (issue 45 items 2 and 4), from outside, on loopback, every loop bounded:
#   lockout   600 connections without the token (8 addresses) do not keep token holders out; the 10-s
#             authentication deadline holds for idle TCP and for upgrades that never authenticate
#   ids       kept as the client wrote them: 2 and "2" are two ids; 1.5, 1e19, 2^63-1 are refused
#   stop      every say/speak a stop drops gets its utterance_ended (interrupted), in order; stopped
#             carries the stop's id
#   record    capped (--record-max), and holding what was parsed, not the junk members
#   http      431 for an oversized header, 413 for a body, query strings on routes
#   first say a say sent as the session opens keeps all its sound
#   drain     SIGTERM with a client that never answers the close frame: stopped within a second
set -euo pipefail
TH=$1 CLIENT=$2
PY=/usr/bin/python3
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
command -v curl >/dev/null || { echo "skipped: curl is not installed"; exit 77; }
T=$(mktemp -d)
servers=()
cleanup() { exec 2>/dev/null; for s in "${servers[@]}"; do kill -9 "$s" || true; done; rm -rf "$T"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }
start() {
	local name=$1; shift
	"$TH" serve --listen 127.0.0.1:0 --size 160x90 --max-load 0 "$@" >"$T/$name.out" 2>"$T/$name.err" &
	pid=$!
	servers+=("$pid")
	for _ in $(seq 100); do grep -q serving "$T/$name.out" 2>/dev/null && break; sleep 0.1; done
	port=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/$name.out")
	[ -n "$port" ] || { cat "$T/$name.out" "$T/$name.err"; fail "serve $name did not start"; }
}

# Lockout. The test and the server hold ~700 descriptors between them.
ulimit -n 4096 2>/dev/null || ulimit -n "$(ulimit -Hn)" 2>/dev/null || true
if [ "$(ulimit -n)" != unlimited ] && [ "$(ulimit -n)" -lt 1400 ]; then
	echo "lockout: skipped (ulimit -n is $(ulimit -n))"
else
	token=th-test-$($PY -c 'import secrets; print(secrets.token_hex(16))')
	printf '%s\n' "$token" >"$T/token"
	start lock --token-file "$T/token"
	$PY "$HERE/lockout.py" "$port" "$token" 600 | tee "$T/lockout.txt" || fail "token holders were kept out: $(cat "$T/lockout.txt")"
	lines=$(grep -c 'not yet authenticated' "$T/lock.err" || true)
	test "$lines" -ge 1 -a "$lines" -le 14 || fail "$lines log lines about unauthenticated connections in ~12 s"
	metrics=$(curl -sf -H "Authorization: Bearer $token" "http://127.0.0.1:$port/metrics")
	grep -q '^talkhead_sessions_refused_total{reason="unauthenticated"} [1-9]' <<<"$metrics" || fail "/metrics has no unauthenticated refusal"
	grep -q '^talkhead_unauthenticated_connections 0$' <<<"$metrics" || fail "unauthenticated connections left: $(grep unauthenticated_conn <<<"$metrics")"
	echo "lockout: ok ($lines log lines)"
fi

start main --record "$T" --record-max 1
# Ids and stop: the says are queued behind a long one, so the stop drops them before they are prepared.
"$CLIENT" "$port" "$T/ids" 3 \
	'100:{"type":"emotion","id":1.5,"emotion":"happy"}' '100:{"type":"emotion","id":1e19,"emotion":"happy"}' \
	'100:{"type":"emotion","id":9223372036854775807,"emotion":"happy"}' '100:{"type":"emotion","id":{"a":1},"emotion":"happy"}' \
	'200:{"type":"say","id":"long","text":"This first sentence is long enough to be still under way when the stop comes in."}' \
	'200:{"type":"say","id":2,"text":"One."}' '200:{"type":"say","id":"2","text":"Two."}' '200:{"type":"say","id":-7,"text":"Three."}' \
	'200:{"type":"emotion","id":"e","emotion":"happy"}' '200:{"type":"say","text":"No id."}' \
	'900:{"type":"stop","id":"s1"}' '1500:{"type":"say","id":9007199254740991,"text":"After."}'
$PY - "$T/ids.events" <<'PY'
import json, sys
ev = [json.loads(l.split('\t', 1)[1]) for l in open(sys.argv[1]) if '\t>' not in l and not l.startswith('close')]
errors = [e for e in ev if e['type'] == 'error']
assert len(errors) == 4 and all("'id' must be a string" in e['message'] and 'id' not in e for e in errors), errors
ended = [e for e in ev if e['type'] == 'utterance_ended']
ids = [e.get('id') for e in ended]
# "long" is cut, the four queued ones end without starting, in the order they came; "After." is spoken.
assert ids[:5] == ['long', 2, '2', -7, None], ids
assert all(e['interrupted'] for e in ended[:5]), ended
started = [e.get('id') for e in ev if e['type'] == 'utterance_started']
assert started == ['long', 9007199254740991], started
stopped = [e for e in ev if e['type'] == 'stopped']
assert len(stopped) == 1 and stopped[0]['id'] == 's1', stopped
assert all(e['frame'] == stopped[0]['frame'] for e in ended[:5]), (ended, stopped)
print(f"ids and stop: ok ({len(ended[:5])} utterance_ended at the stop's frame {stopped[0]['frame']}, ids {ids[:5]})")
PY

# Record: the junk members are not recorded; past --record-max (1 MiB) the record ends, the session goes on.
$PY - "$T" <<'PY'
import base64, io, json, math, sys, wave
t = sys.argv[1]
for i in range(3):
    json.dump({'type': 'say', 'id': f'r{i}', 'text': 'Short.', 'junk': 'x' * 3_000_000}, open(f'{t}/junk{i}.json', 'w'))
for i in (1, 2):  # 3 s of 48 kHz stereo: 770 kB of base64 each, two over the cap
    b = io.BytesIO()
    with wave.open(b, 'wb') as w:
        w.setnchannels(2); w.setsampwidth(2); w.setframerate(48000)
        w.writeframes(b''.join(int(3000 * math.sin(k * 0.05)).to_bytes(2, 'little', signed=True) * 2 for k in range(3 * 48000)))
    json.dump({'type': 'speak', 'id': f's{i}', 'audio': base64.b64encode(b.getvalue()).decode(), 'visemes': [{'id': 0, 'offset_ms': 0}, {'id': 2, 'offset_ms': 300}]},
              open(f'{t}/speak{i}.json', 'w'))
PY
"$CLIENT" "$port" "$T/rec" 5 "100:@$T/junk0.json" "300:@$T/junk1.json" "500:@$T/speak1.json" "600:@$T/speak2.json" "2500:@$T/junk2.json"
grep -q '"type": "utterance_started".*"id": "s2"' "$T/rec.events" || fail "the session did not go on: $(cut -c1-200 "$T/rec.events" | grep -v viseme | tail -3)"
rec=$(grep -l '"r0"' "$T"/session-*.jsonl)
size=$(stat -c %s "$rec")
test "$size" -le $((1 << 20)) || fail "the record is $size bytes, over --record-max 1 MiB"
! grep -q junk "$rec" || fail "junk members were recorded"
grep -q '"r1"' "$rec" || fail "a request before the cap is missing from the record"
grep -q '"s1"' "$rec" || fail "the first speak is missing from the record"
! grep -q '"r2"\|"s2"' "$rec" || fail "a request after the cap was recorded"
grep -q '{"type": "end", "frame": [0-9]*, "truncated": true}' "$rec" || fail "no truncated end: $(tail -c 200 "$rec")"
grep -q 'record reached 1 MiB (--record-max)' "$T/main.err" || fail "the cap was not logged"
"$TH" live "$rec" -o "$T/replay.mp4" -q --size 160x90 || fail "the capped record does not replay"
echo "record: ok ($size bytes, truncated, replays)"

# HTTP: 431, 413, queries.
big=$(head -c 20000 /dev/zero | tr '\0' a)
test "$(curl -s -o /dev/null -w '%{http_code}' -H "X-Big: $big" "http://127.0.0.1:$port/health")" = 431 || fail "no 431 for a 20 kB header"
test "$(curl -s -o /dev/null -w '%{http_code}' --data-binary "@$T/junk0.json" "http://127.0.0.1:$port/health")" = 413 || fail "no 413 for a 3 MB body"
test "$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/health?probe=1")" = 200 || fail "/health?probe=1 is not /health"
test "$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/nothing?x=1")" = 404
echo "http: ok"

# The first say, sent as the session opens: no sound lost (the server says when it drops any).
for i in 1 2 3; do "$CLIENT" "$port" "$T/first$i" 1.5 '0:{"type":"say","id":"first","text":"Hi."}'; done
grep -q '"type": "utterance_started".*"id": "first"' "$T/first1.events" || fail "the first say did not start"
! grep -q 'late for the sound' "$T/main.err" || fail "$(grep 'late for the sound' "$T/main.err" | head -1)"
echo "first say: ok"

# Admission (item 3): a burst counts each admitted session at a speaking session's measured cost before its
# own load is known (it counted as 0: a burst was all admitted), and the admitted ones start paced.
start burst --max-load "$($PY -c "import os; print(0.4 / os.cpu_count())")" --max-sessions 64 --size 320x180  # 0.4 cores
cost=$(sed -nE 's/.*takes ([0-9.]+) cores \(measured at start-up\).*/\1/p' "$T/burst.err")
[ -n "$cost" ] || fail "no start-up measurement: $(cat "$T/burst.err")"
bs=()
for i in $(seq 8); do "$CLIENT" "$port" "$T/b$i" 2 '300:{"type":"say","text":"Hello there."}' >/dev/null 2>&1 & bs+=($!); done
wait "${bs[@]}" || true
admitted=$(grep -l '"type": "hello"' "$T"/b?.events | wc -l)
refused=$(grep -l 'at capacity' "$T"/b?.events | wc -l)
test "$admitted" -ge 1 -a "$admitted" -lt 8 -a $((admitted + refused)) = 8 || fail "burst of 8 within 0.4 cores (a session $cost cores): $admitted admitted, $refused refused"
echo "admission: ok (a session $cost cores; a burst of 8 within 0.4 cores: $admitted admitted, $refused refused)"

# Drain: a client that never answers the close frame does not hold the server for drain + 2 s.
start drain --drain 5
$PY - "$port" >"$T/raw.out" <<'PY' &
import base64, os, socket, sys, time
port = int(sys.argv[1])
s = socket.create_connection(('127.0.0.1', port))
s.sendall((f'GET /live HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n'
           f'Sec-WebSocket-Key: {base64.b64encode(os.urandom(16)).decode()}\r\nSec-WebSocket-Version: 13\r\n\r\n').encode())
s.settimeout(0.2)
t0 = time.time()
while time.time() - t0 < 12:  # reads, never answers
    try:
        if not s.recv(65536): break
    except socket.timeout:
        pass
PY
raw=$!
sleep 1
"$CLIENT" "$port" "$T/polite" 0.5 >/dev/null
t0=$(date +%s%N)
kill -TERM "$pid"
wait "$pid" || fail "serve exited $? on SIGTERM"
t1=$(date +%s%N)
kill "$raw" 2>/dev/null || true
ms=$(( (t1 - t0) / 1000000 ))
test "$ms" -lt 1500 || fail "SIGTERM took $ms ms with every session idle (a client that does not answer the close frame)"
echo "drain: ok (stopped $ms ms after the signal)"
echo "serve round 2: ok"
