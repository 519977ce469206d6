"""mdbrief.fit_essential, fit_homography, check_known_pose (libmdbrief/include/mdbrief/geometry/
two_view.hpp) from Python: bearings of a scene seen by the fisheye fixture from two known poses,
with outliers; the results' types; and every bad input."""
import cv2
import numpy as np
import pytest

import mdbrief

R = cv2.Rodrigues(np.array([0.05, 0.3, -0.04]))[0]  # camera b in camera a's frame: X_a = R X_b + t
T = np.array([0.5, -0.1, 0.15])


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def scene_matches(camera, points, outliers=0, seed=3):
    """Matches of 3D points (camera a's frame) seen by the camera from both poses, through its
    pixels; then `outliers` random pixel pairs. Returns a, b, pixels per radian at b, right."""
    rng = np.random.default_rng(seed)
    pa = camera.bearing_to_pixel(unit(points))
    pb = camera.bearing_to_pixel(unit((points - T) @ R))  # rows: R^T (X - t)
    keep = ~np.isnan(pa).any(axis=1) & ~np.isnan(pb).any(axis=1)
    pa, pb = pa[keep], pb[keep]
    keep = camera.is_valid(pa) & camera.is_valid(pb)
    pa, pb = pa[keep], pb[keep]
    right = np.ones(len(pa), dtype=bool)
    if outliers:
        size = np.array(camera.image_size, dtype=np.float64)
        qa, qb = rng.uniform(0, 1, (4 * outliers, 2)) * size, rng.uniform(0, 1, (4 * outliers, 2)) * size
        valid = camera.is_valid(qa) & camera.is_valid(qb)
        qa, qb = qa[valid][:outliers], qb[valid][:outliers]
        pa, pb = np.vstack([pa, qa]), np.vstack([pb, qb])
        right = np.concatenate([right, np.zeros(len(qa), dtype=bool)])
    return camera.pixel_to_bearing(pa), camera.pixel_to_bearing(pb), mdbrief.pixels_per_radian(camera, pb), right


def general_scene(n, seed=7):
    rng = np.random.default_rng(seed)
    directions = unit(rng.normal(size=(n, 3)) + [0, 0, 1.2])
    return directions * rng.uniform(2, 8, (n, 1))


def plane_scene(n, seed=8):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-2, 2, n), rng.uniform(-2, 2, n), np.full(n, 3.0)])


def rotation_angle(r):
    return np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1))


def test_fit_essential_recovers_the_pose_among_outliers(camera):
    a, b, scale, right = scene_matches(camera, general_scene(300), outliers=90)
    assert right.sum() > 150
    fit = mdbrief.fit_essential(a, b, pixels_per_radian=scale)
    assert isinstance(fit, mdbrief.TwoViewResult)
    assert fit.ok and fit.reason == "" and fit.kind == "essential"
    assert fit.inliers.dtype == np.bool_ and fit.inliers.shape == (len(a),)
    assert fit.residuals.dtype == np.float64 and fit.residuals.shape == (len(a),)
    assert fit.inlier_count == fit.inliers.sum()
    assert fit.inliers[right].mean() > 0.98
    assert fit.inliers[~right].mean() < 0.1
    assert np.degrees(rotation_angle(fit.rotation.T @ R)) < 0.5
    assert np.degrees(np.arccos(np.clip(fit.translation @ unit(T), -1, 1))) < 3
    assert fit.model.shape == (3, 3)
    # a . E b = 0 on the inliers.
    assert np.abs(np.einsum("ij,ij->i", unit(a[fit.inliers]), unit(b[fit.inliers]) @ fit.model.T)).max() < 0.02
    again = mdbrief.fit_essential(a, b, pixels_per_radian=scale)
    assert np.array_equal(again.inliers, fit.inliers) and np.array_equal(again.model, fit.model)
    assert "inliers" in repr(fit)


def test_fit_homography_on_a_plane(camera):
    a, b, scale, right = scene_matches(camera, plane_scene(200), outliers=60)
    fit = mdbrief.fit_homography(a, b, pixels_per_radian=scale)
    assert fit.ok and fit.kind == "homography"
    assert fit.inliers[right].mean() > 0.97
    assert fit.inliers[~right].sum() <= 3
    assert fit.rotation is None and fit.translation is None
    mapped, ub = unit(a @ fit.model.T), unit(b)
    angles = np.arctan2(np.linalg.norm(np.cross(mapped, ub), axis=1), np.einsum("ij,ij->i", mapped, ub))
    assert np.allclose(angles, fit.residuals, atol=1e-9)


def test_check_known_pose_labels_the_matches(camera):
    a, b, scale, right = scene_matches(camera, general_scene(200), outliers=60)
    check = mdbrief.check_known_pose(a, b, R, T * 0.1, pixels_per_radian=scale)
    assert check.ok and check.kind == "known pose" and check.model is None
    assert np.allclose(check.rotation, R) and np.allclose(check.translation, T * 0.1)
    assert check.inliers[right].mean() > 0.98
    assert check.inliers[~right].mean() < 0.1
    # An angular threshold, no pixels per radian.
    assert mdbrief.check_known_pose(a, b, R, T, max_angle=0.01).inliers[right].mean() > 0.98


def test_failures_are_results_with_a_reason(camera):
    a = unit(np.array([[0, 0, 1], [0.1, 0, 1], [0, 0.1, 1], [0.2, 0.3, 1]], dtype=float))
    fit = mdbrief.fit_essential(a, a)
    assert not fit.ok
    assert fit.reason == "too few matches (4 matches, 5 needed)"
    assert not fit.inliers.any() and fit.inliers.shape == (4,)
    assert fit.residuals.shape == (0,)
    assert fit.model is None and fit.rotation is None
    same = np.tile([0.3, -0.2, 1.0], (20, 1))
    assert mdbrief.fit_homography(same, same).reason == "all matches on the same point (of 20)"
    line = np.array([[-3 + 0.4 * i, 1 + 0.1 * i, 2 + 0.3 * i] for i in range(30)])
    assert mdbrief.fit_essential(unit(line), unit((line - T) @ R)).reason == "all matches on a line (of 30)"
    assert "too few matches" in repr(fit)


@pytest.mark.parametrize("bad, message", [
    (np.zeros((6, 2)), r"bearings_a must have shape \(N, 3\)"),
    (np.array([0.0, 0.0, 1.0]), r"bearings_a must have shape \(N, 3\), got \(3,\)"),
    (np.array([[0, 0, 1.0]] * 5 + [[np.nan, 0, 1]]), r"bearings_a\[5\] must be finite and non-zero"),
    (np.array([[0, 0, 1.0]] * 5 + [[0, 0, 0]]), r"bearings_a\[5\] must be finite and non-zero"),
])
def test_bad_bearings_raise_value_error(bad, message):
    good = unit(np.random.default_rng(1).normal(size=(len(bad) if bad.ndim == 2 else 6, 3)))
    with pytest.raises(ValueError, match=message):
        mdbrief.fit_essential(bad, good)


def test_bad_arguments():
    a = unit(np.random.default_rng(2).normal(size=(8, 3)))
    with pytest.raises(TypeError, match="bearings_b must be an array of numbers"):
        mdbrief.fit_homography(a, [["x", "y", "z"]] * 8)
    with pytest.raises(ValueError, match="bearings_a has 8 rows and bearings_b 7"):
        mdbrief.fit_essential(a, a[:7])
    with pytest.raises(ValueError, match=r"pixels_per_radian must have shape \(8,\)"):
        mdbrief.fit_essential(a, a, pixels_per_radian=[300.0] * 3)
    with pytest.raises(ValueError, match=r"pixels_per_radian\[1\] must be positive"):
        mdbrief.fit_essential(a, a, pixels_per_radian=[300.0, -1] + [300.0] * 6)
    with pytest.raises(ValueError, match=r"max_angle must be in \(0, 0.5\], got 0"):
        mdbrief.fit_essential(a, a, max_angle=0)
    with pytest.raises(ValueError, match=r"confidence must be in \(0, 1\)"):
        mdbrief.fit_homography(a, a, confidence=1.5)
    with pytest.raises(TypeError, match="unexpected keyword argument 'threshold'"):
        mdbrief.fit_essential(a, a, threshold=2)
    with pytest.raises(ValueError, match=r"rotation must have shape \(3, 3\)"):
        mdbrief.check_known_pose(a, a, np.eye(2), T)
    with pytest.raises(ValueError, match="^check_known_pose: rotation is not a rotation"):
        mdbrief.check_known_pose(a, a, 2 * np.eye(3), T)
    with pytest.raises(ValueError, match="translation must be finite and non-zero"):
        mdbrief.check_known_pose(a, a, np.eye(3), np.zeros(3))


def test_options_table_and_pixels_per_radian(camera):
    fields = {f["keyword"]: f for f in mdbrief.option_fields("two_view")}
    assert list(fields) == ["max_angle", "max_pixels", "confidence", "max_iterations", "seed", "refine", "in_front",
                           "max_false_alarms"]
    assert fields["max_angle"]["default"] == 0.005 and fields["max_pixels"]["default"] == 2.0
    width, height = camera.image_size
    scale = mdbrief.pixels_per_radian(camera, [[width / 2, height / 2], [-1e6, -1e6]])
    assert scale.shape == (2,) and scale[0] > 0 and np.isnan(scale[1])


def test_ctrl_c_stops_a_long_fit_at_once():
    """Issue 45: Ctrl-C during fit_essential on 300,000 bearings was honoured after 92 s."""
    import os
    import signal
    import subprocess
    import sys
    import time
    code = ("import numpy as np, mdbrief, sys\n"
            "rng = np.random.default_rng(1)\n"
            "a, b = rng.normal(size=(300000, 3)), rng.normal(size=(300000, 3))\n"
            "print('fitting', flush=True)\n"
            "try:\n"
            "    mdbrief.fit_essential(a, b, max_iterations=100000)\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted', flush=True)\n"
            "    sys.exit(3)\n")
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, env=os.environ.copy())
    assert child.stdout.readline().strip() == "fitting"
    time.sleep(1.0)  # inside RANSAC by now
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    try:
        out, _ = child.communicate(timeout=20)
    finally:
        child.kill()
    assert child.returncode == 3 and "interrupted" in out
    assert time.monotonic() - sent < 5
