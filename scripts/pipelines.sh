#!/usr/bin/env bash
# Whole pipelines at equal keypoint budgets (issue 10; docs/RESULTS.md "Whole pipelines"):
# repeatability and PR AUC of every detector with its descriptor on the Oxford sequences, the
# rendered fisheye sequences and the real fisheye photos of ../shared seen by the lens turned.
# CSVs in docs/results/pipelines/. Usage: scripts/pipelines.sh [build-dir]   (default: build).
# About 30 minutes on the 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" --target mdbrief-eval -j2
EVAL="$BUILD_DIR/bench/eval/mdbrief-eval"
OUT=docs/results/pipelines
mkdir -p "$OUT"
"$EVAL" pipelines --out "$OUT"
DATA=${MDBRIEF_DATA:-../shared/data}
USER_DIR=$(mktemp -d)
trap 'rm -rf "$USER_DIR"' EXIT
if [ -d "$DATA/fisheye" ]; then
  while read -r name image camera; do
    [ -f "$DATA/fisheye/$image" ] || { echo "pipelines.sh: skipping $name: $DATA/fisheye/$image not found"; continue; }
    "$EVAL" export-rotated-views --image "$DATA/fisheye/$image" --camera "$DATA/fisheye/$camera" --out "$USER_DIR/$name"
    "$EVAL" pipelines --no-perspective --no-fisheye --out "$OUT/real_fisheye/$name" \
      --user-images "$USER_DIR/$name"/img{1..6}.png --user-camera "$USER_DIR/$name/camera.yaml" \
      --user-homographies "$USER_DIR/$name"/H1to{2..6}
  done <<'EOF_PHOTOS'
ocamcalib_sample ocamcalib-sample/test_fisheye.jpg ocamcalib-sample/calib_results.txt
calib_adapter_kb calib-adapter/kalibr/image.png calib-adapter/kalibr/KB.yml
calib_adapter_ocam calib-adapter/OcamCalib/image.jpg calib-adapter/OcamCalib/OcamCalib.yml
EOF_PHOTOS
else
  echo "pipelines.sh: skipping the real fisheye photos: $DATA/fisheye not found"
fi
echo "pipelines.sh: CSVs in $OUT"
