#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Rebuilds the shipped coarticulation model (issue 48, D90): models/coarticulation/grid.tsv, learned by
# `talkhead corpus coarticulation` from the GRID clips listed in models/coarticulation/clips.tsv (95 clips,
# 6 speakers; GRID is CC BY 4.0, see NOTICE). The 11 clips of ../shared/data/grid — the evaluation set of
# bench/coarticulation.sh — and the HQ copy of one of them (av-candidates/grid-misc/s2hq_swwp2s) are not in
# the list, nor three clips whose audio `talkhead align` refuses for their sentence (s33_lbaa7a,
# s4hq_lgar9n, s4hq_swau8a: confidence 0.12, 0.05, 0.06).
# Each clip is aligned to its sentence (the words are in its file name) by `talkhead align` and tracked by
# `talkhead corpus landmarks` (dlib), as bench/coarticulation.sh does for the real speakers.
# --recognised rebuilds its companion for recognised phones instead (D106):
# models/coarticulation/grid-recognised.tsv, learned from the same clips' phones as `talkhead visemes
# --audio` recognises them (no visual lead: recognised phones are not late, D104).
#   corpus-tools/coarticulation-grid.sh [-o OUT.tsv] [--work DIR] [--without SPEAKER]... [--no-visual-lead] [--recognised]
# --without leaves a speaker's clips out (the bench's held-out models); --no-visual-lead writes no visual
# lead (corpus-tools/visual-lead.sh measures the lead with such models); the work folder caches the
# alignments and tracks (default ${TMPDIR:-/tmp}/talkhead-coarticulation-grid). About 10 min on 2 cores the
# first time, 2 s after. The result is byte-identical to the committed model (bench/coarticulation.sh
# checks).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
DATA=${SHARED_DATA:-$root/../shared/data}
out=$root/models/coarticulation/grid.tsv
work=${TMPDIR:-/tmp}/talkhead-coarticulation-grid
without=()
recognised=
# The visual lead (D104): what corpus-tools/visual-lead.sh measured on these clips (seconds).
visual_lead=-0.025
while [ $# -gt 0 ]; do
	case $1 in
		-o) out=$2; shift 2 ;;
		--work) work=$2; shift 2 ;;
		--without) without+=("$2"); shift 2 ;;
		--no-visual-lead) visual_lead=none; shift ;;
		--recognised) recognised=1; visual_lead=none; [ "$out" = "$root/models/coarticulation/grid.tsv" ] && out=$root/models/coarticulation/grid-recognised.tsv; shift ;;
		*) echo "coarticulation-grid.sh: unknown argument '$1'" >&2; exit 2 ;;
	esac
done
[ -x "$TH" ] || { echo "coarticulation-grid.sh: no talkhead at $TH (build first)" >&2; exit 1; }
[ -d "$DATA/av-candidates" ] && [ -d "$DATA/open-av" ] || { echo "coarticulation-grid.sh: no GRID clips in $DATA" >&2; exit 77; }
source "$root/examples/real-face/grid-words.sh"
mkdir -p "$work"
# The list is named in the model ("learned from N clips of clips.tsv"): a fixed name, in the work folder.
# (recognised: in a folder of its own, under the same name)
[ -n "$recognised" ] && mkdir -p "$work/recognised"
list=$work/${recognised:+recognised/}clips; for s in "${without[@]+"${without[@]}"}"; do list+=-without-$s; done; list+=.tsv
printf 'landmarks\ttranscript\tspeaker\n' >"$list"
n=0
while IFS=$'\t' read -r clip speaker; do
	[ "$clip" = clip ] && continue
	for s in "${without[@]+"${without[@]}"}"; do [ "$s" = "$speaker" ] && continue 2; done
	[ -f "$DATA/$clip" ] || { echo "coarticulation-grid.sh: $DATA/$clip is missing" >&2; exit 1; }
	base=$(basename "$clip" .mpg); c="$work/$base"
	if [ -z "$recognised" ] && [ ! -f "$c.TextGrid" ]; then
		"$TH" align "$DATA/$clip" --text "$(grid_words "${base##*_}")" --lang en-US -o "$c.TextGrid.part" -q
		mv "$c.TextGrid.part" "$c.TextGrid"
	fi
	# The phones as the recogniser hears them (D106).
	if [ -n "$recognised" ] && [ ! -f "$c.recognised.TextGrid" ]; then
		"$TH" visemes --audio "$DATA/$clip" --lang en-US --out-format textgrid -o "$c.recognised.TextGrid.part" 2>/dev/null
		mv "$c.recognised.TextGrid.part" "$c.recognised.TextGrid"
	fi
	if [ ! -f "$c.real/landmarks.tsv" ]; then
		rm -rf "$c.real"
		"$TH" corpus landmarks "$DATA/$clip" -o "$c.real" --no-pts -q
	fi
	phones=$c.TextGrid; [ -n "$recognised" ] && phones=$c.recognised.TextGrid
	printf '%s\t%s\t%s\n' "$c.real/landmarks.tsv" "$phones" "$speaker" >>"$list"
	n=$((n + 1))
done <"$root/models/coarticulation/clips.tsv"
lead=(--visual-lead "$visual_lead"); [ "$visual_lead" = none ] && lead=()
"$TH" corpus coarticulation --clips "$list" --lang en-US "${lead[@]}" -o "$out" -q
echo "coarticulation-grid.sh: $out from $n clips"
