#!/usr/bin/env bash
# Issue 45 (1): a decompression bomb in `speak`. A 20 kB FLAC holding 2 hours of silence used to raise the
# server's peak memory by 1.23 GiB for 9 s before "longer than the 600 s allowed"; the length is now
# refused from the FLAC header before a sample is decoded (and counted as samples come where a file
# declares none: tests/media/audio_test.cpp). The server's peak memory (VmHWM) may grow by at most 32 MiB
# over the bomb, the refusal comes as an error event with the request's id within a second, and the
# session goes on speaking. The command line refuses a 5-hour FLAC (over its 4-hour limit) the same way.
set -euo pipefail
TH=$1 CLIENT=$2
PY=/usr/bin/python3
command -v ffmpeg >/dev/null || { echo "skipped: ffmpeg is not installed"; exit 77; }
T=$(mktemp -d)
server=
cleanup() { [ -n "$server" ] && kill -9 "$server" 2>/dev/null; rm -rf "$T"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }

ffmpeg -nostdin -v error -f lavfi -i anullsrc=r=8000:cl=mono -t 7200 -c:a flac -frame_size 65535 -compression_level 12 "$T/bomb.flac"
# The same written to a pipe: its header declares no length (counted, not read from the header).
ffmpeg -nostdin -v error -f lavfi -i anullsrc=r=8000:cl=mono -t 7200 -c:a flac -frame_size 65535 -compression_level 12 -f flac pipe:1 >"$T/quiet.flac"
echo "bomb: $(stat -c %s "$T/bomb.flac") bytes of FLAC, 7200 s; $(stat -c %s "$T/quiet.flac") bytes without a length in its header"
"$TH" say "Boa noite." -q --size 160x90 --no-audio -o "$T/x.mp4" --save-transcript "$T/a.TextGrid"
$PY - "$T" <<'PY'
import base64, json, sys
t = sys.argv[1]
for name in ('bomb', 'quiet'):
    json.dump({'type': 'speak', 'id': name, 'lang': 'pt-BR', 'audio': base64.b64encode(open(f'{t}/{name}.flac', 'rb').read()).decode(),
               'transcript': open(f'{t}/a.TextGrid').read()}, open(f'{t}/{name}.json', 'w'))
PY

"$TH" serve --listen 127.0.0.1:0 --size 160x90 --max-load 0 -q >"$T/serve.out" 2>"$T/serve.err" &
server=$!
for _ in $(seq 100); do grep -q serving "$T/serve.out" 2>/dev/null && break; sleep 0.1; done
port=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/serve.out")
[ -n "$port" ] || { cat "$T/serve.out" "$T/serve.err"; fail "serve did not start"; }
# The peak before: a session that speaks once (the model loaded, the encoder and espeak-ng warm).
"$CLIENT" "$port" "$T/warm" 3 '100:{"type":"say","id":"warm","text":"Bom dia."}'
grep -q '"type": "utterance_started".*"id": "warm"' "$T/warm.events" || fail "the warm-up was not spoken: $(cut -c1-200 "$T/warm.events")"
before=$(awk '/VmHWM/ {print $2}' /proc/$server/status)
# The bomb, then an ordinary say in the same session.
"$CLIENT" "$port" "$T/b" 4 "100:@$T/bomb.json" '1100:{"type":"say","id":"after","text":"Ainda aqui."}'
after=$(awk '/VmHWM/ {print $2}' /proc/$server/status)
grep -q '"type": "error".*longer than the 600 s allowed.*"id": "bomb"' "$T/b.events" || fail "the bomb was not refused: $(cut -c1-300 "$T/b.events")"
grep -q '"type": "error".*7200.0 s (as its header says)' "$T/b.events" || fail "not refused from the header: $(grep bomb "$T/b.events" | cut -c1-300)"
grep -q '"type": "utterance_started".*"id": "after"' "$T/b.events" || fail "the session did not go on"
grow=$(( (after - before) / 1024 ))
echo "server peak memory: $((before / 1024)) MiB before the bomb, $((after / 1024)) MiB after (+$grow MiB)"
# Under AddressSanitizer freed memory waits in its quarantine, so the bound there is looser (the old
# server took 1244 MiB either way). ldd's output is read whole before grep (pipefail, see cli.real_inputs).
libs=$(ldd "$TH" 2>/dev/null || true)
bound=32; if grep -q libasan <<<"$libs"; then bound=128; fi
test "$grow" -le "$bound" || fail "the bomb raised the server's peak memory by $grow MiB (at most $bound)"
# One that declares nothing is counted before its samples are kept: refused for as little (it took the
# limit's worth, 600 s at 22 050 Hz: +100 MiB, before).
t0=$(date +%s%N)
"$CLIENT" "$port" "$T/q" 3 "100:@$T/quiet.json" '2000:{"type":"say","id":"after","text":"Ainda aqui."}'
quiet=$(awk '/VmHWM/ {print $2}' /proc/$server/status)
grep -q '"type": "error".*lasts longer than the 600 s allowed.*"id": "quiet"' "$T/q.events" || fail "the headerless bomb was not refused: $(grep quiet "$T/q.events" | cut -c1-300)"
grep -q '"type": "utterance_started".*"id": "after"' "$T/q.events" || fail "the session did not go on after the headerless bomb"
qgrow=$(( (quiet - after) / 1024 ))  # over the peak the first bomb left (which a busy machine raises)
echo "headerless bomb: server peak +$qgrow MiB over that"
test "$qgrow" -le "$bound" || fail "the headerless bomb raised the server's peak memory by $qgrow MiB (at most $bound)"

# The command line: a 5-hour FLAC is over its 4-hour limit, refused before decoding (one line, exit 1,
# no output, little memory and time).
timeout 60 ffmpeg -nostdin -v error -f lavfi -i anullsrc=r=8000:cl=mono -t 18000 -c:a flac -frame_size 65535 -compression_level 12 "$T/five.flac" || fail "ffmpeg could not write the 5-hour FLAC within 60 s"
rc=0
# (Bounded: twice in full -j2 runs this test hung somewhere after the server's part, and ctest's timeout
# said nothing of where; a step that hangs now fails naming itself.)
timeout 60 /usr/bin/time -f "%e %M" -o "$T/time" "$TH" render --transcript "$T/a.TextGrid" --audio "$T/five.flac" -o "$T/five.mp4" 2>"$T/five.err" </dev/null || rc=$?
test "$rc" != 124 || fail "render of a 5-hour FLAC did not end within 60 s: $(cat "$T/five.err")"
test "$rc" = 1 || fail "render of a 5-hour FLAC exited $rc"
grep -v '^ *Command exited' "$T/five.err" >"$T/five.err1" || true
test "$(wc -l <"$T/five.err1")" = 1 || { cat "$T/five.err"; fail "not one error line"; }
grep -q "five.flac: lasts 18000.0 s (as its header says), longer than the 14400 s allowed" "$T/five.err1" || fail "$(cat "$T/five.err1")"
test ! -e "$T/five.mp4"
read -r secs kib < <(tail -1 "$T/time")
echo "render --audio of 5 hours: refused in $secs s, peak $((kib / 1024)) MiB"
awk -v k="$kib" 'BEGIN { exit !(k < 400 * 1024) }' || fail "peak memory $((kib / 1024)) MiB"
echo "audio bomb tests passed"
