#!/usr/bin/python3
"""A check of a stereo set's stated pose by the matches themselves (docs/RESULTS.md "Real stereo:
poses against the known pose"): the pose correction, a small turn and a change of the translation's
direction, that best fits the right matches of reference pipelines (OpenCV's by default, so none
of the library's), and for every pipeline its residual under the stated and the corrected pose,
and how far its own fit lies from each.

The input is the folder of `mdbrief-eval tracker --datasets stereo --stereo-matches --out DIR`:
stereo_matches.csv (the right matches at ratio 0.8) and stereo_poses.csv. Every pair of a set
takes the same correction, as a rig's calibration error would be. Each fit minimises the Huber
loss (0.3 px) of the matches' distances from their epipolar planes, in b's pixels, by iteratively
reweighted Gauss-Newton.

Usage: /usr/bin/python3 scripts/stereo_pose_check.py DIR [--set mynteye-fisheye]
       [--reference SIFT AKAZE BRISK ORB]
"""
import argparse
import csv
import pathlib
import sys

import numpy as np

HUBER_PX = 0.3


def rotation(vector):
    """Rodrigues' formula."""
    angle = np.linalg.norm(vector)
    if angle < 1e-15:
        return np.eye(3)
    k = vector / angle
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross


def skew(t):
    return np.array([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])


class Matches:
    """Right matches of one pipeline: bearings a, b (n x 3), b's pixels per radian, and the index
    of each match's stated pose."""

    def __init__(self):
        self.a, self.b, self.scale, self.residual, self.pose = [], [], [], [], []

    def freeze(self):
        for name in ("a", "b", "scale", "residual", "pose"):
            setattr(self, name, np.asarray(getattr(self, name)))
        return self


def corrected(poses, x):
    """Every pose turned by x[:3] (radians) in a's frame, its translation's direction moved by
    x[3:5] along two axes across it (X_a = R X_b + t)."""
    turn = rotation(x[:3])
    out = []
    for r, t in poses:
        direction = t / np.linalg.norm(t)
        across = np.cross(direction, [0.0, 0.0, 1.0] if abs(direction[2]) < 0.9 else [1.0, 0.0, 0.0])
        across /= np.linalg.norm(across)
        other = np.cross(direction, across)
        moved = direction + x[3] * across + x[4] * other
        out.append((turn @ r, turn @ (moved / np.linalg.norm(moved) * np.linalg.norm(t))))
    return out


def residuals(m, poses):
    """Signed distances of b from the epipolar planes of a, in b's pixels (the benchmark's)."""
    out = np.empty(len(m.scale))
    for index, (r, t) in enumerate(poses):
        chosen = m.pose == index
        normal = m.a[chosen] @ (skew(t) @ r)  # rows: (E^T a)^T
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        out[chosen] = np.arcsin(np.clip(np.sum(m.b[chosen] * normal, axis=1), -1, 1)) * m.scale[chosen]
    return out


def fit(m, poses):
    """The correction minimising the Huber loss of m's residuals."""
    x = np.zeros(5)
    for _ in range(30):
        r = residuals(m, corrected(poses, x))
        weights = np.minimum(1.0, HUBER_PX / np.maximum(np.abs(r), 1e-12))
        jacobian = np.empty((len(r), 5))
        for k in range(5):
            step = np.zeros(5)
            step[k] = 1e-7
            jacobian[:, k] = (residuals(m, corrected(poses, x + step)) - r) / 1e-7
        weighted = jacobian * weights[:, None]
        delta = np.linalg.solve(weighted.T @ jacobian, -weighted.T @ r)
        x += delta
        if np.max(np.abs(delta)) < 1e-10:
            break
    return x


def angle_deg(pose_a, pose_b):
    """max(rotation, translation direction) between two poses, degrees (the benchmark's)."""
    (ra, ta), (rb, tb) = pose_a, pose_b
    turn = np.degrees(np.arccos(np.clip((np.trace(ra @ rb.T) - 1) / 2, -1, 1)))
    cosine = ta @ tb / (np.linalg.norm(ta) * np.linalg.norm(tb))
    return max(turn, np.degrees(np.arccos(np.clip(cosine, -1, 1))))


def rows_of(path, set_name):
    """The rows of one set in a CSV file, with the line each starts on; ValueError naming the file
    when it has no header."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        if not reader.fieldnames:
            raise ValueError(f"{path}: empty, no header")
        for row in reader:
            if row.get("set") == set_name:
                yield reader.line_num, row


def read(folder, set_name):
    """One set's known poses, and its right matches by pipeline. ValueError naming the file and line
    of a missing column, a number that is not one or not finite, or a match of a pair without a pose."""
    def numbers(path, line, row, names):
        try:
            values = [float(row[name]) for name in names]
        except (KeyError, TypeError, ValueError):
            raise ValueError(f"{path}:{line}: {', '.join(names)} must be numbers") from None
        if not all(np.isfinite(values)):
            raise ValueError(f"{path}:{line}: {', '.join(names)} must be finite")
        return values

    poses, pose_index = [], {}
    path = folder / "stereo_poses.csv"
    for line, row in rows_of(path, set_name):
        values = numbers(path, line, row, [f"r{i}{j}" for i in range(3) for j in range(3)] + ["t_x", "t_y", "t_z"])
        pose_index[(row.get("image_a"), row.get("image_b"))] = len(poses)
        poses.append((np.array(values[:9]).reshape(3, 3), np.array(values[9:])))
    by_pipeline = {}
    path = folder / "stereo_matches.csv"
    for line, row in rows_of(path, set_name):
        pair = (row.get("image_a"), row.get("image_b"))
        if pair not in pose_index:
            raise ValueError(f"{path}:{line}: pair {pair[0]}, {pair[1]} has no pose in stereo_poses.csv")
        values = numbers(path, line, row, ["a_x", "a_y", "a_z", "b_x", "b_y", "b_z", "b_px_per_radian", "residual_px"])
        m = by_pipeline.setdefault(row.get("pipeline"), Matches())
        m.a.append(values[0:3])
        m.b.append(values[3:6])
        m.scale.append(values[6])
        m.residual.append(values[7])
        m.pose.append(pose_index[pair])
    return poses, {name: m.freeze() for name, m in by_pipeline.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=pathlib.Path)
    parser.add_argument("--set", default="mynteye-fisheye")
    parser.add_argument("--reference", nargs="+", default=["SIFT", "AKAZE", "BRISK", "ORB"],
                        help="pipelines whose right matches the correction is fitted to")
    args = parser.parse_args()
    for name in ("stereo_matches.csv", "stereo_poses.csv"):
        if not (args.folder / name).is_file():
            print(f"stereo_pose_check.py: no {args.folder / name}; run mdbrief-eval tracker --datasets stereo "
                  "--stereo-matches --out DIR", file=sys.stderr)
            return 2
    try:
        poses, by_pipeline = read(args.folder, args.set)
    except ValueError as e:
        print(f"stereo_pose_check.py: {e}", file=sys.stderr)
        return 2
    if not poses:
        print(f"stereo_pose_check.py: set {args.set} is not in {args.folder / 'stereo_poses.csv'}", file=sys.stderr)
        return 2
    missing = [name for name in args.reference if name not in by_pipeline]
    if missing:
        print(f"stereo_pose_check.py: no right matches of {', '.join(missing)} in set {args.set}", file=sys.stderr)
        return 2
    # The benchmark's residuals, recomputed: the same planes.
    worst = max(np.max(np.abs(np.abs(residuals(m, poses)) - np.abs(m.residual))) for m in by_pipeline.values())
    if worst > 1e-4:
        print(f"stereo_pose_check.py: residuals differ from the benchmark's by {worst:.2g} px", file=sys.stderr)
        return 1
    reference = Matches()
    for name in args.reference:
        m = by_pipeline[name]
        for field in ("a", "b", "scale", "residual", "pose"):
            getattr(reference, field).extend(getattr(m, field))
    correction = fit(reference.freeze(), poses)
    better = corrected(poses, correction)
    turn_mrad = np.linalg.norm(correction[:3]) * 1e3
    moved_deg = np.degrees(max(np.arccos(np.clip(a[1] @ b[1] / (np.linalg.norm(a[1]) * np.linalg.norm(b[1])), -1, 1))
                               for a, b in zip(poses, better)))
    print(f"{args.set}: correction fitted to {', '.join(args.reference)} ({len(reference.scale)} right matches): "
          f"turn {turn_mrad:.2f} mrad, translation's direction {moved_deg:.3f} deg")
    print(f"  {'pipeline':40s} {'right':>6s}  {'stated: median / p90 / side':>28s}  "
          f"{'corrected: median / p90 / side':>31s}  {'own fit to stated / corrected':>29s}")
    for name, m in sorted(by_pipeline.items()):
        stated, fixed = residuals(m, poses), residuals(m, better)
        own = corrected(poses, fit(m, poses))
        print(f"  {name:40s} {len(m.scale):6d}  {np.median(np.abs(stated)):8.4f} / {np.percentile(np.abs(stated), 90):.4f}"
              f" / {stated.mean():+.4f}  {np.median(np.abs(fixed)):11.4f} / {np.percentile(np.abs(fixed), 90):.4f}"
              f" / {fixed.mean():+.4f}  {angle_deg(own[0], poses[0]):15.3f} / {angle_deg(own[0], better[0]):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
