#!/usr/bin/python3
"""Per-call overhead of the Python binding against the same work in C++, 1000 keypoints.

    PYTHONPATH=build/python bench/python/binding_overhead.py [--rounds 15]

Each row times the Python call and the same C++ call on the same object and data, the C++ one
in a loop inside the module (mdbrief._mdbrief._native_*), alternating the two in rounds so that
machine load hits both alike, and reports medians. The image is the real fisheye photo of
../shared (OCamCalib sample) when present, else an opencv-doc photo seen through the LaFiDa
calibration's size.
"""
import argparse
import os
import pathlib
import statistics
import time

import cv2

import mdbrief
from mdbrief import _mdbrief as native

ROOT = pathlib.Path(__file__).resolve().parents[2]


def load_scene():
    data = pathlib.Path(os.environ.get("MDBRIEF_DATA", ROOT.parent / "shared" / "data"))
    sample = data / "fisheye" / "ocamcalib-sample"
    if (sample / "test_fisheye.jpg").exists():
        return (mdbrief.load_camera(str(sample / "calib_results.txt")),
                cv2.imread(str(sample / "test_fisheye.jpg"), cv2.IMREAD_GRAYSCALE), "ocamcalib-sample/test_fisheye.jpg")
    camera = mdbrief.load_camera(str(ROOT / "configs/cameras/lafida_fisheye0.yaml"))
    photo = "/usr/share/doc/opencv-doc/examples/data/graf1.png"
    return camera, cv2.resize(cv2.imread(photo, cv2.IMREAD_GRAYSCALE), camera.image_size), photo


def per_call(function, repeats):
    start = time.perf_counter()
    for _ in range(repeats):
        function()
    return (time.perf_counter() - start) / repeats


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--repeats", type=int, default=10, help="calls per round")
    args = parser.parse_args()
    cv2.setNumThreads(1)
    camera, image, name = load_scene()
    features = mdbrief.MdBrief(camera, nfeatures=1000)
    keypoints, d1, m1 = features.detect_and_compute(image)
    _, d2, m2 = features.detect_and_compute(cv2.GaussianBlur(image, (3, 3), 0))
    given = cv2.ORB_create(1000).detect(image)
    rows = {
        "detect_and_compute": (lambda: features.detect_and_compute(image),
                               lambda r: native._native_seconds(features, image, r)),
        "compute (1000 cv2.KeyPoint in)": (lambda: features.compute(image, given),
                                           lambda r: native._native_seconds(features, image, r, given)),
        "match (masked, 1000 x 1000) -> cv2.DMatch": (lambda: mdbrief.match(d1, d2, m1, m2),
                                                      lambda r: native._native_match_seconds(d1, d2, m1, m2, r)),
        "match (masked, 1000 x 1000) -> array": (lambda: mdbrief.match(d1, d2, m1, m2, as_array=True),
                                                 lambda r: native._native_match_seconds(d1, d2, m1, m2, r)),
    }
    print(f"image {name} ({image.shape[1]}x{image.shape[0]}), {len(keypoints)} keypoints detected, "
          f"{len(given)} ORB keypoints given, {args.rounds} rounds of {args.repeats} calls")
    print("| call | Python | C++ | overhead |")
    print("|---|---|---|---|")
    for label, (python_call, native_call) in rows.items():
        python_call()  # warm up caches and the thread pool
        py_times, cpp_times = [], []
        for _ in range(args.rounds):
            py_times.append(per_call(python_call, args.repeats))
            cpp_times.append(native_call(args.repeats))
        py, cpp = statistics.median(py_times), statistics.median(cpp_times)
        print(f"| {label} | {py * 1e3:.3f} ms | {cpp * 1e3:.3f} ms | {100 * (py / cpp - 1):+.1f} % |")


if __name__ == "__main__":
    main()
