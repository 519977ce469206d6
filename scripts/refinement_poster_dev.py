#!/usr/bin/python3
"""Match refinement against ground truth on real fisheye frames (docs/RESULTS.md "Real stereo:
poses against the known pose", "The last change"): poster-dev's 45 pairs with the library's
defaults, each pair's right matches (within 3 px of the truth) refined at each smoothing sigma,
and the distance of b's point from the truth over the matches every sigma refines: before, and
after at each sigma. The truth maps a pixel of frame i through its ray, the poster's plane (G_i^-1)
and G_j into frame j (the data's README; its own residuals are 0.05-0.23 px median per frame).

Usage: PYTHONPATH=build/python /usr/bin/python3 scripts/refinement_poster_dev.py [--sigmas 0.6 2]
The data is MDBRIEF_DATA or ../shared/data; without it the script says so and exits 0.
"""
import argparse
import itertools
import json
import os
import pathlib
import sys

import cv2
import numpy as np

import mdbrief

RIGHT_PX = 3.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sigmas", type=float, nargs="+", default=[0.6, 2.0],
                        help="MatchRefinementOptions::smoothingSigma values to compare")
    args = parser.parse_args()
    root = pathlib.Path(os.environ.get("MDBRIEF_DATA") or pathlib.Path(__file__).resolve().parents[2] / "shared/data")
    folder = root / "fisheye/poster-dev"
    if not (folder / "ground_truth.json").is_file():
        print(f"refinement_poster_dev.py: skipped, no {folder}/ground_truth.json")
        return 0
    truth = json.loads((folder / "ground_truth.json").read_text())
    camera = mdbrief.load_camera(str(folder / "calib_results.txt"))
    features = mdbrief.MdBrief(camera)
    frames = {}
    for frame in truth["frames"]:
        image = cv2.imread(str(folder / frame["image"]), cv2.IMREAD_GRAYSCALE)
        if image is None:
            sys.exit(f"refinement_poster_dev.py: cannot read {folder / frame['image']}")
        frames[frame["image"]] = (image, np.array(frame["G"]), features.detect_and_compute(image))
    before, after = [], {s: [] for s in args.sigmas}
    refined = {s: 0 for s in args.sigmas}
    for (name_a, (image_a, g_a, (ka, da, ma))), (name_b, (image_b, g_b, (kb, db, mb))) in \
            itertools.combinations(frames.items(), 2):
        matches = mdbrief.match(da, db, ma, mb)
        if not matches:
            continue
        points_a = np.float64([ka[m.queryIdx].pt for m in matches])
        points_b = np.float64([kb[m.trainIdx].pt for m in matches])
        plane = (np.linalg.inv(g_a) @ camera.pixel_to_bearing(points_a).T).T
        rays_b = (g_b @ (plane / plane[:, 2:3]).T).T
        truth_b = camera.bearing_to_pixel(rays_b / np.linalg.norm(rays_b, axis=1, keepdims=True))
        right = np.linalg.norm(points_b - truth_b, axis=1) <= RIGHT_PX
        results = {s: mdbrief.refine_matches(features, image_a, ka, image_b, kb, matches, smoothing_sigma=s)
                   for s in args.sigmas}
        common = right.copy()
        for s, r in results.items():
            refined[s] += int((right & r.ok).sum())
            common &= r.ok
        before += list(np.linalg.norm(points_b[common] - truth_b[common], axis=1))
        for s, r in results.items():
            after[s] += list(np.linalg.norm(r.points_b[common] - truth_b[common], axis=1))
    print(f"poster-dev, {len(frames)} frames, matches every sigma refines: {len(before)}")
    print(f"  keypoints        median {np.median(before):.3f} px, p90 {np.percentile(before, 90):.3f} px")
    for s in args.sigmas:
        print(f"  refined sigma {s:g}  median {np.median(after[s]):.3f} px, p90 {np.percentile(after[s], 90):.3f} px"
              f"  ({refined[s]} right matches refined)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
