# Sourced by the browser tests (bash): skips (exit 77) without chromium, node or npm, installs
# playwright-core from npm once into ~/.cache/talkhead-tests/playwright, and sets $PLAYWRIGHT_MODULES
# (the NODE_PATH for the test's node script).
for tool in chromium node npm; do command -v $tool >/dev/null || { echo "skipped: $tool not installed (scripts/setup-deps installs it)"; exit 77; }; done
PLAYWRIGHT_CACHE="${XDG_CACHE_HOME:-$HOME/.cache}/talkhead-tests/playwright"
if [ ! -d "$PLAYWRIGHT_CACHE/node_modules/playwright-core" ]; then
	mkdir -p "$PLAYWRIGHT_CACHE"
	(cd "$PLAYWRIGHT_CACHE" && npm install --no-audit --no-fund --loglevel=error playwright-core@1.65.1 >&2) ||
		{ echo "skipped: npm could not install playwright-core"; exit 77; }
fi
PLAYWRIGHT_MODULES="$PLAYWRIGHT_CACHE/node_modules"
