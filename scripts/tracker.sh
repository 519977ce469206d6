#!/usr/bin/env bash
# The tracker benchmark (docs/RESULTS.md "Real images: what a tracker keeps"): every pipeline on
# the real poster-dev frames, the Oxford sequences, the rendered fisheye sequences and the
# turned-lens photos; prints the table, writes tracker/*.csv, figures/tracker.png and the section
# "## Tracker benchmark (generated)" of a copy of docs/RESULTS.md into the output folder
# (scripts/output_folder.sh: default BUILD_DIR/results, --out DIR; --update-docs also rewrites that
# section of docs/RESULTS.md and docs/figures/tracker.png).
# Extra arguments go to `mdbrief-eval tracker` (e.g. --datasets poster-dev oxford).
# Usage: scripts/tracker.sh [--out DIR | --update-docs] [--dry-run] [build-dir [args...]]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/output_folder.sh
parse_output_flags "$@"
set -- "${REST[@]+"${REST[@]}"}"
BUILD_DIR=${1:-build}
resolve_output_folder
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  run cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
run cmake --build "$BUILD_DIR" --target mdbrief-eval -j"$(nproc)"
OUT=$OUT_ROOT/tracker
run "$BUILD_DIR"/eval/mdbrief-eval tracker --out "$OUT" "${@:2}"
run /usr/bin/python3 scripts/plot_tracker.py "$OUT/tracker_summary.csv" "$FIGURES/tracker.png" --md "$RESULTS_MD"
report_output_folder
