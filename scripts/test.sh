#!/usr/bin/env bash
# The README's test command: installs the Debian dependencies, builds (Release) and runs ctest.
# Usage: scripts/test.sh [build-dir [cmake options...]]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
bash scripts/build.sh "$BUILD_DIR" "${@:2}"
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)"
