#!/usr/bin/env bash
# The tracker benchmark (docs/RESULTS.md "Real images: what a tracker keeps"): every pipeline on
# the real poster-dev frames, the Oxford sequences, the rendered fisheye sequences and the
# turned-lens photos; prints the table, writes docs/results/tracker/*.csv, docs/figures/tracker.png
# and the section "## Tracker benchmark (generated)" of docs/RESULTS.md. Extra arguments go to `mdbrief-eval tracker` (e.g. --datasets
# poster-dev oxford). Usage: scripts/tracker.sh [build-dir [args...]]   (default: build).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" --target mdbrief-eval -j"$(nproc)"
OUT=docs/results/tracker
"$BUILD_DIR"/eval/mdbrief-eval tracker --out "$OUT" "${@:2}"
/usr/bin/python3 scripts/plot_tracker.py "$OUT/tracker_summary.csv" docs/figures/tracker.png --md docs/RESULTS.md
