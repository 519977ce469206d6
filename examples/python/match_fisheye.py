#!/usr/bin/python3
"""Match two fisheye images with mdBRIEF and draw the matches to a PNG.

    PYTHONPATH=build/python examples/python/match_fisheye.py CAMERA IMAGE1 [IMAGE2] -o matches.png

CAMERA is any calibration mdbrief reads (project YAML, OCamCalib calib_results.txt,
fisheye-calib-adapter YAML). Right matches are drawn in green, wrong ones in red. Without IMAGE2
the second view is IMAGE1 seen by the same lens turned by --turn degrees, rendered through the
camera model: the true position of every match is known, and a match is right within 3 px of it.
With IMAGE2, a match is right when the relative pose that mdbrief.fit_essential finds on the
matches' bearings explains it (within 2 px; any lens, beyond 90 degrees of incidence). For example:

    PYTHONPATH=build/python examples/python/match_fisheye.py \
        ../shared/data/fisheye/ocamcalib-sample/calib_results.txt \
        ../shared/data/fisheye/ocamcalib-sample/test_fisheye.jpg -o matches.png
"""
import argparse
import sys

import cv2
import numpy as np

import mdbrief


def rotation(degrees):
    """A turn of the lens about an axis between its x and y axes."""
    axis = np.array([1.0, 1.0, 0.3]) / np.linalg.norm([1.0, 1.0, 0.3])
    return cv2.Rodrigues(axis * np.radians(degrees))[0]


def turned_view(camera, image, turn):
    """IMAGE as the lens turned by R sees it: pixel p of the new view shows bearing R^T b(p)."""
    width, height = camera.image_size
    u, v = np.meshgrid(np.arange(width, dtype=np.float64), np.arange(height, dtype=np.float64))
    bearings = camera.pixel_to_bearing(np.stack([u.ravel(), v.ravel()], axis=1)) @ turn  # rows: R^T b
    source = camera.bearing_to_pixel(bearings).astype(np.float32).reshape(height, width, 2)
    source[~camera.is_valid(np.nan_to_num(source.reshape(-1, 2), nan=-1)).reshape(height, width)] = -1
    return cv2.remap(image, source[..., 0], source[..., 1], cv2.INTER_LINEAR, borderValue=0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("camera")
    parser.add_argument("image1")
    parser.add_argument("image2", nargs="?")
    parser.add_argument("-o", "--output", required=True, help="PNG to draw the matches into")
    parser.add_argument("--turn", type=float, default=15.0, help="degrees the lens turns without IMAGE2")
    parser.add_argument("--nfeatures", type=int, default=1000)
    args = parser.parse_args()

    camera = mdbrief.load_camera(args.camera)
    image1 = cv2.imread(args.image1)
    if image1 is None:
        sys.exit(f"error: cannot read {args.image1}")
    turn = rotation(args.turn)
    image2 = turned_view(camera, image1, turn) if args.image2 is None else cv2.imread(args.image2)
    if image2 is None:
        sys.exit(f"error: cannot read {args.image2}")

    features = mdbrief.MdBrief(camera, nfeatures=args.nfeatures)
    kp1, d1, m1 = features.detect_and_compute(image1)
    kp2, d2, m2 = features.detect_and_compute(image2)
    matches = mdbrief.match(d1, d2, m1, m2, ratio=0.8, cross_check=True)
    print(f"{len(kp1)} and {len(kp2)} keypoints, {len(matches)} matches")

    correct = np.zeros(len(matches), dtype=bool)
    if args.image2 is None and matches:
        # Where each matched keypoint of view 2 truly lies in view 1: as turned_view maps it.
        seen = camera.pixel_to_bearing(np.array([kp2[m.trainIdx].pt for m in matches]))
        truth = camera.bearing_to_pixel(seen @ turn)
        found = np.array([kp1[m.queryIdx].pt for m in matches])
        correct = np.linalg.norm(truth - found, axis=1) < 3
        print(f"correct (within 3 px of the true position): {correct.sum()} of {len(matches)}")
    elif matches:
        pixels1 = np.array([kp1[m.queryIdx].pt for m in matches], dtype=np.float64)
        pixels2 = np.array([kp2[m.trainIdx].pt for m in matches], dtype=np.float64)
        a, b = camera.pixel_to_bearing(pixels1), camera.pixel_to_bearing(pixels2)
        scale = mdbrief.pixels_per_radian(camera, pixels2)
        usable = ~np.isnan(a).any(axis=1) & ~np.isnan(b).any(axis=1) & ~np.isnan(scale)
        fit = mdbrief.fit_essential(a[usable], b[usable], pixels_per_radian=scale[usable])
        if fit.ok:
            correct[np.flatnonzero(usable)[fit.inliers]] = True
            print(f"right (the fitted relative pose explains them within 2 px): {correct.sum()} of {len(matches)}")
        else:
            print(f"no relative pose: {fit.reason}; every match is drawn as wrong")

    green, red = (0, 200, 0), (0, 0, 255)
    flags = cv2.DrawMatchesFlags_NOT_DRAW_SINGLE_POINTS
    canvas = cv2.drawMatches(image1, kp1, image2, kp2, [m for m, ok in zip(matches, correct) if ok], None,
                             matchColor=green, singlePointColor=green, flags=flags)
    canvas = cv2.drawMatches(image1, kp1, image2, kp2, [m for m, ok in zip(matches, correct) if not ok], canvas,
                             matchColor=red, singlePointColor=red,
                             flags=flags | cv2.DrawMatchesFlags_DRAW_OVER_OUTIMG)
    if not cv2.imwrite(args.output, canvas):
        sys.exit(f"error: cannot write {args.output}")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
