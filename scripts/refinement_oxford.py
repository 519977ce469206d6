#!/usr/bin/python3
"""Match refinement against the Oxford sequences' homographies (docs/RESULTS.md "Real stereo: poses
against the known pose"), a check on real images that the refinement's defaults were not chosen on:
img1 against img2..img6 of each sequence with the library's defaults (an ideal pinhole, focal
length the image width), each pair's right matches (within 3 px of where the homography takes a's
keypoint) refined, and the distance of b's point from that truth, before and after.

Usage: PYTHONPATH=build/python /usr/bin/python3 scripts/refinement_oxford.py
The data is MDBRIEF_DATA or ../shared/data; without it the script says so and exits 0.
"""
import os
import pathlib
import sys

import cv2
import numpy as np

import mdbrief

RIGHT_PX = 3.0
SEQUENCES = ["bikes", "boat", "graf", "leuven", "trees", "ubc"]


def main():
    root = pathlib.Path(os.environ.get("MDBRIEF_DATA") or pathlib.Path(__file__).resolve().parents[2] / "shared/data")
    folder = root / "oxford-affine"
    if not (folder / "graf/H1to2p").is_file():
        print(f"refinement_oxford.py: skipped, no {folder}/graf/H1to2p")
        return 0
    total_before, total_after, total_right, total_refined = [], [], 0, 0
    print(f"{'sequence':10s} {'right':>6s} {'refined':>8s}  {'before: median / p90':>21s}  {'after: median / p90':>20s}")
    for name in SEQUENCES:
        images = [cv2.imread(str(folder / name / f"img{k}.png"), cv2.IMREAD_GRAYSCALE) for k in range(1, 7)]
        if any(image is None for image in images):
            sys.exit(f"refinement_oxford.py: cannot read the images of {folder / name}")
        height, width = images[0].shape
        camera = mdbrief.Camera("pinhole", width, height, fx=width, fy=width, cx=(width - 1) / 2, cy=(height - 1) / 2)
        features = mdbrief.MdBrief(camera)
        ka, da, ma = features.detect_and_compute(images[0])
        before, after, right, refined = [], [], 0, 0
        for k in range(2, 7):
            try:
                homography = np.loadtxt(folder / name / f"H1to{k}p")
            except (OSError, ValueError) as e:
                sys.exit(f"refinement_oxford.py: cannot read {folder / name / f'H1to{k}p'}: {e}")
            if homography.shape != (3, 3) or not np.all(np.isfinite(homography)):
                sys.exit(f"refinement_oxford.py: {folder / name / f'H1to{k}p'} is no 3 x 3 matrix of finite numbers")
            if images[k - 1].shape != images[0].shape:
                continue  # the camera is the first image's
            kb, db, mb = features.detect_and_compute(images[k - 1])
            matches = mdbrief.match(da, db, ma, mb)
            if not matches:
                continue
            points_a = np.float64([ka[m.queryIdx].pt for m in matches])
            points_b = np.float64([kb[m.trainIdx].pt for m in matches])
            truth = cv2.perspectiveTransform(points_a.reshape(-1, 1, 2), homography).reshape(-1, 2)
            is_right = np.linalg.norm(points_b - truth, axis=1) <= RIGHT_PX
            result = mdbrief.refine_matches(features, images[0], ka, images[k - 1], kb, matches)
            kept = is_right & result.ok
            right += int(is_right.sum())
            refined += int(kept.sum())
            before += list(np.linalg.norm(points_b[kept] - truth[kept], axis=1))
            after += list(np.linalg.norm(result.points_b[kept] - truth[kept], axis=1))
        if before:
            print(f"{name:10s} {right:6d} {refined:8d}  {np.median(before):10.3f} / {np.percentile(before, 90):.3f}"
                  f"  {np.median(after):9.3f} / {np.percentile(after, 90):.3f}")
        total_before += before
        total_after += after
        total_right += right
        total_refined += refined
    print(f"{'all':10s} {total_right:6d} {total_refined:8d}  {np.median(total_before):10.3f} / "
          f"{np.percentile(total_before, 90):.3f}  {np.median(total_after):9.3f} / {np.percentile(total_after, 90):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
