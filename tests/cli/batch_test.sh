#!/usr/bin/env bash
# Issue 14: talkhead batch. A small manifest renders under blind IDs with a key whose SHA-256s are the
# files'; the same seed gives a byte-identical key and orders, another seed other IDs; a rerun skips what
# is complete; a failing row leaves the others rendered and exits 1; shards 0/2 + 1/2 give the unsharded
# run's checksums; a bad manifest renders nothing.
set -euo pipefail
TH=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
# A transcript whose phone is unknown: that row fails at render time (the manifest itself is valid).
printf '0.0\t0.3\tp\n0.3\t0.6\tq!\n' >"$T/bad.tsv"
cat >"$T/m.csv" <<'CSV'
text,transcript,emotion,muted,size,condition
Bom dia.,,joy,yes,160x90,a
Bom dia.,,anger,yes,160x90,b
,bad.tsv,neutral,yes,160x90,c
Boa noite.,,fear:0.5,yes,160x90,d
CSV
set +e
"$TH" batch "$T/m.csv" -o "$T/a" --seed 5 -q; rc=$?
set -e
test $rc = 1  # one row failed
test "$(grep -c ',ok,' "$T/a/key.csv")" = 3
grep -q ',failed,' "$T/a/key.csv"
# The key's checksums are the files'.
tail -n +2 "$T/a/key.csv" | grep ',ok,' | while IFS=, read -r id row status sha file rest; do
	test "$(sha256sum "$T/a/$file" | cut -d' ' -f1)" = "$sha"
	test "$file" = "$id.mp4"
done
# 4 stimuli: a Williams design of 4 orders, each a permutation of the 4 IDs.
test "$(ls "$T/a"/order-*.csv | wc -l)" = 4
for o in "$T/a"/order-*.csv; do test "$(tail -n +2 "$o" | cut -d, -f2 | sort -u | wc -l)" = 4; done
# The failing row's file is not there; the others are.
test "$(ls "$T/a"/*.mp4 | wc -l)" = 3
# Fix the failing row's transcript: the rerun renders it and skips the three complete ones.
printf '0.0\t0.3\tp\n0.3\t0.6\ta\n' >"$T/bad.tsv"
"$TH" batch "$T/m.csv" -o "$T/a" --seed 5 2>"$T/rerun.log"
test "$(grep -c '"status": "complete"' "$T/rerun.log")" = 3
test "$(grep -c '"status": "rendered"' "$T/rerun.log")" = 1
grep -q '{"type": "summary", "stimuli": 4, "in_shard": 4, "rendered": 1, "complete": 3, "failed": 0' "$T/rerun.log"
test "$(grep -c ',ok,' "$T/a/key.csv")" = 4
# Same seed, another folder: byte-identical key and orders (and so the same checksums); another seed: other IDs.
"$TH" batch "$T/m.csv" -o "$T/b" --seed 5 -q
cmp "$T/a/key.csv" "$T/b/key.csv"
for o in "$T/a"/order-*.csv; do cmp "$o" "$T/b/$(basename "$o")"; done
"$TH" batch "$T/m.csv" -o "$T/c" --seed 6 -q
test "$(cut -d, -f1 "$T/a/key.csv" | tail -n +2)" != "$(cut -d, -f1 "$T/c/key.csv" | tail -n +2)"
# Shards: each renders its rows only; together they have the unsharded run's files.
"$TH" batch "$T/m.csv" -o "$T/s" --seed 5 --shard 0/2 -q
test "$(ls "$T/s"/*.mp4 | wc -l)" = 2
"$TH" batch "$T/m.csv" -o "$T/s" --seed 5 --shard 1/2 -q
for f in "$T/a"/*.mp4; do cmp "$f" "$T/s/$(basename "$f")"; done
cmp "$T/a/key.csv" "$T/s/key.csv"  # both shards' stimuli complete in one folder: the unsharded key
# Shards in their own folders (machines), then --merge: the unsharded key and files.
"$TH" batch "$T/m.csv" -o "$T/s0" --seed 5 --shard 0/2 -q
set +e
"$TH" batch --merge "$T/half" "$T/s0" 2>"$T/merge.err"; rc=$?
set -e
test $rc = 1 && grep -q "2 stimuli are in no shard yet" "$T/merge.err"
"$TH" batch "$T/m.csv" -o "$T/s1" --seed 5 --shard 1/2 -q
"$TH" batch --merge "$T/joined" "$T/s0" "$T/s1" -q
cmp "$T/a/key.csv" "$T/joined/key.csv"
for f in "$T/a"/*.mp4 "$T/a"/order-*.csv; do cmp "$f" "$T/joined/$(basename "$f")"; done
test "$(ls "$T/joined"/*.json | wc -l)" = 4
# A damaged file in a shard is caught.
f=$(ls "$T/s1"/*.mp4 | head -1); printf 'x' >>"$f"
set +e
"$TH" batch --merge "$T/j2" "$T/s0" "$T/s1" 2>"$T/merge.err"; rc=$?
set -e
test $rc = 1 && grep -q "does not match its SHA-256" "$T/merge.err"
# Timing for experiment software: lead-in, tail and an audio-visual offset; each stimulus's timeline.
printf 'text,muted,size,lead-in,tail,av-offset\nBom dia.,no,160x90,500,300,200\n' >"$T/t.csv"
"$TH" batch "$T/t.csv" -o "$T/t" -q
id=$(tail -n 1 "$T/t/key.csv" | cut -d, -f1)
/usr/bin/python3 - "$T/t/$id.json" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
assert abs(t["lead_in"] - 0.5) < 1e-9 and abs(t["tail"] - 0.3) < 1e-9 and abs(t["av_offset"] - 0.2) < 1e-9, t
assert 0.5 <= t["speech_onset"] < 0.6, t["speech_onset"]
assert t["keyposes"][0]["time"] >= 0.5 and t["phones"][0]["start"] == 0.5, t["keyposes"][0]
assert abs(t["duration"] - (t["speech_offset"] + 0.3)) < 0.02, (t["duration"], t["speech_offset"])
PY
# The audio starts at the speech's onset + the offset: silence until then.
onset=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['speech_onset'])" "$T/t/$id.json")
ffmpeg -nostdin -i "$T/t/$id.mp4" -af silencedetect=n=-50dB:d=0.1 -f null - 2>&1 | grep -o 'silence_end: [0-9.]*' | head -1 | awk -v o="$onset" '{ d = $2 - (o + 0.2); if (d < -0.02 || d > 0.02) { print "audio starts at " $2 ", expected " o + 0.2; exit 1 } }'
# A bad manifest: every error named, nothing rendered.
printf 'text,emotion,colour\nOi.,glee,red\n' >"$T/bad.csv"
set +e
"$TH" batch "$T/bad.csv" -o "$T/d" 2>"$T/err"; rc=$?
set -e
test $rc = 1
grep -q "bad.csv:1:colour: unknown column" "$T/err"
grep -q "bad.csv:2:emotion: unknown emotion 'glee'" "$T/err"
test ! -e "$T/d"
echo "batch: ok"
