#!/usr/bin/env bash
# The README's main job on a fresh machine: install dependencies, build, train the perspective
# ORB pattern on the default images (opencv-doc photos), regenerate its header in patterns/,
# rebuild the library with it, then run the evaluation (docs/RESULTS.md and docs/figures).
# Usage: scripts/main.sh [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
bash scripts/setup-deps.sh
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j"$(nproc)"
# Same settings as the shipped header (see its header comment): a rerun reproduces it byte for byte.
"$BUILD_DIR"/trainer/mdbrief-train --detector orb --patches 20000 --seed 1 --tests 512 --name orb_perspective_512 --make-default --out patterns
cmake --build "$BUILD_DIR" -j"$(nproc)"
bash scripts/reproduce.sh "$BUILD_DIR"
