#!/usr/bin/env bash
# Whole pipelines at equal keypoint budgets (docs/RESULTS.md "Whole pipelines"): repeatability
# and PR AUC of every detector with its descriptor on the Oxford sequences, the rendered fisheye
# sequences and the real fisheye photos of ../shared seen by the lens turned. CSVs in
# pipelines/ of the output folder (scripts/output_folder.sh: default BUILD_DIR/results, --out
# DIR). The section is written by hand from them: --update-docs changes nothing in docs/.
# Usage: scripts/pipelines.sh [--out DIR | --update-docs] [--dry-run] [build-dir]   (default: build).
# About 30 minutes on the 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/output_folder.sh
parse_output_flags "$@"
set -- "${REST[@]+"${REST[@]}"}"
BUILD_DIR=${1:-build}
if [ "$UPDATE_DOCS" = 1 ]; then
  # No section of docs/RESULTS.md is generated from these CSVs: the plain run, with a note.
  echo "pipelines.sh: --update-docs: nothing to update in docs/; \"Whole pipelines\" is copied by hand from the CSVs" >&2
  UPDATE_DOCS=0
fi
resolve_output_folder
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  run cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
run cmake --build "$BUILD_DIR" --target mdbrief-eval -j2
EVAL="$BUILD_DIR/eval/mdbrief-eval"
OUT=$OUT_ROOT/pipelines
run mkdir -p "$OUT"
run "$EVAL" pipelines --out "$OUT"
# The library's detectors on the stereographic view (DetectorOptions::conformal), fisheye only:
# through a perspective lens the view only adds distortion.
run "$EVAL" pipelines --no-perspective --only modORB+mdBRIEF Hessian+mdBRIEF --conformal --out "$OUT/conformal"
USER_DIR=$(mktemp -d)
trap 'rm -rf "$USER_DIR"' EXIT
source scripts/real_fisheye_photos.sh
for name in $(export_real_fisheye_views "$EVAL" "${MDBRIEF_DATA:-../shared/data}" "$USER_DIR"); do
  # shellcheck disable=SC2046  # the flags are paths without spaces (a temporary folder)
  run "$EVAL" pipelines --no-perspective --no-fisheye --out "$OUT/real_fisheye/$name" $(user_sequence_flags "$USER_DIR/$name")
  # shellcheck disable=SC2046
  run "$EVAL" pipelines --no-perspective --no-fisheye --only modORB+mdBRIEF Hessian+mdBRIEF --conformal \
    --out "$OUT/conformal/real_fisheye/$name" $(user_sequence_flags "$USER_DIR/$name")
done
report_output_folder
