#!/usr/bin/python3
"""Does detecting on a conformal (stereographic) image of a fisheye frame make the Hessian
detector more repeatable? An experiment of issue 10's "distortion awareness", built on the
Python module.

    PYTHONPATH=build/python bench/python/conformal_detection.py [--budget 500] [--data ../shared/data]

The stereographic projection r = 2 f tan(theta / 2) is conformal: a small structure keeps its
shape wherever the lens sees it, only its scale changes, which a scale-space detector absorbs.
Each real fisheye photo of ../shared is seen again by the same lens turned by 10..40 degrees
(rendered through its calibration, exact ground truth), so structures move between the centre
and the rim. Repeatability: of the keypoints of view 1 whose true position lies in the valid part
of view 2, the fraction with a view-2 keypoint within 3 px (positions in the fisheye images).

Rows: modORB and Hessian on the fisheye image as the library runs them; Hessian on the
stereographic image at the centre's resolution (zoom 1) and at about the fisheye image's pixel
count (zoom < 1), keypoints mapped back through the camera model.
"""
import argparse
import os
import pathlib

import cv2
import numpy as np

import mdbrief

PHOTOS = [("ocamcalib_sample", "ocamcalib-sample/calib_results.txt", "ocamcalib-sample/test_fisheye.jpg"),
          ("calib_adapter_kb", "calib-adapter/kalibr/KB.yml", "calib-adapter/kalibr/image.png"),
          ("calib_adapter_ocam", "calib-adapter/OcamCalib/OcamCalib.yml", "calib-adapter/OcamCalib/image.jpg")]
TURNS = [10, 20, 30, 40]


def rotation(degrees):
    axis = np.array([1.0, 1.0, 0.3]) / np.linalg.norm([1.0, 1.0, 0.3])
    return cv2.Rodrigues(axis * np.radians(degrees))[0]


def pixel_grid(width, height, step=1.0):
    u, v = np.meshgrid(np.arange(0, width, step), np.arange(0, height, step))
    return np.stack([u.ravel(), v.ravel()], axis=1)


def turned_view(camera, image, turn):
    """The image as the lens turned by `turn` sees it, and where that view has ground truth."""
    width, height = camera.image_size
    pixels = pixel_grid(width, height)
    source = camera.bearing_to_pixel(camera.pixel_to_bearing(pixels) @ turn)
    known = np.isfinite(source).all(axis=1) & camera.is_valid(pixels)
    known[known] = camera.is_valid(source[known])
    source[~known] = -1
    source = source.astype(np.float32).reshape(height, width, 2)
    return cv2.remap(image, source[..., 0], source[..., 1], cv2.INTER_LINEAR), known.reshape(height, width)


class Stereographic:
    """The camera's field of view in the stereographic projection, focal length zoom * the
    camera's tangent-plane scale (the fisheye image's resolution at its centre)."""

    def __init__(self, camera, zoom):
        self.camera, self.f = camera, camera.tangent_plane_scale * zoom
        width, height = camera.image_size
        seen = pixel_grid(width, height, 4.0)
        corners = self.from_bearing(camera.pixel_to_bearing(seen[camera.is_valid(seen)]))
        self.origin = np.floor(corners.min(axis=0)) - 2
        self.size = tuple(int(v) for v in np.ceil(corners.max(axis=0) - self.origin) + 3)
        source = camera.bearing_to_pixel(self.to_bearing(pixel_grid(*self.size)))
        valid = np.isfinite(source).all(axis=1)
        valid[valid] = camera.is_valid(source[valid])
        source[~valid] = -1
        self.map = source.astype(np.float32).reshape(self.size[1], self.size[0], 2)
        self.mask = cv2.erode(valid.reshape(self.size[1], self.size[0]).astype(np.uint8) * 255, np.ones((3, 3)))

    def from_bearing(self, b):
        theta = np.arccos(np.clip(b[:, 2], -1, 1))
        phi = np.arctan2(b[:, 1], b[:, 0])
        r = 2 * self.f * np.tan(theta / 2)
        return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1)

    def to_bearing(self, p):
        x, y = p[:, 0] + self.origin[0], p[:, 1] + self.origin[1]
        theta, phi = 2 * np.arctan(np.hypot(x, y) / (2 * self.f)), np.arctan2(y, x)
        return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=1)

    def detect(self, detector, image):
        keypoints = detector.detect(cv2.remap(image, self.map[..., 0], self.map[..., 1], cv2.INTER_LINEAR), self.mask)
        if not keypoints:
            return np.zeros((0, 2))
        back = self.camera.bearing_to_pixel(self.to_bearing(np.array([k.pt for k in keypoints])))
        return back[np.isfinite(back).all(axis=1)]


def repeatability(camera, points1, points2, turn, known2):
    """View-1 point p lies at view-2 pixel project(R b(p))."""
    truth = camera.bearing_to_pixel(camera.pixel_to_bearing(points1) @ turn.T)
    inside = np.isfinite(truth).all(axis=1)
    index = np.round(truth[inside]).astype(int)
    height, width = known2.shape
    on = (index[:, 0] >= 0) & (index[:, 0] < width) & (index[:, 1] >= 0) & (index[:, 1] < height)
    inside[inside] = on
    inside[inside] = known2[index[on, 1], index[on, 0]]
    truth = truth[inside]
    if len(truth) == 0 or len(points2) == 0:
        return 0.0
    nearest = np.linalg.norm(truth[:, None, :] - points2[None, :, :], axis=2).min(axis=1)
    return float((nearest < 3).mean())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--budget", type=int, default=500)
    parser.add_argument("--data", default=os.environ.get("MDBRIEF_DATA",
                                                         pathlib.Path(__file__).resolve().parents[3] / "shared/data"))
    args = parser.parse_args()
    fisheye = pathlib.Path(args.data) / "fisheye"
    print(f"Hessian repeatability (3 px), {args.budget} keypoints, lens turned by {TURNS} degrees (mean)")
    print("| photo | fisheye size | modORB | Hessian | Hessian on stereographic, zoom 1 (size) |"
          " Hessian on stereographic, fisheye's pixel count (zoom, size) |")
    print("|---|---|---|---|---|---|")
    for name, calibration, photo in PHOTOS:
        if not (fisheye / photo).exists():
            print(f"skipping {name}: {fisheye / photo} not found")
            continue
        camera = mdbrief.load_camera(str(fisheye / calibration))
        image = cv2.imread(str(fisheye / photo), cv2.IMREAD_GRAYSCALE)
        full = Stereographic(camera, 1.0)
        zoom = min(1.0, np.sqrt(camera.width * camera.height / (full.size[0] * full.size[1])))
        equal = Stereographic(camera, zoom)
        planar = mdbrief.MdBrief(None, detector="hessian", descriptor="brief", nfeatures=args.budget)
        runs = {
            "modORB": lambda img: np.array([k.pt for k in mdbrief.MdBrief(camera, nfeatures=args.budget).detect(img)]),
            "Hessian": lambda img: np.array([k.pt for k in mdbrief.MdBrief(camera, detector="hessian",
                                                                         nfeatures=args.budget).detect(img)]),
            "full": lambda img: full.detect(planar, img),
            "equal": lambda img: equal.detect(planar, img),
        }
        scores = {key: [] for key in runs}
        for degrees in TURNS:
            turn = rotation(degrees)
            other, known = turned_view(camera, image, turn)
            for key, run in runs.items():
                scores[key].append(repeatability(camera, run(image), run(other), turn, known))
        mean = {key: np.mean(v) for key, v in scores.items()}
        print(f"| {name} | {camera.width}x{camera.height} | {mean['modORB']:.3f} | {mean['Hessian']:.3f} | "
              f"{mean['full']:.3f} ({full.size[0]}x{full.size[1]}) | "
              f"{mean['equal']:.3f} ({zoom:.2f}, {equal.size[0]}x{equal.size[1]}) |")


if __name__ == "__main__":
    main()
