#!/usr/bin/env bash
# Reproduces the paper's experiments (issue 5) into docs/: builds mdbrief-eval if needed, runs
# the simulation, the precision-recall evaluation and the timing table (CSVs in docs/results/),
# then draws docs/figures/*.png and regenerates the sections "## Simulation",
# "## Precision-recall" and "## Timing table" of docs/RESULTS.md.
# Usage: scripts/reproduce.sh [build-dir]   (default: build). Environment: MDBRIEF_DATA = the
# shared data folder (default ../shared/data; the Oxford sequences are skipped if absent).
# About 10 minutes on the 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
RESULTS=docs/results
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" --target mdbrief-eval -j2
EVAL="$BUILD_DIR/bench/eval/mdbrief-eval"
mkdir -p "$RESULTS" docs/figures
start=$(date +%s)
echo "== simulation"
"$EVAL" sim --out "$RESULTS"
echo "== precision-recall"
"$EVAL" eval --out "$RESULTS"
echo "== timing table"
"$EVAL" timing --out "$RESULTS"
# The view strips of the simulation are figures too.
mv -f "$RESULTS"/sim_*_views.png docs/figures/
echo "== plots and docs/RESULTS.md"
/usr/bin/python3 scripts/plot_results.py --results "$RESULTS" --figures docs/figures --md docs/RESULTS.md
echo "reproduce.sh: done in $(( $(date +%s) - start )) s"
