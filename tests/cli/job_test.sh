#!/usr/bin/env bash
# talkhead job FILE|-: a job written as JSON runs as its command, byte for byte; bad jobs are one line.
set -euo pipefail
TH=$1
EX=$(cd "$(dirname "$0")/../.." && pwd)/examples
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
"$TH" corpus synth -q -o "$T/c" --size 320x180 --emotions neutral,joy
"$TH" build -q "$T/c/corpus.csv" -o "$T/face.thm"
cat >"$T/j.json" <<JSON
{"command": "render", "fields": {"transcript": "$EX/que_noticia.TextGrid", "model": "$T/face.thm", "emotion": "joy:0.6",
 "components": ["lips=3"], "fps": 25, "blinks": false, "quiet": true, "format": "y4m", "output": "$T/job.y4m"}}
JSON
"$TH" job "$T/j.json"
"$TH" render --transcript "$EX/que_noticia.TextGrid" --model "$T/face.thm" --emotion joy:0.6 --components lips=3 --fps 25 -q -o "$T/cli.y4m"
cmp "$T/job.y4m" "$T/cli.y4m"
# say's text is its field, also when it starts with a dash; from standard input.
echo '{"command": "say", "fields": {"text": "-Olá.", "dry-run": true}}' | "$TH" job - >"$T/say.tsv"
"$TH" say --dry-run -- "-Olá." >"$T/say-cli.tsv"
cmp "$T/say.tsv" "$T/say-cli.tsv"
# Bad jobs: one line naming the file, a non-zero exit, nothing written.
check() {  # expected exit, expected text, job
	local rc=0
	printf '%s' "$3" >"$T/bad.json"
	"$TH" job "$T/bad.json" 2>"$T/err" >/dev/null || rc=$?
	[ "$rc" = "$1" ] || { echo "exit $rc, not $1, for $3"; cat "$T/err"; exit 1; }
	[ "$(wc -l <"$T/err")" = 1 ] || { echo "not one line for $3"; cat "$T/err"; exit 1; }
	grep -qF -- "$2" "$T/err" || { echo "no '$2' for $3"; cat "$T/err"; exit 1; }
}
check 1 "bad.json: 'command' is 'rendr', not a talkhead command" '{"command": "rendr", "fields": {}}'
check 1 "bad.json: 'command' is 'job'" '{"command": "job", "fields": {}}'
check 1 "bad.json: a job is a JSON object" '"render"'
check 1 "bad.json" '{"command": "render", "fields": {'
check 2 "unknown option '--colour'" '{"command": "render", "fields": {"colour": "red"}}'
check 1 "none.TextGrid" "{\"command\": \"render\", \"fields\": {\"transcript\": \"$T/none.TextGrid\", \"output\": \"$T/none.mp4\"}}"
[ ! -e "$T/none.mp4" ]
echo ok
