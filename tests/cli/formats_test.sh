#!/usr/bin/env bash
# talkhead formats (issue 50, D96): the registry listed, README's table generated from it, and detection
# that never guesses — one error line naming what a file looks like, or both formats a file fits.
set -euo pipefail
trap 'echo "FAIL: $0:$LINENO: a command exited $?" >&2' ERR
TH=$1; ROOT=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT

"$TH" formats >"$T/table"
grep -q '^assemblyai  *AssemblyAI transcript' "$T/table"
grep -q 'from the file: times in ms; audio_duration' "$T/table"
grep -q '^ass  *Advanced SubStation Alpha' "$T/table"
grep -q 'not read: export SRT or WebVTT' "$T/table"
# Fields are worded as flags, never {{…}}.
! grep -q '{{' "$T/table"
"$TH" formats --format tsv >"$T/tsv"
test "$(head -1 "$T/tsv")" = $'format\twhat writes it\textensions\tlevel\ttaken from the file'
test "$(wc -l <"$T/tsv")" -gt 40
# README's table is the registry's, generated (update it with: talkhead formats --format markdown).
"$TH" formats --format markdown >"$T/md"
sed -n '/<!-- talkhead formats: begin -->/,/<!-- talkhead formats: end -->/p' "$ROOT/README.md" | sed '1d;$d' >"$T/readme"
diff "$T/md" "$T/readme" || { echo "FAIL: README's format table differs from 'talkhead formats --format markdown' (above)"; exit 1; }
rc=0; "$TH" formats --format xml 2>"$T/e" || rc=$?
test "$rc" = 2 && grep -q "formats: --format is table, tsv or markdown, not 'xml'" "$T/e"

# Detection: no fallback, one line.
one_error() {  # FILE PATTERN [OPTIONS…]
	local f=$1 pattern=$2; shift 2
	local rc=0
	"$TH" visemes "$f" "$@" >"$T/out" 2>"$T/err" || rc=$?
	if [ "$rc" = 0 ] || [ "$(grep -vc '^talkhead: warning: ' "$T/err")" != 1 ] || ! grep -Eq "^talkhead: error: $pattern" "$T/err" || [ -s "$T/out" ]; then
		echo "FAIL $f $*: exit $rc, stderr '$(cat "$T/err")' does not match /$pattern/"; exit 1
	fi
}
printf '{"foo": 1, "bar": [2]}' >"$T/odd.json"
one_error "$T/odd.json" ".*odd.json: no timing format talkhead reads matches this file \(JSON whose members are 'foo', 'bar'\); formats read: textgrid, .* \(\`talkhead formats\` describes them; --format names one\)$"
printf '0 3050 h#\n3050 4559 sh\n' >"$T/both.lab"
one_error "$T/both.lab" ".*both.lab: ambiguous: the file fits both HTK .* and TIMIT .phn; choose with --format htk or --format timit$"
"$TH" visemes "$T/both.lab" --format timit --lang en-US >/dev/null
printf '[Script Info]\nTitle: x\n' >"$T/subs.ass"
one_error "$T/subs.ass" ".*subs.ass: Advanced SubStation Alpha subtitles \(.ass/.ssa\): not read: export SRT or WebVTT"
# Units: milliseconds read as seconds are refused naming milliseconds; the right format reads them.
printf '{"words": [{"word": "one", "start": 1437, "end": 1597}, {"word": "two", "start": 1630, "end": 1822}, {"word": "three", "start": 1855, "end": 2047}]}' >"$T/ms.json"
one_error "$T/ms.json" ".*ms.json: times read as seconds are not speech: the median word lasts 192 s \(at most 5 s is speech\); they look like milliseconds"
# A speaker not in the file: the ones that are.
printf 'WEBVTT\n\n00:01.000 --> 00:02.000\n<v Anna>Hello Bob</v>\n\n00:02.000 --> 00:03.500\n<v Bob>Hi Anna</v>\n' >"$T/teams.vtt"
one_error "$T/teams.vtt" ".*teams.vtt: no voice 'Carol' in this file \(its voices: Anna, Bob\)$" --speaker Carol --lang en-US
rc=0; "$TH" visemes "$T/teams.vtt" --speaker Bob --tier Bob 2>"$T/e" >/dev/null || rc=$?
test "$rc" = 2 && grep -q -- "--tier and --speaker name the same choice" "$T/e"
"$TH" visemes "$T/teams.vtt" --speaker Bob --lang en-US -v >"$T/bob" 2>"$T/v"
grep -q 'plausible: 2 words over' "$T/v"
test "$(awk -F'\t' 'NR == 2 { print $1 }' "$T/bob")" = 2.000000
echo "formats ok"
