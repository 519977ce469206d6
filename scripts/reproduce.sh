#!/usr/bin/env bash
# Reproduces the paper's experiments (issue 5) into docs/: builds mdbrief-eval if needed, runs
# the simulation, the precision-recall evaluation and the timing table (CSVs in docs/results/),
# then draws docs/figures/*.png and regenerates the sections "## Simulation",
# "## Precision-recall" and "## Timing table" of docs/RESULTS.md.
# Usage: scripts/reproduce.sh [build-dir]   (default: build). Environment: MDBRIEF_DATA = the
# shared data folder (default ../shared/data; the Oxford sequences are skipped if absent).
# About 5 minutes on the 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
RESULTS=docs/results
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" --target mdbrief-eval -j2
EVAL="$BUILD_DIR/eval/mdbrief-eval"
mkdir -p "$RESULTS" docs/figures
start=$(date +%s)
echo "== simulation"
"$EVAL" sim --out "$RESULTS"
echo "== precision-recall"
# The user-data path end to end: a rendered sequence exported as files (images, camera.yaml,
# bearing homographies) and read back like a user's own sequence.
USER_DIR=$(mktemp -d)
trap 'rm -rf "$USER_DIR"' EXIT
"$EVAL" export-user-sample --out "$USER_DIR" --poses 6
"$EVAL" eval --out "$RESULTS" --user-images "$USER_DIR"/img{1..6}.png --user-camera "$USER_DIR/camera.yaml" \
  --user-homographies "$USER_DIR"/H1to{2..6}
# Real fisheye photos of ../shared with their calibrations, seen again by the same lens turned
# (exact ground truth: the rotations); one folder of CSVs per photo.
source scripts/real_fisheye_photos.sh
for name in $(export_real_fisheye_views "$EVAL" "${MDBRIEF_DATA:-../shared/data}" "$USER_DIR"); do
  # shellcheck disable=SC2046  # the flags are paths without spaces (a temporary folder)
  "$EVAL" eval --no-perspective --no-fisheye --out "$RESULTS/real_fisheye/$name" $(user_sequence_flags "$USER_DIR/$name")
done
echo "== timing table"
"$EVAL" timing --out "$RESULTS"
# The view strips of the simulation are figures too.
mv -f "$RESULTS"/sim_*_views.png docs/figures/
echo "== plots and docs/RESULTS.md"
/usr/bin/python3 scripts/plot_results.py --results "$RESULTS" --figures docs/figures --md docs/RESULTS.md
echo "reproduce.sh: done in $(( $(date +%s) - start )) s"
