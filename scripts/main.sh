#!/usr/bin/env bash
# The README's main job on a fresh machine: install dependencies, build, train the default
# pattern (configs/training/orb_perspective_512.toml), regenerate its header in patterns/,
# rebuild the library with it, then run the evaluation (scripts/reproduce.sh: into BUILD_DIR/results
# by default, --out DIR; --update-docs also rewrites docs/RESULTS.md's generated sections).
# Usage: scripts/main.sh [--out DIR | --update-docs] [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/output_folder.sh
parse_output_flags "$@"
OUTPUT_FLAGS=()
if [ "$UPDATE_DOCS" = 1 ]; then OUTPUT_FLAGS+=(--update-docs); fi
if [ -n "$OUT_ROOT" ]; then OUTPUT_FLAGS+=(--out "$OUT_ROOT"); fi
if [ "$DRY_RUN" = 1 ]; then
  echo "main.sh: --dry-run is not supported (it installs and builds); try scripts/reproduce.sh --dry-run" >&2
  exit 2
fi
set -- "${REST[@]+"${REST[@]}"}"
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
bash scripts/reproduce.sh "${OUTPUT_FLAGS[@]+"${OUTPUT_FLAGS[@]}"}" "$BUILD_DIR"
