#!/usr/bin/env bash
# talkhead serve --demo (issue 16): the browser demo in real headless Chromium (Debian chromium, driven by
# playwright-core from npm, installed once into ~/.cache/talkhead-tests): it connects, a sentence is sent,
# the video plays and its time advances, the events arrive.
set -euo pipefail
TH=$1; HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
. "$HERE/../support/playwright.sh"
T=$(mktemp -d)
server=0 web=0 server2=0
trap '[ "$server" = 0 ] || kill "$server" 2>/dev/null; [ "$server2" = 0 ] || kill "$server2" 2>/dev/null; [ "$web" = 0 ] || kill "$web" 2>/dev/null; rm -rf "$T"' EXIT
"$TH" serve --listen 127.0.0.1:0 --size 640x360 --max-load 0 --demo >"$T/out" 2>"$T/err" &
server=$!
for _ in $(seq 50); do grep -q serving "$T/out" 2>/dev/null && break; sleep 0.1; done
port=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/out")
[ -n "$port" ] || { cat "$T/out" "$T/err"; exit 1; }
# Self-contained: no external script, stylesheet or font.
curl -sf "http://127.0.0.1:$port/" >"$T/index.html"
! grep -Eq 'https?://|<script src|<link ' "$T/index.html"
# A WAV for the page's "speak a WAV" (issue 49): espeak-ng's sound, spoken back alone and with its text.
"$TH" say "Good morning, how can I help you today?" --lang en-US -q --size 160x90 --no-audio -o "$T/x.mp4" --save-audio "$T/speech.wav"
NODE_PATH="$PLAYWRIGHT_MODULES" timeout 180 node "$HERE/demo_test.js" "http://127.0.0.1:$port/" "" "$T/speech.wav"

# Cross-site control (issue 28): a page of another site cannot open a session; a loopback page can.
pageport=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
(cd "$HERE" && exec /usr/bin/python3 -m http.server "$pageport" --bind 127.0.0.1 >/dev/null 2>&1) &
web=$!
for _ in $(seq 50); do curl -sf "http://127.0.0.1:$pageport/attack.html" >/dev/null && break; sleep 0.1; done
NODE_PATH="$PLAYWRIGHT_MODULES" timeout 120 node "$HERE/origin_test.js" "$port" "$pageport"
grep -q "upgrade refused: origin 'http://evil.example:$pageport' is not allowed" "$T/err"

# With a token (issue 28): the demo page sends it from its address's fragment as the first message.
token=demo-token-$(/usr/bin/python3 -c 'import secrets; print(secrets.token_hex(12))')
echo "$token" >"$T/token"
"$TH" serve --listen 127.0.0.1:0 --size 320x180 --max-load 0 --demo --token-file "$T/token" >"$T/out2" 2>"$T/err2" &
server2=$!
for _ in $(seq 50); do grep -q serving "$T/out2" 2>/dev/null && break; sleep 0.1; done
port2=$(sed -nE 's/.*127\.0\.0\.1:([0-9]+)\/ .*/\1/p' "$T/out2")
NODE_PATH="$PLAYWRIGHT_MODULES" timeout 180 node "$HERE/demo_test.js" "http://127.0.0.1:$port2/" "token=$token"
! grep -q "$token" "$T/err2" "$T/out2"
