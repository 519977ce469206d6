#!/usr/bin/python3
"""How far the library's ratio-test matches on the Oxford pairs (1-k) land from the ground truth,
by the scale of the keypoint (docs/RESULTS.md "Coarse blobs first").

Usage: PYTHONPATH=build/python /usr/bin/python3 scripts/oxford_match_errors.py
           [--data DIR] [--budget N] [--ratio R] [--exponent E ...]
DIR defaults to $MDBRIEF_DATA or ../shared/data; without its Oxford sequences the script says so
and exits 0. Each image gets its own pinhole (focal length = width), as in the tracker benchmark.
"""
import argparse
import os
import sys

import cv2
import numpy as np

import mdbrief

SEQUENCES = ["bikes", "boat", "graf", "leuven", "trees", "ubc"]
SCALE_EDGES = [0.0, 1.5, 2.5, 4.0, np.inf]  # keypoint scale (size / 31) in input pixels per level pixel
ERROR_EDGES = [1.5, 3.0, 8.0]  # px: right within 1.5, within 3, a near miss up to 8, wrong beyond


def find_image(folder, index):
    for ext in (".ppm", ".png", ".pgm", ".jpg"):
        path = os.path.join(folder, "img%d%s" % (index, ext))
        if os.path.isfile(path):
            return path
    raise FileNotFoundError("%s: no img%d" % (folder, index))


def read_grey(path):
    image = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise ValueError("%s: not an image OpenCV can read" % path)
    return image


def features(image, budget, exponent):
    h, w = image.shape
    camera = mdbrief.Camera("pinhole", w, h, fx=w, fy=w, cx=w / 2, cy=h / 2)
    extractor = mdbrief.MdBrief(camera, nfeatures=budget, hessian_scale_exponent=exponent)
    return extractor.detect_and_compute(image)


def count(oxford, budget, ratio, exponent):
    table = np.zeros((len(SCALE_EDGES) - 1, len(ERROR_EDGES) + 1), dtype=int)
    for sequence in SEQUENCES:
        folder = os.path.join(oxford, sequence)
        k1, d1, m1 = features(read_grey(find_image(folder, 1)), budget, exponent)
        for j in range(2, 7):
            k2, d2, m2 = features(read_grey(find_image(folder, j)), budget, exponent)
            H = np.loadtxt(os.path.join(folder, "H1to%dp" % j))
            for m in mdbrief.match(d1, d2, m1, m2, ratio=ratio):
                p = H @ np.array([*k1[m.queryIdx].pt, 1.0])
                error = np.linalg.norm(p[:2] / p[2] - np.array(k2[m.trainIdx].pt))
                row = np.searchsorted(SCALE_EDGES, k1[m.queryIdx].size / 31.0, side="right") - 1
                table[row, np.searchsorted(ERROR_EDGES, error)] += 1
    return table


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.environ.get("MDBRIEF_DATA", "../shared/data"))
    parser.add_argument("--budget", type=int, default=500)
    parser.add_argument("--ratio", type=float, default=0.55)
    parser.add_argument("--exponent", type=float, nargs="+", default=[0.0, 1.0])
    args = parser.parse_args()
    oxford = os.path.join(args.data, "oxford-affine")
    if not all(os.path.isdir(os.path.join(oxford, s)) for s in SEQUENCES):
        print("oxford_match_errors: skipped, no Oxford sequences under %s" % oxford)
        return 0
    print("| exponent | keypoint scale | within 1.5 px | 1.5-3 px | 3-8 px (near miss) | beyond 8 px | precision (3 px) |")
    print("|---|---|---|---|---|---|---|")
    for exponent in args.exponent:
        table = count(oxford, args.budget, args.ratio, exponent)
        for row, counts in enumerate(table):
            low, high = SCALE_EDGES[row], SCALE_EDGES[row + 1]
            scale = "%g-%g" % (low, high) if np.isfinite(high) else ">= %g" % low
            total = max(counts.sum(), 1)
            print("| %g | %s | %d | %d | %d | %d | %.3f |" % (exponent, scale, *counts, (counts[0] + counts[1]) / total))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (OSError, ValueError) as e:
        print("oxford_match_errors: %s" % e, file=sys.stderr)
        sys.exit(2)
