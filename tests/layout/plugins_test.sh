#!/usr/bin/env bash
# Start-up stays light: OpenImageIO and libav are plugins loaded on first use, not libraries the CLI
# links (they cost ~0.35 s and ~60 ms of start-up); the plugins load from the build tree when needed.
set -euo pipefail
TH=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
! ldd "$TH" | grep -E 'libOpenImageIO|libavformat|libavcodec|libswresample'
LD_DEBUG=files "$TH" --version 2>"$T/v" >/dev/null
! grep -E 'libOpenImageIO|libavformat|libtalkhead-' "$T/v"
# Writing PNGs loads the image plugin, and only that one.
LD_DEBUG=files "$TH" corpus synth -q -o "$T/c" --size 128x72 --emotions neutral --visemes a,u 2>"$T/s"
grep -q 'file=.*lib/talkhead/libtalkhead-oiio.so' "$T/s"
! grep -q 'libtalkhead-av.so' "$T/s"
test -f "$T/c/corpus.csv"
echo "plugins ok"
