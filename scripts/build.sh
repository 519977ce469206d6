#!/usr/bin/env bash
# Installs the Debian dependencies, configures (Release) and builds everything.
# Usage: scripts/build.sh [build-dir [cmake options...]]   (default: build). Used by test.sh and
# main.sh; .ci/run passes -DMDBRIEF_PORTABLE_KERNELS=ON for the portable variant.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
bash scripts/setup-deps.sh
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release "${@:2}"
cmake --build "$BUILD_DIR" -j"$(nproc)"
