#!/usr/bin/env bash
# Install the build into a temporary prefix and build a small program against find_package(talkhead).
set -euo pipefail
BUILD=$1; CONSUMER=$2; EXAMPLES=${3:-}; DATA=${4:-}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
cmake --install "$BUILD" --prefix "$T/prefix" >/dev/null
test -x "$T/prefix/bin/talkhead"
test -f "$T/prefix/share/talkhead/schemes/imm-73.scheme"
# The shipped coarticulation model and its attribution (issue 48, D90).
cmp "$T/prefix/share/talkhead/models/coarticulation/grid.tsv" "$(dirname "$0")/../../models/coarticulation/grid.tsv"
cmp "$T/prefix/share/talkhead/models/coarticulation/grid-recognised.tsv" "$(dirname "$0")/../../models/coarticulation/grid-recognised.tsv"
grep -q "M. Cooke, J. Barker, S. Cunningham & X. Shao" "$T/prefix/share/talkhead/NOTICE"
cmake -S "$CONSUMER" -B "$T/build" -G Ninja -DCMAKE_PREFIX_PATH="$T/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$T/build" >/dev/null
"$T/build/consumer" | tee "$T/out"
grep -q "similarity scale 2" "$T/out"
# The installed CLI finds its schemes in the installed tree, and its plugins there too.
"$T/prefix/bin/talkhead" --version
LD_DEBUG=files "$T/prefix/bin/talkhead" corpus synth -q -o "$T/c" --size 128x72 --emotions neutral --visemes a,u 2>"$T/s"
grep -q "file=$T/prefix/.*/talkhead/libtalkhead-oiio.so" "$T/s"
# examples/library: a transcript rendered to MP4 through the library, and frames received by a callback,
# built against the installed tree and run with its data and plugins (the prefix is relocated, so say where).
if [ -n "$EXAMPLES" ]; then
	cmake -S "$EXAMPLES" -B "$T/lib" -G Ninja -DCMAKE_PREFIX_PATH="$T/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build "$T/lib" >/dev/null
	export TALKHEAD_DATA_DIR="$T/prefix/share/talkhead"
	TALKHEAD_MODULE_DIR=$(dirname "$(find "$T/prefix" -name libtalkhead-av.so | head -1)")
	export TALKHEAD_MODULE_DIR
	"$T/prefix/bin/talkhead" corpus synth -q -o "$T/c2" --size 160x90 --emotions neutral,joy
	"$T/prefix/bin/talkhead" build -q "$T/c2/corpus.csv" -o "$T/face.thm"
	"$T/lib/render_transcript" "$T/face.thm" "$DATA/transcripts/que_noticia.TextGrid" "$T/lib.mp4" pt-BR joy | tee "$T/r"
	grep -q "frames, 160x90" "$T/r"
	frames=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 "$T/lib.mp4")
	expected=$(grep -o '^[^:]*: [0-9]*' "$T/r" | grep -o '[0-9]*$')
	test "$frames" = "$expected" || { echo "MP4 has $frames frames, the library said $expected"; exit 1; }
	"$T/lib/frame_stats" "$T/face.thm" "$DATA/transcripts/que_noticia.TextGrid" | tee "$T/f"
	grep -q "out of order 0" "$T/f"
	# The same frames through the CLI (y4m) have the same mean luma as the callback saw.
	# (frame_stats plans the thesis's way, one target per phone: the CLI's --coarticulation off.)
	"$T/prefix/bin/talkhead" render -q --model "$T/face.thm" --transcript "$DATA/transcripts/que_noticia.TextGrid" --fps 25 --format y4m --coarticulation off -o "$T/cli.y4m"
	/usr/bin/python3 - "$T/cli.y4m" "$(sed -E 's/.*mean luma ([0-9.]+).*/\1/' "$T/f")" <<'PY'
import sys
data = open(sys.argv[1], 'rb').read()
head, rest = data.split(b'\n', 1)
w = int([t for t in head.split() if t.startswith(b'W')][0][1:]); h = int([t for t in head.split() if t.startswith(b'H')][0][1:])
frame = len(b'FRAME\n') + w * h * 3 // 2
n = len(rest) // frame; s = 0.0
for i in range(n):
    y = rest[i * frame + 6: i * frame + 6 + w * h]
    s += sum(y) / (w * h)
mean = s / n
assert abs(mean - float(sys.argv[2])) < 0.01, (mean, sys.argv[2])
print(f"cli y4m: {n} frames, mean luma {mean:.2f}")
PY
fi
# The Python module (issue 33), installed with the rest: imported from the prefix's dist-packages (it
# finds the installed data by itself), renders, and raises the CLI's message.
if py=$(find "$T/prefix" -path '*dist-packages/talkhead/__init__.py' | head -1) && [ -n "$py" ]; then
	env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR PYTHONPATH="$(dirname "$(dirname "$py")")" /usr/bin/python3 - "$T" "$DATA" <<'PY'
import sys
import talkhead
t, data = sys.argv[1:3]
assert talkhead.__file__.startswith(t), talkhead.__file__
talkhead.run("corpus", "synth", "-q", "-o", f"{t}/c3", "--size", "160x90", "--emotions", "neutral", "--visemes", "sil,a,u,p1")
model = talkhead.build(f"{t}/c3/corpus.csv", f"{t}/py.thm", quiet=True)
frames = list(talkhead.frames(transcript=f"{data}/transcripts/que_noticia.TextGrid", model=model))
assert len(frames) > 10 and frames[0][1].shape == (90, 160, 3), len(frames)
try:
    talkhead.render(f"{t}/x.mp4", transcript=f"{t}/none.TextGrid", model=model)
    raise SystemExit("no error")
except talkhead.Error as e:
    assert "none.TextGrid" in str(e), e
talkhead.render(f"{t}/py.mp4", transcript=f"{data}/transcripts/que_noticia.TextGrid", model=model, quiet=True)  # libav's plugin
import os
assert os.path.getsize(f"{t}/py.mp4") > 1000 and os.environ["TALKHEAD_MODULE_DIR"].startswith(t), os.environ.get("TALKHEAD_MODULE_DIR")
print(f"installed python module: {len(frames)} frames")
PY
fi
