#!/usr/bin/env bash
# Retrains the shipped learned test sets (configs/training/*.toml) into patterns/ with
# mdbrief-train, building it first if needed. Each run takes ~15-90 s and ~0.2 GB on 2 cores
# (docs/training.md). Outputs are byte-identical on every run.
#   scripts/train-patterns.sh [BUILD_DIR] [CONFIG...]   (default: build/, every config)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
shift || true
configs=("$@")
if [[ ${#configs[@]} -eq 0 ]]; then configs=("$root"/configs/training/*.toml); fi
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" --target mdbrief-train -j"$(nproc)"
cd "$root"  # the configs use paths relative to the repository root
for config in "${configs[@]}"; do
  "$build/trainer/mdbrief-train" --config "$config"
done
