#!/usr/bin/env bash
# The README's main job on a fresh machine: install dependencies, build, train the perspective
# ORB pattern on the default images (opencv-doc photos), regenerate its header in patterns/,
# rebuild the library with it, then run the evaluation (docs/RESULTS.md and docs/figures).
# Usage: scripts/main.sh [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
bash scripts/build.sh "$BUILD_DIR"
# The shipped recipe of the default set: a rerun reproduces patterns/orb_perspective_512.hpp byte
# for byte (scripts/train-patterns.sh retrains every set in configs/training).
"$BUILD_DIR"/trainer/mdbrief-train --config configs/training/orb_perspective_512.toml
cmake --build "$BUILD_DIR" -j"$(nproc)"
bash scripts/reproduce.sh "$BUILD_DIR"
