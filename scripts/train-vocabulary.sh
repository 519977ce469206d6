#!/usr/bin/env bash
# Retrains the vocabulary shipped for the default preset, configs/vocabularies/tracking_k10_L4.mdbvoc
# (docs/vocabulary.md "The shipped vocabulary"): masked mdBRIEF-256 of the tracking preset,
# k = 10, L = 4, tf-idf, seed 1, from the 400 BSDS500 train and test photos of ../shared (the
# val photos are the validation images, configs/validation-images.txt). About 1 minute on 2
# cores; the same inputs give the same file byte for byte.
#   scripts/train-vocabulary.sh [BUILD_DIR]   (default: build/)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
data="${MDBRIEF_DATA:-$root/../shared/data}/natural/bsds500"
if [[ ! -d "$data" ]]; then
  echo "train-vocabulary.sh: $data not found: keeping the shipped vocabulary" >&2
  exit 0
fi
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" --target mdbrief-train-vocabulary -j"$(nproc)"
"$build/vocabulary/mdbrief-train-vocabulary" --images "$data"/train_* "$data"/test_* --preset tracking \
  --branching 10 --depth 4 --weighting tf-idf --seed 1 --out "$root/configs/vocabularies/tracking_k10_L4.mdbvoc"
