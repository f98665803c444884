#!/usr/bin/env bash
# `pip install .` (issue 33 §1, D66): the in-tree backend packs this build into a wheel that pip installs
# into a virtual environment, offline (--no-index; numpy from Debian through --system-site-packages). The
# installed command and module work from anywhere, find their data and plugins in the environment, render
# what the build renders byte for byte, and `pip uninstall` removes all of it.
set -euo pipefail
PY=$1; SRC=$2; BUILD=$3
"$PY" -c 'import venv, ensurepip' 2>/dev/null || { echo "skipped: python3-venv is not installed (scripts/setup-deps installs it)"; exit 77; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
"$PY" -m venv --system-site-packages "$T/venv"
cd "$T"  # not the source tree: nothing may come from it
"$T/venv/bin/pip" install -q --no-index --config-settings build-dir="$BUILD" "$SRC"
test -x "$T/venv/bin/talkhead"
test -f "$T/venv/lib/talkhead/libtalkhead-av.so"
test -f "$T/venv/share/talkhead/phonetics/visemes.tsv"
test ! -e "$T/venv/share/talkhead/models/default.thm"  # the default face is made on first use (D64)
# The command: the same frames as the build's (a model given: no default face to make here).
"$BUILD/talkhead" corpus synth -q -o "$T/c" --size 160x90 --emotions neutral
"$BUILD/talkhead" build -q "$T/c/corpus.csv" -o "$T/face.thm"
env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR "$T/venv/bin/talkhead" say "Hello there" --lang en-US --model "$T/face.thm" --format y4m -o "$T/venv.y4m" -q
"$BUILD/talkhead" say "Hello there" --lang en-US --model "$T/face.thm" --format y4m -o "$T/build.y4m" -q
cmp "$T/venv.y4m" "$T/build.y4m"
env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR "$T/venv/bin/talkhead" say "Hello there" --lang en-US --model "$T/face.thm" -o "$T/venv.mp4" -q  # the libav plugin
# The module: the environment's, with its data; frames as the command's.
env -u PYTHONPATH -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR "$T/venv/bin/python" - "$T" <<'PY'
import sys
from pathlib import Path
import numpy as np
import talkhead
T = Path(sys.argv[1])
assert Path(talkhead.__file__).is_relative_to(T / "venv"), talkhead.__file__
talkhead.say("Hello there", T / "py.y4m", lang="en-US", model=T / "face.thm", format="y4m", quiet=True)
assert (T / "py.y4m").read_bytes() == (T / "venv.y4m").read_bytes()
try:
    talkhead.say("Hello", T / "x.mp4", lang="xx-XX", model=T / "face.thm")
    raise SystemExit("an unknown language raised nothing")
except talkhead.Error as e:
    assert "xx-XX" in str(e), e
print("pip install: module ok")
PY
"$T/venv/bin/pip" uninstall -q -y talkhead
test ! -e "$T/venv/bin/talkhead" && test ! -e "$T/venv/lib/talkhead/libtalkhead-av.so" && test ! -e "$T/venv/share/talkhead/phonetics"
echo "pip install: ok"
