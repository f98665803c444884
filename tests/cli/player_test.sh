#!/usr/bin/env bash
# Issue 14: batch --player writes a static test player that runs in real headless Chromium (Debian
# chromium, driven by playwright-core from npm, installed once into ~/.cache/talkhead-tests): keyboard
# only, the answers' CSV in the participant's order.
set -euo pipefail
TH=$1; HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
. "$HERE/../support/playwright.sh"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
printf 'text,emotion,muted,size\nBom dia.,joy,yes,160x90\nBoa noite.,anger,yes,160x90\nOi.,fear,yes,160x90\n' >"$T/m.csv"
"$TH" batch "$T/m.csv" -o "$T/out" --player -q
# Self-contained: no http(s) URL, no external script, stylesheet or font.
! grep -Eq 'https?://|<script src|<link ' "$T/out/index.html"
NODE_PATH="$PLAYWRIGHT_MODULES" timeout 180 node "$HERE/player_test.js" "$T/out"
