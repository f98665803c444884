#!/usr/bin/env bash
# talkhead serve (issue 16) with a scripted WebSocket client: two sessions at once give, frame for frame,
# what 'talkhead live' renders offline from their records (lossless H.264: the decoded stream is the drawn
# frames); utterances back to back, a barge-in, bad requests (malformed JSON, an unknown emotion, audio in
# no known format, a 100 MB message) each answered with an error while the session and the server go on;
# a session over --max-sessions is refused.
set -euo pipefail
TH=$1 CLIENT=$2
PY=/usr/bin/python3
command -v ffmpeg >/dev/null || { echo "skipped: ffmpeg (the test's decoder) is not installed"; exit 77; }
T=$(mktemp -d)
server=0
cleanup() { [ "$server" = 0 ] || kill "$server" 2>/dev/null || true; rm -rf "$T"; }
[ -n "${KEEP:-}" ] && cleanup() { echo kept $T; }
trap cleanup EXIT

# Bad options are one error line before anything listens.
for bad in "--emotion grumpy" "--sample-rate 12345" "--listen nowhere:1" "--listen 127.0.0.1:99999" "--model $T/none.thm"; do
	if timeout 20 "$TH" serve $bad >"$T/bad.out" 2>"$T/bad.err"; then echo "serve $bad: exit 0"; exit 1; fi
	test "$(wc -l <"$T/bad.err")" = 1 || { echo "serve $bad:"; cat "$T/bad.err"; exit 1; }
	grep -q '^talkhead: ' "$T/bad.err"
done

# Speech with its timing, for speak requests (the sound and the phones as say made them).
"$TH" say "Bom dia, tudo bem?" -q --size 160x90 --no-audio -o "$T/x.mp4" --save-audio "$T/a.wav" --save-transcript "$T/a.TextGrid"
"$TH" say "Good morning, how can I help you today?" --lang en-US -q --size 160x90 --no-audio -o "$T/z.mp4" --save-audio "$T/c.wav"
"$TH" say "Boa noite." -q --size 160x90 --no-audio -o "$T/y.mp4" --save-audio "$T/b.wav" --save-transcript "$T/b.TextGrid"
$PY - "$T" <<'EOF'
import base64, json, sys
t = sys.argv[1]
for n in 'ab':
    req = {'type': 'speak', 'id': 'speak-' + n, 'lang': 'pt-BR', 'audio': base64.b64encode(open(f'{t}/{n}.wav', 'rb').read()).decode(),
           'transcript': open(f'{t}/{n}.TextGrid').read()}
    open(f'{t}/speak-{n}.json', 'w').write(json.dumps(req))
# Raw 16-bit PCM as TTS services stream it: a's samples without the WAV header.
w = open(f'{t}/a.wav', 'rb').read()
pcm = w[w.index(b'data') + 8:]
json.dump({'type': 'speak', 'id': 'pcm', 'lang': 'pt-BR', 'encoding': 'pcm_s16le', 'sample_rate': 22050, 'audio': base64.b64encode(pcm).decode(),
           'transcript': open(f'{t}/a.TextGrid').read()}, open(f'{t}/speak-pcm.json', 'w'))
# Issue 49: the same sound with only its text (aligned by the server), and with no timing at all (recognised).
a = base64.b64encode(open(f'{t}/a.wav', 'rb').read()).decode()
json.dump({'type': 'speak', 'id': 'text', 'lang': 'pt-BR', 'audio': a, 'text': 'Bom dia, tudo bem?'}, open(f'{t}/speak-text.json', 'w'))
json.dump({'type': 'speak', 'id': 'heard', 'lang': 'pt-BR', 'audio': a}, open(f'{t}/speak-heard.json', 'w'))
# Issue 49 part 2: the same sound streamed as a TTS streams it, raw PCM in 0.3-s pieces, its text with the first.
step = 22050 * 2 * 3 // 10
pieces = [pcm[k:k + step] for k in range(0, len(pcm), step)]
for k, p in enumerate(pieces):
    req = {'type': 'speak', 'audio': base64.b64encode(p).decode()}
    if k == 0:
        req.update({'id': 'stream', 'lang': 'pt-BR', 'encoding': 'pcm_s16le', 'sample_rate': 22050, 'text': 'Bom dia, tudo bem?'})
    else:
        req['continue'] = 'stream'
    if k + 1 < len(pieces):
        req['more'] = True
    json.dump(req, open(f'{t}/stream-{k}.json', 'w'))
open(f'{t}/stream-count', 'w').write(str(len(pieces)))
# …and an English sentence in 0.2-s pieces sent at real time (the case that ran dry before D97's lead).
w = open(f'{t}/c.wav', 'rb').read()
pcm = w[w.index(b'data') + 8:]
step = 22050 * 2 // 5
pieces = [pcm[k:k + step] for k in range(0, len(pcm), step)]
for k, p in enumerate(pieces):
    req = {'type': 'speak', 'audio': base64.b64encode(p).decode()}
    if k == 0:
        req.update({'id': 'rt', 'lang': 'en-US', 'encoding': 'pcm_s16le', 'sample_rate': 22050, 'text': 'Good morning, how can I help you today?'})
    else:
        req['continue'] = 'rt'
    if k + 1 < len(pieces):
        req['more'] = True
    json.dump(req, open(f'{t}/rt-{k}.json', 'w'))
    req.pop('text', None)  # …and the same with no text: its phones recognised as it comes
    if k == 0: req['id'] = 'heard-stream'
    else: req['continue'] = 'heard-stream'
    json.dump(req, open(f'{t}/hs-{k}.json', 'w'))
open(f'{t}/rt-count', 'w').write(str(len(pieces)))
bad = {'type': 'speak', 'id': 'noise', 'audio': base64.b64encode(b'\x13\x37' * 3000).decode(), 'transcript': open(f'{t}/a.TextGrid').read()}
open(f'{t}/bad-audio.json', 'w').write(json.dumps(bad))
with open(f'{t}/huge.json', 'w') as f:  # 100 MB
    f.write('{"type": "say", "text": "' + 'a' * (100 << 20) + '"}')
EOF

mkdir -p "$T/rec"
"$TH" serve --listen 127.0.0.1:0 --size 320x180 --crf 0 --seed 5 --max-sessions 3 --max-load 0 --record "$T/rec" -q >"$T/serve.out" 2>"$T/serve.err" &
server=$!
for _ in $(seq 50); do grep -q serving "$T/serve.out" 2>/dev/null && break; sleep 0.1; done
port=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/serve.out")
[ -n "$port" ] || { cat "$T/serve.out" "$T/serve.err"; echo "serve did not start"; exit 1; }

# Two sessions at once, different emotions, each speaking.
"$CLIENT" "$port" "$T/s1" 3.5 '100:{"type":"emotion","emotion":"joy"}' "400:@$T/speak-a.json" &
c1=$!
"$CLIENT" "$port" "$T/s2" 3.5 '100:{"type":"emotion","emotion":"anger","ramp":0.2}' "600:@$T/speak-b.json" &
c2=$!
wait $c1 $c2
for s in s1 s2; do
	grep -q '"type": "hello"' "$T/$s.events"
	grep -q '"type": "utterance_started", "frame": [0-9]*, "time": [0-9.]*, "id": "speak-' "$T/$s.events"
	grep -q '"type": "utterance_ended"' "$T/$s.events"
	! grep -q '"type": "error"' "$T/$s.events"
done
# A speak with its text, then one with its audio alone: each starts and ends, no error; the recognised one
# says its phones are en-US's in a pt-BR session only through its mouth (no error, no warning needed).
"$CLIENT" "$port" "$T/s3" 5 "100:@$T/speak-text.json" "200:@$T/speak-heard.json"
grep -q '"type": "utterance_started", "frame": [0-9]*, "time": [0-9.]*, "id": "text"' "$T/s3.events"
grep -q '"type": "utterance_started", "frame": [0-9]*, "time": [0-9.]*, "id": "heard"' "$T/s3.events"
test "$(grep -c '"type": "utterance_ended"' "$T/s3.events")" = 2
! grep -q '"type": "error"' "$T/s3.events"
# A streamed speak: one start, one end, no error; its pieces a stop overtook are dropped without an error,
# and the stream ends once, interrupted.
args=()
for k in $(seq 0 $(( $(cat "$T/stream-count") - 1 ))); do args+=("$(( 100 + 300 * k )):@$T/stream-$k.json"); done
"$CLIENT" "$port" "$T/s4" 4 "${args[@]}"
test "$(grep -c '"type": "utterance_started".*"id": "stream"' "$T/s4.events")" = 1
test "$(grep -c '"type": "utterance_ended".*"id": "stream"' "$T/s4.events")" = 1
! grep -q '"type": "error"' "$T/s4.events"
# Sent at real time, a stream plays without a hole: the utterance lasts as long as its sound, within a frame
# (D97's lead).
args=()
for k in $(seq 0 $(( $(cat "$T/rt-count") - 1 ))); do args+=("$(( 300 + 200 * k )):@$T/rt-$k.json"); done
"$CLIENT" "$port" "$T/s7" 7 "${args[@]}"
! grep -q '"type": "error"' "$T/s7.events"
if [ -n "${TALKHEAD_SANITIZED:-}" ]; then
	echo "note: the real-time gap check is skipped on a sanitized build (its alignment runs 2-3x slower than a release build's)"
else $PY - "$T/s7.events" "$T/c.wav" <<'EOF'
import json, sys, wave
ev = [json.loads(l.split('\t', 1)[1]) for l in open(sys.argv[1]) if '\t>' not in l and l.split('\t', 1)[1].startswith('{')]
start = [e for e in ev if e['type'] == 'utterance_started'][0]['time']
end = [e for e in ev if e['type'] == 'utterance_ended'][0]['time']
w = wave.open(sys.argv[2])
sound = w.getnframes() / w.getframerate()
assert abs((end - start) - sound) <= 1 / 30 + 1e-3, f'the streamed utterance lasts {end - start:.3f} s, its sound {sound:.3f} s'
EOF
fi
"$CLIENT" "$port" "$T/s5" 3 "100:@$T/stream-0.json" "400:@$T/stream-1.json" "700:@$T/stream-2.json" '800:{"type":"stop","id":"halt"}' "850:@$T/stream-3.json" "900:@$T/stream-4.json"
test "$(grep -c '"type": "utterance_ended".*"id": "stream"' "$T/s5.events")" = 1
grep -q '"type": "stopped"' "$T/s5.events"
! grep -q '"type": "error"' "$T/s5.events"
# A piece of no open stream is refused, naming it.
"$CLIENT" "$port" "$T/s6" 1 '100:{"type":"speak","continue":"nope","audio":"AAAAAA=="}' '200:{"type":"speak","continue":"nope","audio":"AAAA"}'
grep -q '"type": "error".*no streamed speak.*"id": "nope"' "$T/s6.events"
grep -q '"type": "error".*16-bit sample frames.*"id": "nope"' "$T/s6.events"
# A streamed speak with no text, recorded: `talkhead live` replays it frame for frame.
args=()
for k in $(seq 0 $(( $(cat "$T/rt-count") - 1 ))); do args+=("$(( 300 + 200 * k )):@$T/hs-$k.json"); done
"$CLIENT" "$port" "$T/s8" 8 "${args[@]}"
! grep -q '"type": "error"' "$T/s8.events"
test "$(grep -c '"type": "utterance_ended".*"id": "heard-stream"' "$T/s8.events")" = 1
sleep 0.3
rec=$(grep -l 'heard-stream' "$T"/rec/session-*.jsonl)
"$TH" live "$rec" --size 320x180 --seed 5 --format y4m -o "$T/live8.y4m" -q
ffmpeg -v error -i "$T/s8.mp4" -vsync passthrough -f rawvideo -pix_fmt yuv420p "$T/stream8.yuv"
ffmpeg -v error -i "$T/live8.y4m" -f rawvideo -pix_fmt yuv420p "$T/live8.yuv"
$PY - "$T/stream8.yuv" "$T/live8.yuv" "$T/s8.events" <<'EOF'
import json, sys
frame = 320 * 180 * 3 // 2
a, b = open(sys.argv[1], 'rb').read(), open(sys.argv[2], 'rb').read()
n = min(len(a), len(b)) // frame
end = [json.loads(l.split('\t', 1)[1]) for l in open(sys.argv[3]) if '"utterance_ended"' in l and '\t>' not in l][0]['frame']
assert n > end, f'{n} frames to compare, the utterance ends at {end}'
bad = [i for i in range(n) if a[i * frame:(i + 1) * frame] != b[i * frame:(i + 1) * frame]]
assert not bad, f'{len(bad)} of {n} frames differ, the first {bad[0]}'
EOF
# Its parts took effect at frames of their own (recognised while later pieces came): the record says where,
# and a part step with no speech before it is one error line naming the script's line.
grep -q '"type": "part", "id": "heard-stream"' "$rec"
printf '{"frame": 3, "type": "part", "id": "x"}\n{"type": "end", "frame": 10}\n' >"$T/orphan.jsonl"
if "$TH" live "$T/orphan.jsonl" --size 320x180 --format y4m -o "$T/orphan.y4m" -q 2>"$T/orphan.err"; then echo "a part with no speech replayed"; exit 1; fi
grep -q "orphan.jsonl:1: .*'part' step with no speech part made before it" "$T/orphan.err"
test ! -e "$T/orphan.y4m"
# Offline: the records replayed give the frames each stream had, bit for bit.
sleep 0.3  # the sessions write their end lines as they close
for n in 1 2; do
	rec=$(grep -l "speak-$( [ $n = 1 ] && echo a || echo b)" "$T"/rec/session-*.jsonl)
	grep -q '"type": "end"' "$rec"
	"$TH" live "$rec" --size 320x180 --seed 5 --format y4m -o "$T/live$n.y4m" -q
	ffmpeg -v error -i "$T/s$n.mp4" -vsync passthrough -f rawvideo -pix_fmt yuv420p "$T/stream$n.yuv"
	ffmpeg -v error -i "$T/live$n.y4m" -f rawvideo -pix_fmt yuv420p "$T/live$n.yuv"
	$PY - "$T/stream$n.yuv" "$T/live$n.yuv" <<'EOF'
import sys
frame = 320 * 180 * 3 // 2
a, b = open(sys.argv[1], 'rb').read(), open(sys.argv[2], 'rb').read()
n = min(len(a), len(b)) // frame
assert n >= 60, f'only {n} frames to compare'
bad = [i for i in range(n) if a[i * frame:(i + 1) * frame] != b[i * frame:(i + 1) * frame]]
assert not bad, f'{len(bad)} of {n} frames differ, the first {bad[0]}'
print(f'{sys.argv[1]}: {n} frames identical to the offline render')
EOF
done
# The two sessions are different streams (their own emotions).
! cmp -s "$T/stream1.yuv" "$T/stream2.yuv"

# Back to back, then a barge-in.
"$CLIENT" "$port" "$T/s3" 3.5 '200:{"type":"say","id":"one","text":"Hello there.","lang":"en-US"}' \
	'200:{"type":"say","id":"two","text":"How are you?"}' \
	'200:{"type":"say","id":"three","text":"I am going to talk for a long long time now, about many things."}' \
	'2400:{"type":"stop"}'
$PY - "$T/s3.events" <<'EOF'
import json, sys
ev = [json.loads(l.split('\t', 1)[1]) for l in open(sys.argv[1]) if '\t>' not in l]
def one(t, i):
    m = [e for e in ev if e['type'] == t and e.get('id') == i]
    assert len(m) == 1, f'{t} {i}: {m}'
    return m[0]
assert one('utterance_ended', 'one')['frame'] == one('utterance_started', 'two')['frame'], 'a gap between one and two'
assert one('utterance_ended', 'two')['frame'] == one('utterance_started', 'three')['frame'], 'a gap between two and three'
three = one('utterance_ended', 'three')
stop = [e for e in ev if e['type'] == 'stopped']
assert stop and three['interrupted'] and three['frame'] == stop[0]['frame'], (three, stop)
assert 'latency_ms' in one('utterance_started', 'one')
print('back to back and barge-in: ok')
EOF

# Bad requests: an error each, and the session goes on (the say after them is spoken). 10 s: under the
# sanitizers, with other tests beside it, the 32-MiB message alone takes seconds.
"$CLIENT" "$port" "$T/s4" 10 '100:{"type": "say", "text": ' '200:{"type":"emotion","emotion":"grumpy"}' "300:@$T/bad-audio.json" \
	"400:@$T/huge.json" '500:{"type":"dance"}' '700:{"type":"say","id":"after","text":"Still here."}' "800:@$T/speak-pcm.json"
test "$(grep -c '"type": "error"' "$T/s4.events")" = 5 || { cat "$T/s4.events" | cut -c1-200; exit 1; }
grep -q 'malformed JSON' "$T/s4.events" || { echo "s4: no malformed JSON"; cut -c1-200 "$T/s4.events"; exit 1; }
grep -q "unknown emotion 'grumpy'" "$T/s4.events" || { echo "s4: no unknown emotion grumpy"; cut -c1-200 "$T/s4.events"; exit 1; }
grep -q '"id": "noise"' "$T/s4.events" || { echo "s4: no id: noise"; cut -c1-200 "$T/s4.events"; exit 1; }
grep -q 'larger than 32 MiB' "$T/s4.events" || { echo "s4: no larger than 32 MiB"; cut -c1-200 "$T/s4.events"; exit 1; }
grep -q "unknown request type 'dance'" "$T/s4.events" || { echo "s4: no unknown request type dance"; cut -c1-200 "$T/s4.events"; exit 1; }
grep -q '"type": "utterance_started".*"id": "after"' "$T/s4.events" || { echo "s4: no type: utterance_started.*id: after"; cut -c1-200 "$T/s4.events"; exit 1; }
grep -q '"type": "utterance_started".*"id": "pcm"' "$T/s4.events" || { echo "s4: no type: utterance_started.*id: pcm"; cut -c1-200 "$T/s4.events"; exit 1; }

# The port in use: an error naming it.
if timeout 20 "$TH" serve --listen "127.0.0.1:$port" 2>"$T/busy.err"; then echo "a second server on the same port"; exit 1; fi
grep -q "cannot listen on 127.0.0.1:$port: Address already in use" "$T/busy.err"

# At most --max-sessions; a closed session frees its place; the server is still up.
pids=()
for m in 1 2 3; do "$CLIENT" "$port" "$T/m$m" 2 & pids+=($!); done
sleep 0.8
"$CLIENT" "$port" "$T/m4" 1 || true
wait "${pids[@]}"
grep -q 'sessions already' "$T/m4.events" || { echo "m4 was not refused:"; cut -c1-200 "$T/m4.events"; exit 1; }
health=$(curl -sf "http://127.0.0.1:$port/health") && grep -q '"sessions": 0' <<<"$health" || { echo "sessions left: $(curl -s "http://127.0.0.1:$port/health")"; exit 1; }
"$CLIENT" "$port" "$T/m5" 0.5
grep -q '"type": "hello"' "$T/m5.events"
kill -0 "$server"
echo "serve: ok"
