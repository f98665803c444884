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
# Notation decided per file from its labels (issue 12): SAMPA's V S are ʌ ʃ, ARPAbet's are v s; MBROLA .pho
# is SAMPA (us1's r=) or br1 (x = ʃ, j = ʒ: chave, jato); labels both read differently are an error.
printf '0\t0.1\t_\n0.1\t0.2\th\n0.2\t0.3\t@\n0.3\t0.4\tl\n0.4\t0.5\t@U\n0.5\t0.6\tV\n0.6\t0.7\tS\n0.7\t0.8\t_\n' >"$T/sampa.tsv"
"$TH" visemes "$T/sampa.tsv" --lang en-US 2>"$T/n.err" | cut -f3 | tail -n +2 | tr '\n' ' ' | grep -q "^_ h ə l o w ʌ ʃ _ $"
grep -q "phones read as SAMPA/X-SAMPA (detected from '@' '@U' 'V' 'S')" "$T/n.err"
printf '0\t0.1\tS\n0.1\t0.2\tIH1\n0.2\t0.3\tT\n' >"$T/arpa.tsv"
"$TH" visemes "$T/arpa.tsv" --lang en-US --out-format json | /usr/bin/python3 -c "import json,sys; d=json.load(sys.stdin); assert d['notation']=='ARPAbet' and [p['phone'] for p in d['phones']]==['s','ɪ','t'], d"
printf '0\t0.1\tS\n0.1\t0.2\tT\n' >"$T/st.tsv"
"$TH" visemes "$T/st.tsv" --lang en-US --notation sampa 2>/dev/null | cut -f3 | tail -n +2 | tr '\n' ' ' | grep -q "^ʃ θ $"
printf '_ 100\nh 80\n@ 60\nl 70\n@U 150\nw 60\nr= 150\nl 70\nd 60\n_ 100\n' >"$T/us1.pho"
"$TH" visemes "$T/us1.pho" --lang en-US 2>/dev/null | cut -f3 | tail -n +2 | tr '\n' ' ' | grep -q "^_ h ə l o w w ɝ l d _ $"
printf '_ 100\nx 80\na 120\nv 70\ny 60\n_ 50\nj 80\na 120\nt 70\nu 100\n_ 100\n' >"$T/br1.pho"
"$TH" visemes "$T/br1.pho" 2>"$T/n.err" | cut -f3,4 | tail -n +2 | tr '\t\n' ': ' | grep -q "^_:sil ʃ:ʃ1 a:a v:f1 j:ɪ _:sil ʒ:ʃ1 a:a t:t1 u:u _:sil $"
grep -q "phones read as MBROLA br1" "$T/n.err"
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
err visemes "$T/st.tsv" --lang en-US | grep -q "$T/st.tsv: the phone labels can be read as ARPAbet or SAMPA/X-SAMPA, which differ ('S' is \[s\] or \[ʃ\]); say which with --notation arpabet or --notation sampa"
err visemes "$TG" --notation klingon | grep -q "notation takes auto"
printf '0\t0.5\ta\n0.4\t1\te\n' >"$T/overlap.tsv"
err visemes "$T/overlap.tsv" | grep -q "$T/overlap.tsv:2: interval 'e' \[0.4, 1\] overlaps 'a'"
echo "visemes ok"
