#!/usr/bin/env bash
# Whole pipelines at equal keypoint budgets (issue 10; docs/RESULTS.md "Whole pipelines"):
# repeatability and PR AUC of every detector with its descriptor on the Oxford sequences, the
# rendered fisheye sequences and the real fisheye photos of ../shared seen by the lens turned.
# CSVs in docs/results/pipelines/. Usage: scripts/pipelines.sh [build-dir]   (default: build).
# About 30 minutes on the 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" --target mdbrief-eval -j2
EVAL="$BUILD_DIR/eval/mdbrief-eval"
OUT=docs/results/pipelines
mkdir -p "$OUT"
"$EVAL" pipelines --out "$OUT"
# The library's detectors on the stereographic view (DetectorOptions::conformal), fisheye only:
# through a perspective lens the view only adds distortion.
"$EVAL" pipelines --no-perspective --only modORB+mdBRIEF Hessian+mdBRIEF --conformal --out "$OUT/conformal"
USER_DIR=$(mktemp -d)
trap 'rm -rf "$USER_DIR"' EXIT
source scripts/real_fisheye_photos.sh
for name in $(export_real_fisheye_views "$EVAL" "${MDBRIEF_DATA:-../shared/data}" "$USER_DIR"); do
  # shellcheck disable=SC2046  # the flags are paths without spaces (a temporary folder)
  "$EVAL" pipelines --no-perspective --no-fisheye --out "$OUT/real_fisheye/$name" $(user_sequence_flags "$USER_DIR/$name")
  # shellcheck disable=SC2046
  "$EVAL" pipelines --no-perspective --no-fisheye --only modORB+mdBRIEF Hessian+mdBRIEF --conformal \
    --out "$OUT/conformal/real_fisheye/$name" $(user_sequence_flags "$USER_DIR/$name")
done
echo "pipelines.sh: CSVs in $OUT"
