#!/usr/bin/env bash
# Installs the Debian dependencies, configures (Release) and builds everything.
# Usage: scripts/build.sh [build-dir]   (default: build). Used by test.sh and main.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
bash scripts/setup-deps.sh
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j"$(nproc)"
