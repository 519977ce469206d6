#!/usr/bin/env bash
# Regenerates patterns/brief_random_512.hpp, patterns/brief_random_512.json and
# patterns/registry.hpp with mdbrief-pattern-random (BRIEF G II Gaussian tests, fixed seed; see
# trainer/random_pattern.hpp). Builds the tool first if needed.
#   scripts/gen-random-pattern.sh [BUILD_DIR] [extra mdbrief-pattern-random flags...]
# BUILD_DIR defaults to build/. The output is byte-identical on every run and machine.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
shift || true
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" --target mdbrief-pattern-random -j"$(nproc)"
"$build/trainer/mdbrief-pattern-random" --out "$root/patterns" "$@"
