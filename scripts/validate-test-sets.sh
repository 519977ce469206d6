#!/usr/bin/env bash
# The validation protocol the training options were chosen with (docs/training.md "Validation"):
# the first 12 BSDS500 val photos (never trained on: configs/validation-images.txt) rendered as
# planes through the ideal pinhole and the LaFiDa fisheye camera at 6 poses (120 pairs), and the
# test-set study (dBRIEF/mdBRIEF at 128/256/512 bits) of each given set on them.
# Usage: scripts/validate-test-sets.sh BUILD_DIR OUT_DIR SET...   (SET: registry name or JSON file)
# Needs ../shared/data/natural/bsds500 (or MDBRIEF_DATA). About 20 s per set on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 3 ] || { echo "usage: $0 BUILD_DIR OUT_DIR SET..." >&2; exit 2; }
BUILD_DIR=$1 OUT=$2
shift 2
DATA=${MDBRIEF_DATA:-../shared/data}
[ -d "$DATA/natural/bsds500" ] || { echo "validate-test-sets: $DATA/natural/bsds500 not found" >&2; exit 2; }
args=()
for s in "$@"; do args+=(--test-set "$s"); done
textures=()
for f in $(ls "$DATA"/natural/bsds500/val_*.jpg | head -12); do textures+=(--texture "$f"); done
"$BUILD_DIR"/eval/mdbrief-eval eval --no-perspective --fisheye-camera configs/cameras/pinhole_example.yaml \
  --fisheye-camera configs/cameras/lafida_fisheye0.yaml "${textures[@]}" "${args[@]}" --out "$OUT" >&2
grep ',ALL,' "$OUT/eval_summary.csv" | cut -d, -f3,4
