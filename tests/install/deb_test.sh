#!/usr/bin/env bash
# Issue 33 (D64): `cpack -G DEB` makes a Debian package whose dependencies are Debian's runtime libraries
# and espeak-ng's data, without the 1.6 GB default face; unpacked into a scratch root (dpkg-deb -x), its
# binary renders a video with its own plugins and data, and its Python module imports from there.
set -euo pipefail
BUILD=$1; DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
(cd "$BUILD" && cpack -G DEB -B "$T/pkg" >"$T/cpack.log" 2>&1) || { cat "$T/cpack.log"; exit 1; }
deb=$(ls "$T"/pkg/talkhead_*.deb)
dpkg-deb -I "$deb" >"$T/info"
cat "$T/info" | grep -E 'Package|Version|Installed-Size|Depends'
for dep in espeak-ng-data libespeak-ng1 'libavcodec[0-9]' 'libopenimageio[0-9.]' 'libopencv-imgproc[0-9.]' 'libdlib[0-9.]' 'libc6'; do
	grep -E "^ Depends: .*$dep" "$T/info" >/dev/null || { echo "no dependency on $dep"; exit 1; }
done
dpkg-deb -c "$deb" >"$T/contents"
grep -q './usr/bin/talkhead$' "$T/contents"
grep -q './usr/lib/talkhead/libtalkhead-av.so$' "$T/contents"
grep -q './usr/share/talkhead/models/au-appearance.bin$' "$T/contents"
! grep -q 'default.thm' "$T/contents"   # made on first use (D64)
size=$(du -k "$deb" | cut -f1); echo "package: $(basename "$deb"), ${size} KiB"
test "$size" -lt 100000
dpkg-deb -x "$deb" "$T/root"
TH="$T/root/usr/bin/talkhead"
# Portable (issue 44, D74): no instruction above x86-64-v3 in the binary, the plugins or the Python module
# (cpack refuses such files itself: cmake/check_isa.cmake) — and the scan can fail: an AVX-512 function is caught.
"$(dirname "$0")/../../scripts/check-isa" "$T/root"
printf '#include <immintrin.h>\n__m512 f(__m512 a, __m512 b) { return _mm512_add_ps(a, b); }\n' >"$T/v4.cpp"
c++ -O2 -mavx512f -c "$T/v4.cpp" -o "$T/v4.o"
if "$(dirname "$0")/../../scripts/check-isa" "$T/v4.o" >"$T/v4.log"; then cat "$T/v4.log"; echo "check-isa missed an AVX-512 instruction"; exit 1; fi
grep -q "vaddps %zmm" "$T/v4.log"
env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR "$TH" --version | grep -q "built for x86-64-v3"
env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR "$TH" --version
env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR "$TH" corpus synth -q -o "$T/c" --size 160x90 --emotions neutral,joy --visemes sil,a,u,p1,i1
env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR "$TH" build -q "$T/c/corpus.csv" -o "$T/face.thm"
LD_DEBUG=files env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR "$TH" render -q --model "$T/face.thm" \
	--transcript "$DATA/transcripts/que_noticia.TextGrid" --emotion joy -o "$T/out.mp4" 2>"$T/ld"
grep -q "file=$T/root/usr/lib/talkhead/libtalkhead-av.so" "$T/ld"   # the package's own plugin
frames=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 "$T/out.mp4")
test "$frames" -ge 35
echo "rendered with the packaged binary: $frames frames"
if py=$(find "$T/root" -path '*dist-packages/talkhead/__init__.py' | head -1) && [ -n "$py" ]; then
	env -u TALKHEAD_DATA_DIR -u TALKHEAD_MODULE_DIR PYTHONPATH="$(dirname "$(dirname "$py")")" /usr/bin/python3 -c "
import talkhead, sys
assert talkhead.__file__.startswith('$T'), talkhead.__file__
n = sum(1 for _ in talkhead.frames(transcript='$DATA/transcripts/que_noticia.TextGrid', model='$T/face.thm'))
print('packaged python module:', n, 'frames')"
fi
