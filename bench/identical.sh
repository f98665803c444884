#!/usr/bin/env bash
# Behaviour unchanged (issue 30, 46): ~30 cases — the README's renders (emotions, sources, fit, controls,
# sidecars), visemes as JSON and Rhubarb JSON, `say` (text, SSML, saved speech and transcript, dry run), two
# batches with their players, live session scripts (`talkhead live`, the serve path frame for frame; y4m and
# mp4), and with the research data beside the project a GRID clip with its audio, its text aligned, a
# sentence cue aligned, a driving video, a driven mouth, a forced alignment, a tracked control track and
# the learned mouth (D62: render, say and live with a coarticulation model learned from two GRID clips) — rendered by two talkhead binaries; every output is compared byte for byte (frames, MP4
# and WAV bytes, keys, orders, sidecars, stdout). One line per case; exit 1 on any difference.
#   bench/identical.sh BASE_TALKHEAD [NEW_TALKHEAD]   two built binaries (NEW: build/talkhead)
#   bench/identical.sh GIT_REF [NEW_TALKHEAD]         first builds GIT_REF's CLI in a scratch worktree (a full
#                                                     build: ~10 min on 2 cores), with NEW's default face
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
base=${1:?usage: bench/identical.sh BASE_TALKHEAD|GIT_REF [NEW_TALKHEAD]}
new=$(realpath "${2:-$root/build/talkhead}")
tmp=$(mktemp -d); trap 'rm -rf "$tmp"; [ -n "${wt:-}" ] && git -C "$root" worktree remove --force "$wt" 2>/dev/null || true' EXIT
if [ -x "$base" ]; then base=$(realpath "$base"); else
	wt="$tmp/base-tree"
	git -C "$root" worktree add --detach "$wt" "$base" >/dev/null
	echo "building $base in $wt (the CLI and its face tracker)"
	# The default face reused from this checkout's build (both sides then draw the same model).
	cmake -S "$wt" -B "$wt/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTALKHEAD_DEFAULT_MODEL_FROM="$(dirname "$new")/models" >"$tmp/cmake.log" 2>&1 ||
		{ tail -20 "$tmp/cmake.log"; exit 1; }
	ninja -C "$wt/build" talkhead_cli talkhead_dlib default_model >"$tmp/build.log" 2>&1 || { tail -20 "$tmp/build.log"; exit 1; }
	base="$wt/build/talkhead"
fi
ex="$root/examples"
# Each case: NAME, then a command with @TH@ for the binary and @OUT@ for its output folder.
cases=(
	"render-example|@TH@ render --transcript $ex/que_noticia.TextGrid --emotion joy --size 320x180 --format y4m -o @OUT@/a.y4m -q"
	"render-anger-0.6|@TH@ render --transcript $ex/que_noticia.TextGrid --emotion anger:0.6 --size 320x180 --format y4m -o @OUT@/a.y4m -q"
	"render-au|@TH@ render --transcript $ex/que_noticia.TextGrid --emotion distress --emotion-source au --size 320x180 --format y4m -o @OUT@/a.y4m -q"
	"render-pho|@TH@ render --transcript $ex/tts/que.pho --emotion hope --trajectory linear --size 320x180 --format y4m -o @OUT@/a.y4m -q"
	"render-polly|@TH@ render --transcript $ex/tts/polly_marks.json --lang en-US --size 320x180 --format y4m -o @OUT@/a.y4m -q"
	"render-controls|@TH@ render --transcript $ex/que_noticia.TextGrid --controls $tmp/controls.json --size 320x180 --format y4m -o @OUT@/a.y4m -q"
	"say-pt|@TH@ say 'Que notícia excelente!' --lang pt-BR --emotion joy --size 320x180 -o @OUT@/a.mp4 -q"
	"say-en-ssml|@TH@ say '<speak>Hello <blink/>there. <break time=\"300ms\"/><emotion name=\"anger\" intensity=\"0.7\">Stop <brows down=\"0.6\"/>that.</emotion><mark name=\"m\"/></speak>' --lang en-US --size 320x180 -o @OUT@/a.mp4 -q"
	"batch|@TH@ batch $tmp/manifest.csv -o @OUT@/stimuli --seed 7 --player --player-lang pt -q"
	"batch-player-en|@TH@ batch $tmp/manifest.csv -o @OUT@/stimuli --seed 7 --player -q"
	"live|@TH@ live $tmp/session.jsonl --size 320x180 --format y4m -o @OUT@/a.y4m -q"
	"live-mp4|@TH@ live $tmp/session.jsonl --size 320x180 -o @OUT@/a.mp4"
	"render-fit-pad|@TH@ render --transcript $ex/que_noticia.TextGrid --size 200x200 --fit pad --format y4m -o @OUT@/a.y4m -q"
	"live-fit-crop|@TH@ live $tmp/session.jsonl --size 200x90 --fit crop --format y4m -o @OUT@/a.y4m -q"
	"render-timeline|@TH@ render --transcript $ex/que_noticia.TextGrid --emotion joy --lead-in 0.3 --tail 0.2 --size 160x90 --format y4m -o @OUT@/a.y4m --timeline-out @OUT@/t.json -q"
	"say-save|@TH@ say 'Bom dia, tudo bem?' --size 160x90 -o @OUT@/a.mp4 --save-audio @OUT@/a.wav --save-transcript @OUT@/a.TextGrid --timeline-out @OUT@/t.json -q"
	"say-dry-run|@TH@ say 'Que notícia excelente!' --dry-run"
	"visemes-json|@TH@ visemes $ex/que_noticia.TextGrid --out-format json"
	"visemes-rhubarb|@TH@ visemes $ex/que_noticia.TextGrid --out-format rhubarb-json -o @OUT@/r.json"
	"live-speak|@TH@ live $tmp/speak.jsonl --size 320x180 --format y4m -o @OUT@/a.y4m -q"
	"live-speak-webm|@TH@ live $tmp/speak.jsonl --size 160x90 --background transparent -o @OUT@/a.webm -q"
	"batch-columns|@TH@ batch $tmp/manifest2.csv -o @OUT@/stimuli --seed 3 -q"
)
# With the research data beside the project: speech from a real clip (its GRID alignment, its text aligned
# to it, sentence cues aligned to it) and a driving video.
grid="$root/../shared/data/grid"
if [ -f "$grid/swwp2s.align" ] && [ -f "$grid/id2_vcd_swwp2s.mpg" ]; then
	cases+=(
		"render-grid-audio|@TH@ render --transcript $grid/swwp2s.align --audio $grid/id2_vcd_swwp2s.mpg --size 160x90 --format y4m -o @OUT@/a.y4m -q"
		"render-text-audio|@TH@ render --text 'set white with p two soon' --audio $grid/id2_vcd_swwp2s.mpg --lang en-US --size 160x90 --format y4m -o @OUT@/a.y4m --timeline-out @OUT@/t.json -q"
		"render-cue-audio|@TH@ render --transcript $tmp/cue.srt --audio $grid/id2_vcd_swwp2s.mpg --lang en-US --size 160x90 --format y4m -o @OUT@/a.y4m -q"
		"render-drive|@TH@ render --transcript $grid/swwp2s.align --drive $grid/id2_vcd_swwp2s.mpg --size 160x90 --format y4m -o @OUT@/a.y4m -q"
		"align-text|@TH@ align $grid/id2_vcd_swwp2s.mpg --text 'set white with p two soon' --lang en-US -o @OUT@/a.TextGrid -q"
		"track-controls|@TH@ track $grid/id2_vcd_swwp2s.mpg --parts head,brows,eyes,mouth -o @OUT@/c.json -q"
		"render-drive-mouth|@TH@ render --drive $grid/id2_vcd_swwp2s.mpg --drive-mouth --size 160x90 --format y4m -o @OUT@/a.y4m -q"
		"render-coarticulation|@TH@ render --transcript $grid/swwp2s.align --audio $grid/id2_vcd_swwp2s.mpg --coarticulation $tmp/coart.tsv --emotion joy --size 160x90 --format y4m -o @OUT@/a.y4m -q"
		"say-coarticulation|@TH@ say 'Hello there, how are you today?' --lang en-US --coarticulation $tmp/coart.tsv --emotion anger:0.7 --size 160x90 --format y4m -o @OUT@/a.y4m -q"
		"live-coarticulation|@TH@ live $tmp/session.jsonl --coarticulation $tmp/coart.tsv --size 160x90 --format y4m -o @OUT@/a.y4m -q"
	)
	printf '1\n00:00:00,500 --> 00:00:02,800\nset white with p two soon\n' >"$tmp/cue.srt"
	# A coarticulation model (D62) from two GRID clips, learned once by the new binary: both sides use it.
	printf 'landmarks\ttranscript\tspeaker\n' >"$tmp/coart-clips.tsv"
	source "$root/examples/real-face/grid-words.sh"
	for b in bbaf2n lbax4n; do
		"$new" align "$grid/$b.mpg" --text "$(grid_words $b)" --lang en-US -o "$tmp/$b.TextGrid" -q
		"$new" corpus landmarks "$grid/$b.mpg" -o "$tmp/$b.real" --no-pts -q
		printf '%s\t%s\t%s\n' "$tmp/$b.real/landmarks.tsv" "$tmp/$b.TextGrid" "$b" >>"$tmp/coart-clips.tsv"
	done
	"$new" corpus coarticulation --clips "$tmp/coart-clips.tsv" --lang en-US -o "$tmp/coart.tsv" -q
fi
cat >"$tmp/manifest.csv" <<CSV
text,transcript,emotion,size,versus:emotion,condition
Bom dia.,,joy:0.5,160x90,,a
,$ex/que_noticia.TextGrid,fear,160x90,,b
Que notícia excelente!,,anger,160x90,distress,c
CSV
cat >"$tmp/manifest2.csv" <<CSV
text,transcript,emotion,intensity,size,trajectory,lead-in,tail,muted,crf,condition
Bom dia.,,anger,0.4,160x90,linear,200,100,yes,30,a
,$ex/que_noticia.TextGrid,joy:1.3,,160x90,monotone,,,,,b
,$ex/que_noticia.TextGrid,,,160x90,,,,,,c
CSV
# A speak (raw PCM, its timing as a TextGrid), emotions with intensities, a stop mid-word, a say.
python3 - "$ex/que_noticia.TextGrid" >"$tmp/speak.jsonl" <<'PY'
import base64, json, math, struct, sys
tg = open(sys.argv[1], encoding="utf-8").read()
pcm = b"".join(struct.pack("<h", int(6000 * math.sin(2 * math.pi * 180 * n / 16000) * (0.5 + 0.5 * math.sin(n / 900)))) for n in range(16000 * 2))
print(json.dumps({"frame": 2, "request": {"type": "emotion", "emotion": "distress", "intensity": 0.6, "ramp": 0.2}}))
print(json.dumps({"frame": 5, "request": {"type": "speak", "id": 1, "audio": base64.b64encode(pcm).decode(), "encoding": "pcm_s16le", "sample_rate": 16000, "transcript": tg, "lang": "pt-BR", "emotion": "joy", "intensity": 1.2}}))
print(json.dumps({"frame": 50, "request": {"type": "emotion", "emotion": "anger", "intensity": 0.3, "ramp": 0}}))
print(json.dumps({"frame": 70, "request": {"type": "stop", "id": "s"}}))
print(json.dumps({"frame": 75, "request": {"type": "say", "id": "b", "text": "Tudo bem.", "lang": "pt-BR", "emotion": "fear"}}))
print(json.dumps({"type": "end", "frame": 130}))
PY
cat >"$tmp/controls.json" <<'JSON'
{"events": [
  {"type": "emotion", "time": 0.4, "emotion": "anger", "intensity": 0.9, "ramp": 0.3},
  {"type": "blink", "time": 0.3},
  {"type": "nod", "time": 0.8, "duration": 0.6, "amount": 1},
  {"type": "brows", "time": 1.0, "duration": 0.5, "raise": 0.8},
  {"type": "au", "time": 0.5, "au": "AU12", "intensity": 0.7, "side": "left", "onset": 0.2, "apex": 0.3, "offset": 0.2}]}
JSON
cat >"$tmp/session.jsonl" <<'JSONL'
{"frame": 3, "request": {"type": "say", "id": "a", "text": "Hello there.", "lang": "en-US"}}
{"frame": 40, "request": {"type": "emotion", "emotion": "joy", "intensity": 0.8}}
{"frame": 45, "request": {"type": "say", "id": "b", "text": "<speak>Good <blink/>news!</speak>", "lang": "en-US"}}
{"frame": 120, "request": {"type": "stop"}}
{"type": "end", "frame": 150}
JSONL
fail=0
for c in "${cases[@]}"; do
	name=${c%%|*} cmd=${c#*|}
	for side in base new; do
		bin=$base; [ $side = new ] && bin=$new
		mkdir -p "$tmp/$side/$name"
		run=${cmd//@TH@/\'$bin\'}; run=${run//@OUT@/$tmp/$side/$name}
		(cd "$tmp" && eval "$run") >"$tmp/$side/$name.stdout" 2>"$tmp/$side/$name.stderr" || { echo "$name: the $side binary failed: $(tail -2 "$tmp/$side/$name.stderr")"; fail=1; continue 2; }
	done
	a=$(cd "$tmp/base/$name" && find . -type f | sort | xargs sha256sum | sha256sum | cut -c1-16)
	b=$(cd "$tmp/new/$name" && find . -type f | sort | xargs sha256sum | sha256sum | cut -c1-16)
	files=$(cd "$tmp/new/$name" && find . -type f | wc -l)
	if [ "$a" = "$b" ] && cmp -s "$tmp/base/$name.stdout" "$tmp/new/$name.stdout"; then
		echo "$name: identical ($files files, $a)"
	else
		echo "$name: DIFFERENT"; diff -r -q "$tmp/base/$name" "$tmp/new/$name" | head -5 || true; fail=1
	fi
done
[ $fail = 0 ] && echo "identical: every case byte for byte" || { echo "identical: differences (above)"; exit 1; }
