#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The timed phones of the CREMA-D face's takes (models/faces/crema-1001/*.TextGrid, issue 48, D91): each
# clip's sentence aligned to its audio by `talkhead align`, each in a process of its own. They are
# committed rather than aligned when the face is built because an alignment synthesises reference speech
# with libespeak-ng, whose timings depend on what it synthesised before in the same process (D51): a face
# built inside `say` would differ from one built by `talkhead faces --build`.
#   corpus-tools/face-transcripts.sh [-o DIR]   (default: rewrite them in place; DIR: write them there)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TH=${TALKHEAD:-$root/build/talkhead}
faces="$root/models/faces/crema-1001"
out=$faces
[ "${1:-}" = -o ] && out=$2 && mkdir -p "$out"
for e in NEU ANG DIS FEA HAP SAD; do
	"$TH" align "$faces/1001_DFA_${e}_XX.flv" --text "Don't forget a jacket" --lang en-US -o "$out/1001_DFA_${e}_XX.TextGrid"
done
