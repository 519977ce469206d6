#!/usr/bin/env bash
# The user guide's command-line walk-through (docs/guide/README.md "The command line"): extract,
# match, draw and convert a calibration with the `mdbrief` tool. The guide shows the part between
# the "[guide:NAME]" and "[guide]" lines; ctest `guide_command_line` runs the whole on two
# synthetic views and checks the outputs.
# Usage: command_line.sh MDBRIEF_TOOL CALIBRATION WORK_DIR
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: $0 MDBRIEF_TOOL CALIBRATION WORK_DIR" >&2; exit 2; }
tool=$(realpath "$1") calib=$(realpath "$2") work=$3
mkdir -p "$work"
cd "$work"
mdbrief() { "$tool" "$@"; }
# Two views at the calibration's size: a textured image and the same turned by 12 degrees.
/usr/bin/python3 - "$calib" <<'PYTHON'
import re
import sys

import cv2
import numpy as np

text = open(sys.argv[1]).read()  # the project's YAML schema: width and height at the top level
width, height = (int(re.search(rf"^{key}:\s*(\d+)", text, re.M).group(1)) for key in ("width", "height"))
rng = np.random.default_rng(7)
image = np.full((height, width), 128, np.uint8)
for i in range(900):
    x, y = (int(v) for v in rng.integers([0, 0], [width, height]))
    shade = int(rng.integers(0, 256))
    dx, dy = (int(v) for v in rng.integers(-20, 21, 2))
    cv2.rectangle(image, (x, y), (x + dx, y + dy), shade, cv2.FILLED, cv2.LINE_AA)
image = cv2.GaussianBlur(image, (0, 0), 1.0)
turn = cv2.getRotationMatrix2D((width / 2, height / 2), 12.0, 1.0)
cv2.imwrite("a.png", image)
cv2.imwrite("b.png", cv2.warpAffine(image, turn, (width, height), borderValue=128))
PYTHON
cp "$calib" calib.yaml

# [guide:command-line]
mkdir -p features
mdbrief extract --camera calib.yaml a.png b.png -o features/       # keypoints, descriptors, masks
mdbrief match features/a.yml features/b.yml -o matches.yml         # brute force, masked distance
mdbrief match features/a.yml features/b.yml --inliers --camera calib.yaml -o inliers.yml  # + essential matrix
mdbrief match features/a.yml features/b.yml --inliers --camera calib.yaml --model homography -o turned.yml  # a turn
mdbrief draw --camera calib.yaml a.png --other b.png --matches matches.yml -o matches.png
mdbrief extract --preset matching --camera calib.yaml a.png -o a_512.yml  # another preset
mdbrief camera convert calib.yaml -o converted.yaml                # any calibration file to the schema
# [guide]

for f in features/a.yml features/b.yml matches.yml inliers.yml turned.yml matches.png a_512.yml converted.yaml; do
  [ -s "$f" ] || { echo "command_line.sh: $f was not written" >&2; exit 1; }
done
grep -q "masked: 1" matches.yml || { echo "command_line.sh: matches.yml is not a masked match" >&2; exit 1; }
echo "command_line.sh: every output written"
