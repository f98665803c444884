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
# The examples/tts recipe's br1 file (what espeak-ng -v mb-br1 --pho writes) reads as br1: chave, jato.
"$TH" visemes "$DATA/../../examples/tts/chave_br1.pho" 2>/dev/null | cut -f3 | tail -n +2 | tr '\n' ' ' | grep -q "^_ a ʃ a v j d u ʒ a t u _ $"
# A GRID .align is English by definition: without --lang it is read as en-US (issue 12 item 11).
printf '0 12250 sil\n12250 19250 set\n19250 27250 white\n27250 40000 sil\n' >"$T/g.align"
"$TH" visemes "$T/g.align" 2>/dev/null | cut -f3 | tail -n +2 | tr '\n' ' ' | grep -q "^_ s ɛ t w a"
# Errors: one line, the file named, no output file.
err() { local rc=0; "$TH" "$@" >"$T/o" 2>"$T/e" || rc=$?; test "$rc" != 0; test "$(wc -l <"$T/e")" = 1; cat "$T/e"; }
printf '0\t0.1\ta\n0.1\t0.2\tqq\n' >"$T/bad.tsv"
err visemes "$T/bad.tsv" -o "$T/never.tsv" | grep -q "$T/bad.tsv:2: unknown pt-BR phone 'qq'"
test ! -e "$T/never.tsv"
err visemes "$T/missing.TextGrid" | grep -q "$T/missing.TextGrid: cannot read file"
err visemes "$TG" --tier nope | grep -q "no tier named 'nope'"
err visemes "$TG" --lang xx | grep -q "no viseme table for language 'xx'"
err visemes "$TG" --out-format pdf | grep -q "unknown --out-format 'pdf'"
err visemes "$TG" --pauses none | grep -q "pauses takes natural, still or thesis"
err visemes "$T/st.tsv" --lang en-US | grep -q "$T/st.tsv: the phone labels can be read as ARPAbet or SAMPA/X-SAMPA, which differ ('S' is \[s\] or \[ʃ\]) in en-US; is that the language (--lang)? if so, say which with --notation arpabet or --notation sampa"
err visemes "$TG" --notation klingon | grep -q "notation takes auto"
printf '0\t0.5\ta\n0.4\t1\te\n' >"$T/overlap.tsv"
err visemes "$T/overlap.tsv" | grep -q "$T/overlap.tsv:2: interval 'e' \[0.4, 1\] overlaps 'a'"
# Transcripts from real tools (issue 12 items 7–10, docs/decisions.md D39).
# TextGrid writer: tg FILE 'tier|a b label|a b label…' … (long text format, times in seconds, [0, 1]).
tg() { /usr/bin/python3 - "$@" <<'PY'
import sys
out, tiers = sys.argv[1], [t.split('|') for t in sys.argv[2:]]
s = 'File type = "ooTextFile"\nObject class = "TextGrid"\n\nxmin = 0\nxmax = 1\ntiers? <exists>\nsize = %d\nitem []:\n' % len(tiers)
for i, t in enumerate(tiers):
    s += '    item [%d]:\n        class = "IntervalTier"\n        name = "%s"\n        xmin = 0\n        xmax = 1\n        intervals: size = %d\n' % (i + 1, t[0], len(t) - 1)
    for j, iv in enumerate(t[1:]):
        a, b, label = iv.split(' ', 2)
        s += '        intervals [%d]:\n            xmin = %s\n            xmax = %s\n            text = "%s"\n' % (j + 1, a, b, label)
open(out, 'w', encoding='utf-8').write(s)
PY
}
phones() { tail -n +2 | cut -f3 | tr '\n' ' '; }
# Item 7: MFA's speaker tiers; the first speaker's phones, said on stderr (one line, stdout clean); spn and
# noise tags are pauses; --tier by name.
tg "$T/multi.TextGrid" 'KY25A - words|0 0.5 yeah|0.5 1 <unk>' 'KY25A - phones|0 0.2 Y|0.2 0.5 AE1|0.5 0.8 spn|0.8 1 {LG}' \
  'IVR - words|0 1 well' 'IVR - phones|0 0.4 W|0.4 0.8 EH1|0.8 1 L'
"$TH" visemes "$T/multi.TextGrid" --lang en-US >"$T/m.tsv" 2>"$T/m.err"
grep -qx "talkhead: $T/multi.TextGrid: tier 'KY25A - phones' (phones; also 'IVR - phones' (tier 4): choose with --tier)" "$T/m.err"
test "$(phones <"$T/m.tsv")" = "j æ _ _ "
head -1 "$T/m.tsv" | grep -q $'^start\tend\tphone\tcdv\tkeypose$'
test "$("$TH" visemes "$T/multi.TextGrid" --lang en-US --tier 'IVR - phones' 2>/dev/null | phones)" = "w ɛ l "
# Item 8: an utterance tier is words, phonemised by espeak-ng; --level phones makes it an error that says so.
tg "$T/utt.TextGrid" 'utt|0 0.1 |0.1 0.9 hello there|0.9 1 '
"$TH" visemes "$T/utt.TextGrid" --lang en-US 2>"$T/u.err" | phones | grep -q "^_ h ə l o"
grep -qx "talkhead: $T/utt.TextGrid: tier 'utt' (words)" "$T/u.err"
err visemes "$T/utt.TextGrid" --lang en-US --level phones | grep -q "$T/utt.TextGrid:20: tier 'utt' holds words, not phones; use --level words ('hello there' is no en-US phone)"
tg "$T/both.TextGrid" 'words|0 1 hi' 'phones|0 0.5 h|0.5 1 aI'
test "$("$TH" visemes "$T/both.TextGrid" --lang en-US 2>/dev/null | phones)" = "h a j "
"$TH" visemes "$T/both.TextGrid" --lang en-US --level words 2>&1 >/dev/null | grep -q "tier 'words' (words)"
err visemes "$T/both.TextGrid" --level sentences | grep -q "level takes auto, phones or words"
# Item 9: festvox/EHMM xlabel (end times in seconds after a '#' line) and HTS full-context labels.
printf 'separator ;\nnfields 1\n#\n\t0.1\t26\tsil ; score -1 ;\n\t0.2\t26\thh ; score -2 ;\n\t0.3\t26\taa ; score -3 ;\n\t0.4\t26\tpau\n' >"$T/xl.lab"
test "$("$TH" visemes "$T/xl.lab" --lang en-US 2>/dev/null | phones)" = "_ h ɑ _ "
printf '0 1000000 x^x-sil+hh=aa@x_x/A:0_0_0/B:x-x-x\n1000000 2000000 x^sil-hh+aa=sil@1_2/A:0_0_0\n2000000 3000000 sil^hh-aa+sil=x@2_1/A:0_0_0\n' >"$T/fc.lab"
test "$("$TH" visemes "$T/fc.lab" --lang en-US 2>/dev/null | phones)" = "_ h ɑ "
printf '0 1000000 x^x-sil+hh=aa@x_x/A:0_0_0/B:x-x-x@x-x&x-x#x-x$x-x!x-x;x-x|x/C:1+1+2/D:0_0/E:x+x@x+x&x+x#x+x/F:content_1/G:0_0/H:x=x@1=2|0/I:4=3/J:13+9-2\n x^sil-hh+aa=sil@1_2/A:0_0_0/B:1-1-2@1-1&1-4#1-3$1-4!0-1;0-1|iy/C:1+1+4/D:0_0/E:content+1@1+3&1+2#0+1/F:content_1/G:0_0/H:4=3@1=2|L-H%%/I:9=6/J:13+9-2\n' >"$T/untimed.lab"
err visemes "$T/untimed.lab" --lang en-US | grep -qx "talkhead: error: $T/untimed.lab:2: no times: the line holds only the label 'x^sil-hh+aa=sil@1_2…' (an HTS full-context label, centre phone 'hh'); every line needs 'start end label'"
# Item 10: UTF-16 without a BOM (BE and LE) reads as UTF-8 does; no message prints a NUL byte; --unknown
# nearest is the closest spelling (ɐ̰ → ɐ), never a prefix of a sentence.
tg "$T/u8.TextGrid" 'phones|0 0.3 k|0.3 0.6 ɐ̰|0.6 1 '
"$TH" visemes "$T/u8.TextGrid" --unknown nearest >"$T/u8.tsv" 2>/dev/null
test "$(phones <"$T/u8.tsv")" = "k ɐ _ "
for enc in utf-16-be utf-16-le; do
  /usr/bin/python3 -c "import sys; open('$T/u16.TextGrid','wb').write(open('$T/u8.TextGrid',encoding='utf-8').read().encode('$enc'))"
  "$TH" visemes "$T/u16.TextGrid" --unknown nearest 2>/dev/null | cmp - "$T/u8.tsv"
done
/usr/bin/python3 -c "open('$T/bad16.tsv','wb').write('0\t0.1\tqq\n'.encode('utf-16-le'))"
err visemes "$T/bad16.tsv" | grep -q "$T/bad16.tsv:1: unknown pt-BR phone 'qq'"
printf '0\t0.1\ta\000\001\n' >"$T/nul.tsv"
err visemes "$T/nul.tsv" | grep -q "NUL bytes (the first at byte 7): not a text transcript"
test "$(tr -dc '\000' <"$T/e" | wc -c)" = 0
printf '0\t0.1\ta\n0.1\t0.9\tthis is the acoustic corpus\n' >"$T/sentence.tsv"
err visemes "$T/sentence.tsv" --unknown nearest | grep -q "$T/sentence.tsv:2: the labels hold words, not phones; use --level words"
printf '0\t0.1\ta\n0.1\t0.9\tblah\n' >"$T/blah.tsv"
err visemes "$T/blah.tsv" --unknown nearest | grep -q "$T/blah.tsv:2: unknown pt-BR phone 'blah': no known spelling is near it; correct the label, or check --lang and --notation"
echo "visemes ok"
