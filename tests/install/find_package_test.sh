#!/usr/bin/env bash
# Install the build into a temporary prefix and build a small program against find_package(talkhead).
set -euo pipefail
BUILD=$1; CONSUMER=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
cmake --install "$BUILD" --prefix "$T/prefix" >/dev/null
test -x "$T/prefix/bin/talkhead"
test -f "$T/prefix/share/talkhead/schemes/imm-73.scheme"
cmake -S "$CONSUMER" -B "$T/build" -G Ninja -DCMAKE_PREFIX_PATH="$T/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$T/build" >/dev/null
"$T/build/consumer" | tee "$T/out"
grep -q "similarity scale 2" "$T/out"
# The installed CLI finds its schemes in the installed tree, and its plugins there too.
"$T/prefix/bin/talkhead" --version
LD_DEBUG=files "$T/prefix/bin/talkhead" corpus synth -q -o "$T/c" --size 128x72 --emotions neutral --visemes a,u 2>"$T/s"
grep -q "file=$T/prefix/.*/talkhead/libtalkhead-oiio.so" "$T/s"
