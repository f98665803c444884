#!/usr/bin/env bash
# Issue 14: batch --player writes a static test player that runs in real headless Chromium (Debian
# chromium, driven by playwright-core from npm, installed once into ~/.cache/talkhead-tests): keyboard
# only, the answers' CSV in the participant's order.
set -euo pipefail
TH=$1; HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for tool in chromium node npm; do command -v $tool >/dev/null || { echo "skipped: $tool not installed (scripts/setup-deps installs it)"; exit 77; }; done
cache="${XDG_CACHE_HOME:-$HOME/.cache}/talkhead-tests/playwright"
if [ ! -d "$cache/node_modules/playwright-core" ]; then
	mkdir -p "$cache"
	(cd "$cache" && npm install --no-audit --no-fund --loglevel=error playwright-core@1.65.1 >&2) ||
		{ echo "skipped: npm could not install playwright-core"; exit 77; }
fi
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
printf 'text,emotion,muted,size\nBom dia.,joy,yes,160x90\nBoa noite.,anger,yes,160x90\nOi.,fear,yes,160x90\n' >"$T/m.csv"
"$TH" batch "$T/m.csv" -o "$T/out" --player -q
# Self-contained: no http(s) URL, no external script, stylesheet or font.
! grep -Eq 'https?://|<script src|<link ' "$T/out/index.html"
NODE_PATH="$cache/node_modules" timeout 180 node "$HERE/player_test.js" "$T/out"
