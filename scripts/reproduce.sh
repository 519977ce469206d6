#!/usr/bin/env bash
# Reproduces the paper's experiments: builds mdbrief-eval if needed, runs the simulation, the
# precision-recall evaluation and the timing table (CSVs), then draws the figures (figures/*.png)
# and regenerates the sections "## Simulation", "## Precision-recall", "## Learned vs random test
# sets", "## Real fisheye photos (turned lens)" and "## Timing table" of a copy of docs/RESULTS.md,
# all in the output folder (scripts/output_folder.sh: default BUILD_DIR/results, --out DIR;
# --update-docs also rewrites those sections of docs/RESULTS.md and the figures docs/figures keeps).
# Usage: scripts/reproduce.sh [--out DIR | --update-docs] [--dry-run] [build-dir]   (default: build).
# Environment: MDBRIEF_DATA = the shared data folder (default ../shared/data; the Oxford
# sequences are skipped if absent). About 5 minutes on the 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/output_folder.sh
parse_output_flags "$@"
set -- "${REST[@]+"${REST[@]}"}"
BUILD_DIR=${1:-build}
resolve_output_folder
RESULTS=$OUT_ROOT
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  run cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
run cmake --build "$BUILD_DIR" --target mdbrief-eval -j2
EVAL="$BUILD_DIR/eval/mdbrief-eval"
run mkdir -p "$RESULTS" "$FIGURES"
start=$(date +%s)
echo "== simulation"
run "$EVAL" sim --out "$RESULTS"
echo "== precision-recall"
# The user-data path end to end: a rendered sequence exported as files (images, camera.yaml,
# bearing homographies) and read back like a user's own sequence.
USER_DIR=$(mktemp -d)
trap 'rm -rf "$USER_DIR"' EXIT
run "$EVAL" export-user-sample --out "$USER_DIR" --poses 6
run "$EVAL" eval --out "$RESULTS" --user-images "$USER_DIR"/img{1..6}.png --user-camera "$USER_DIR/camera.yaml" \
  --user-homographies "$USER_DIR"/H1to{2..6}
# Real fisheye photos of ../shared with their calibrations, seen again by the same lens turned
# (exact ground truth: the rotations); one folder of CSVs per photo.
source scripts/real_fisheye_photos.sh
for name in $(export_real_fisheye_views "$EVAL" "${MDBRIEF_DATA:-../shared/data}" "$USER_DIR"); do
  # shellcheck disable=SC2046  # the flags are paths without spaces (a temporary folder)
  run "$EVAL" eval --no-perspective --no-fisheye --out "$RESULTS/real_fisheye/$name" $(user_sequence_flags "$USER_DIR/$name")
done
echo "== timing table"
run "$EVAL" timing --out "$RESULTS"
# The view strips of the simulation are figures too.
run sh -c 'mv -f "$1"/sim_*_views.png "$2"/' mv "$RESULTS" "$FIGURES"
echo "== plots and $RESULTS_MD"
run /usr/bin/python3 scripts/plot_results.py --results "$RESULTS" --figures "$FIGURES" --md "$RESULTS_MD"
echo "reproduce.sh: done in $(( $(date +%s) - start )) s"
report_output_folder
