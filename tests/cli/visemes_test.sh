#!/usr/bin/env bash
# talkhead visemes: every output format, stdin, errors.
set -euo pipefail
TH=$1; DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
TG=$DATA/transcripts/que_noticia.TextGrid
# TSV rows: start, end, phone, CDV, keypose; the thesis's worked example.
"$TH" visemes "$TG" >"$T/out.tsv"
head -1 "$T/out.tsv" | grep -q $'^start\tend\tphone\tcdv\tkeypose$'
test "$(cut -f4 "$T/out.tsv" | tail -n +2 | tr '\n' ' ')" = "sil k1 i1 t1 o t1 i1 s1 e l2 e t1 ɪ sil "
grep -q $'^0.100000\t0.180000\tk\tk1\t0.140000$' "$T/out.tsv"
# Standard input, explicit format, JSON, Rhubarb outputs, TextGrid round trip.
"$TH" visemes - --format textgrid <"$TG" | cmp - "$T/out.tsv"
"$TH" visemes "$TG" --out-format json -o "$T/out.json"
/usr/bin/python3 -c "import json,sys; d=json.load(open('$T/out.json')); assert d['phones'][1]['cdv']=='k1' and d['keyposes'][0]['cdv']=='sil', d"
"$TH" visemes "$TG" --out-format rhubarb-json -o "$T/rh.json"
/usr/bin/python3 -c "import json; d=json.load(open('$T/rh.json')); assert all(c['value'] in 'ABCDEFGHX' for c in d['mouthCues']), d"
"$TH" visemes "$TG" --out-format rhubarb-tsv | head -1 | grep -q $'^0.00\tX$'
"$TH" visemes "$TG" --out-format textgrid -o "$T/out.TextGrid"
"$TH" visemes "$T/out.TextGrid" | cmp - "$T/out.tsv"
"$TH" visemes "$T/out.TextGrid" --out-format textgrid | cmp - "$T/out.TextGrid"
"$TH" visemes "$T/out.TextGrid" --tier cdv --format textgrid --unknown silence >/dev/null
# Other inputs.
"$TH" visemes "$DATA/transcripts/que_noticia.pho" | cut -f4 | tail -n +2 | tr '\n' ' ' | grep -q "^sil k1 i1 t1 o t1 i1 s1 e l2 e t1 ɪ sil $"
"$TH" visemes --lang en-US "$DATA/transcripts/hello_arpabet.lab" >/dev/null
"$TH" visemes "$DATA/transcripts/polly_visemes.marks" | sed -n 2p | cut -f4 | grep -q '^k1$'
# Pauses (D34): a leading pause of 0.6 s rests, then breathes in 0.3 s before speech (keyposes tier, JSON);
# --pauses thesis puts one silence keypose at its midpoint.
printf '0\t0.6\t_\n0.6\t0.7\ta\n0.7\t1.5\t_\n' >"$T/pause.tsv"
"$TH" visemes "$T/pause.tsv" --fps 25 --out-format json | /usr/bin/python3 -c "import json,sys; k=[(x['time'],x['cdv'],x.get('breath',False)) for x in json.load(sys.stdin)['keyposes']]; assert k==[(0.15,'sil',False),(0.3,'ɐ',True),(0.65,'a',False),(0.82,'sil',False)], k"
"$TH" visemes "$T/pause.tsv" --fps 25 --out-format json --pauses thesis | /usr/bin/python3 -c "import json,sys; k=[(x['time'],x['cdv']) for x in json.load(sys.stdin)['keyposes']]; assert k==[(0.3,'sil'),(0.65,'a'),(1.1,'sil')], k"
# Errors: one line, the file named, no output file.
err() { local rc=0; "$TH" "$@" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" != 0; test "$(wc -l <"$T/e")" = 1; cat "$T/e"; }
printf '0\t0.1\ta\n0.1\t0.2\tqq\n' >"$T/bad.tsv"
err visemes "$T/bad.tsv" -o "$T/never.tsv" | grep -q "$T/bad.tsv:2: unknown pt-BR phone 'qq'"
test ! -e "$T/never.tsv"
err visemes "$T/missing.TextGrid" | grep -q "$T/missing.TextGrid: cannot read file"
err visemes "$TG" --tier nope | grep -q "no tier named 'nope'"
err visemes "$TG" --lang xx | grep -q "no viseme table for language 'xx'"
err visemes "$TG" --out-format pdf | grep -q "unknown --out-format 'pdf'"
err visemes "$TG" --pauses none | grep -q "pauses takes natural or thesis"
printf '0\t0.5\ta\n0.4\t1\te\n' >"$T/overlap.tsv"
err visemes "$T/overlap.tsv" | grep -q "$T/overlap.tsv:2: interval 'e' \[0.4, 1\] overlaps 'a'"
echo "visemes ok"
