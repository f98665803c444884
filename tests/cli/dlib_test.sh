#!/usr/bin/env bash
# dlib's face detector and 68-point predictor must take every image of the default synthetic corpus for
# a face, with eye and mouth points within 0.1 eye-corner distances of the ground truth on average.
set -euo pipefail
CHECK=$1; BUILD=$2
CORPUS=$BUILD/models/default-corpus/corpus.csv
if [ ! -f "$CORPUS" ]; then echo "default corpus not built ($CORPUS): skipped"; exit 77; fi
if [ ! -f /usr/share/dlib/shape_predictor_68_face_landmarks.dat ]; then echo "libdlib-data not installed: skipped"; exit 77; fi
"$CHECK" "$CORPUS" --max-error 0.1 | tail -20
