#!/usr/bin/env bash
# Issue 44 (D74): a second build of the command line at another -march (native where this build is the
# portable x86-64-v3, and the other way round), for the tests that compare its bytes with this build's
# (cli.cross_width, cli.slurm). Only the CLI and its plugins, with this build's default face linked in
# (TALKHEAD_DEFAULT_MODEL_FROM): ~5 min on 2 cores, nothing when the folder is up to date.
#   width_build.sh SOURCE_DIR BUILD_DIR MARCH MODELS_DIR
set -euo pipefail
SRC=$1; OUT=$2; MARCH=$3; MODELS=$4
mkdir -p "$OUT"
if ! cmake -S "$SRC" -B "$OUT" -G Ninja -DCMAKE_BUILD_TYPE=Release "-DTALKHEAD_MARCH=$MARCH" -DTALKHEAD_BUILD_TESTS=OFF \
	-DTALKHEAD_BUILD_BENCH=OFF -DTALKHEAD_PYTHON=OFF "-DTALKHEAD_DEFAULT_MODEL_FROM=$MODELS" >"$OUT/configure.log" 2>&1; then
	cat "$OUT/configure.log"; exit 1
fi
targets=(talkhead_cli default_model)
if ninja -C "$OUT" -t targets all 2>/dev/null | grep -q '^talkhead_dlib:'; then targets+=(talkhead_dlib); fi  # tracking, where dlib is
cmake --build "$OUT" --target "${targets[@]}" -j 2 >"$OUT/build.log" 2>&1 || { tail -40 "$OUT/build.log"; exit 1; }
"$OUT/talkhead" --version
