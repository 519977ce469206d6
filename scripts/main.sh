#!/usr/bin/env bash
# The README's main job on a fresh machine: install dependencies, build, train the default
# pattern (configs/training/orb_perspective_512.toml), regenerate its header in patterns/,
# rebuild the library with it, then run the evaluation (docs/RESULTS.md and docs/figures).
# Usage: scripts/main.sh [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
bash scripts/build.sh "$BUILD_DIR"
# The shipped recipe of the default set: a rerun reproduces patterns/orb_perspective_512.hpp byte
# for byte (scripts/train-patterns.sh retrains every set in configs/training). It trains on the
# BSDS500 photos of ../shared.
if [ -d ../shared/data/natural/bsds500 ]; then
  "$BUILD_DIR"/trainer/mdbrief-train --config configs/training/orb_perspective_512.toml
else
  echo "main.sh: ../shared/data/natural/bsds500 not found: keeping the shipped patterns/orb_perspective_512.hpp"
fi
cmake --build "$BUILD_DIR" -j"$(nproc)"
bash scripts/reproduce.sh "$BUILD_DIR"
