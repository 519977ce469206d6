#!/usr/bin/env bash
# The SIMD kernels on AArch64: cross-builds tests/kernels (the kernels and their digest check,
# nothing else) with g++-aarch64-linux-gnu and runs it under qemu-user at every level (portable,
# neon), expecting the digests recorded on x86-64. qemu emulates: its times say nothing of an
# ARM board's speed. Usage: scripts/test-arm.sh [build-dir]   (default: build-arm)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build-arm}
bash scripts/setup-deps.sh
cmake -S tests/kernels -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/aarch64-linux-gnu.cmake"
cmake --build "$BUILD_DIR" -j"$(nproc)"
qemu-aarch64-static -L /usr/aarch64-linux-gnu "$BUILD_DIR/kernel_digests"
