#!/usr/bin/env bash
# Start-up stays light: OpenImageIO and libav are plugins loaded on first use, not libraries the CLI
# links (they cost ~0.35 s and ~60 ms of start-up); the plugins load from the build tree when needed.
# The server's network side (Boost.Beast, D68) is a plugin too, holding no second copy of the library.
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
# No Beast in the CLI; serve's plugin is loaded by serve alone, and links only base and the access rules
# (the rest through ServeHost): no module's code twice in one process.
nm -C "$TH" >"$T/nm"
! grep -q 'boost::beast' "$T/nm"
LD_DEBUG=files "$TH" serve --help 2>"$T/h" >/dev/null
! grep -q 'libtalkhead-serve.so' "$T/h"
so="$(dirname "$TH")/lib/talkhead/libtalkhead-serve.so"
test -f "$so"
nm -C -D --defined-only "$so" >"$T/so"
grep -q ' T talkhead::NetServer::run()' "$T/so"
if grep -E ' T talkhead::(LiveWorker|LiveSession|Language|Synthesizer|FaceModel|Performance|loadPlugin|avModule|registerTemporary|espeak)' "$T/so"; then
	echo "libtalkhead-serve.so holds code of other modules (above)"
	exit 1
fi
echo "plugins ok"
