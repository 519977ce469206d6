"""mdbrief.refine_matches: on an image and a copy of it shifted by a known fraction of a pixel
(a pinhole camera), the refined points of the second image lie nearer the shift than its
keypoints; bad input is refused with an error naming the Python argument."""
import math

import cv2
import numpy as np
import pytest

import mdbrief
from conftest import PINHOLE_CAMERA

# Where image a's content lies in image b: b shows a's scene moved by this many pixels.
SHIFT = np.array([-1.25, 0.75])


def shifted_pair(size):
    """A smooth random texture at 4 times `size`, and two windows of it 5 and -3 fine pixels
    apart, each averaged down by INTER_AREA (the same box filter for both): b's pixel x shows what
    a's pixel x - SHIFT shows, exactly."""
    width, height = size
    rng = np.random.default_rng(11)
    noise = rng.random((height + 40, width + 40), dtype=np.float32)
    total = np.zeros_like(noise)
    for sigma in (1.5, 3.0, 6.0):
        blurred = cv2.GaussianBlur(noise, (0, 0), sigma)
        total += cv2.normalize(blurred, None, 0, 1, cv2.NORM_MINMAX)
    total = cv2.normalize(total, None, 0, 255, cv2.NORM_MINMAX)
    fine = cv2.resize(total, None, fx=4, fy=4, interpolation=cv2.INTER_CUBIC)

    def window(dx, dy):
        crop = fine[80 + dy:80 + dy + 4 * height, 80 + dx:80 + dx + 4 * width]
        return cv2.resize(crop, (width, height), interpolation=cv2.INTER_AREA).astype(np.uint8)

    return window(0, 0), window(5, -3)


@pytest.fixture(scope="module")
def pair():
    camera = mdbrief.load_camera(str(PINHOLE_CAMERA))
    a, b = shifted_pair(camera.image_size)
    features = mdbrief.MdBrief(camera)
    ka, da, ma = features.detect_and_compute(a)
    kb, db, mb = features.detect_and_compute(b)
    matches = mdbrief.match(da, db, ma, mb)
    return {"camera": camera, "features": features, "a": a, "b": b, "ka": ka, "kb": kb, "matches": matches}


def test_refinement_moves_the_second_images_points_onto_the_known_shift(pair):
    ka, kb, matches = pair["ka"], pair["kb"], pair["matches"]
    refined = mdbrief.refine_matches(pair["features"], pair["a"], ka, pair["b"], kb, matches)
    n = len(matches)
    assert len(refined) == n
    assert refined.points_b.shape == (n, 2) and refined.points_b.dtype == np.float64
    assert refined.bearings_b.shape == (n, 3) and refined.sigma_px.shape == (n,)
    assert refined.ok.dtype == bool and refined.levels.dtype == np.int32 and len(refined.reasons) == n
    points_a = np.array([ka[m.queryIdx].pt for m in matches])
    points_b = np.array([kb[m.trainIdx].pt for m in matches])
    octaves = np.array([kb[m.trainIdx].octave for m in matches])
    truth = points_a + SHIFT
    right = np.linalg.norm(points_b - truth, axis=1) < 3.0
    assert right.sum() > 200
    ok = refined.ok
    assert (ok & right).sum() > 0.9 * right.sum()
    kept = ok & right
    before = np.median(np.linalg.norm(points_b[kept] - truth[kept], axis=1))
    after = np.median(np.linalg.norm(refined.points_b[kept] - truth[kept], axis=1))
    assert after < 0.5 * before, (before, after)
    assert after < 0.05, (before, after)
    # Refined: a finite sigma, a level no coarser than the keypoint's, b's ray of the point.
    assert np.all(np.isfinite(refined.sigma_px[ok])) and np.all(refined.sigma_px[ok] > 0)
    assert np.all(refined.levels[ok] <= octaves[ok])
    rays = pair["camera"].pixel_to_bearing(refined.points_b[ok])
    np.testing.assert_allclose(refined.bearings_b[ok], rays / np.linalg.norm(rays, axis=1, keepdims=True), atol=1e-12)
    assert all(reason == "" for reason, good in zip(refined.reasons, ok) if good)
    # Failed: b's keypoint kept, no sigma, no level, a reason.
    failed = ~ok
    np.testing.assert_array_equal(refined.points_b[failed], points_b[failed])
    assert np.all(np.isinf(refined.sigma_px[failed])) and np.all(refined.levels[failed] == -1)
    assert all(reason != "" for reason, good in zip(refined.reasons, ok) if not good)
    assert repr(refined) == f"<mdbrief.RefinedMatches {ok.sum()} of {n} refined>"


def test_the_structured_matches_of_match_give_the_same_result(pair):
    features, a, b, ka, kb = pair["features"], pair["a"], pair["b"], pair["ka"], pair["kb"]
    listed = mdbrief.refine_matches(features, a, ka, b, kb, pair["matches"])
    rows = np.array([(m.queryIdx, m.trainIdx, m.distance) for m in pair["matches"]],
                    dtype=[("query_idx", "<i4"), ("train_idx", "<i4"), ("distance", "<f4")])
    arrayed = mdbrief.refine_matches(features, a, ka, b, kb, rows)
    np.testing.assert_array_equal(listed.points_b, arrayed.points_b)
    # A grey image and its BGR copy are the same pyramid; camera_b as the feature's camera.
    colour = mdbrief.refine_matches(features, a, ka, cv2.cvtColor(b, cv2.COLOR_GRAY2BGR), kb, pair["matches"],
                                    camera_b=pair["camera"])
    np.testing.assert_array_equal(listed.points_b, colour.points_b)


def test_options_are_keywords_of_the_option_table(pair):
    keywords = [f["keyword"] for f in mdbrief.option_fields("refine_matches")]
    assert keywords == ["patch_radius", "smoothing_sigma", "finer_levels", "max_iterations", "max_shift",
                        "min_eigenvalue", "max_sigma_px"]
    for keyword in keywords:
        assert f"{keyword}=" in mdbrief.refine_matches.__doc__
    args = (pair["features"], pair["a"], pair["ka"], pair["b"], pair["kb"], pair["matches"])
    with pytest.raises(ValueError, match=r"^patch_radius must be in \[2, 15\], got 1$"):
        mdbrief.refine_matches(*args, patch_radius=1)
    with pytest.raises(ValueError, match=r"^smoothing_sigma must be in \(0, 8\], got 9$"):
        mdbrief.refine_matches(*args, smoothing_sigma=9)
    with pytest.raises(TypeError, match="unexpected keyword argument 'radius'"):
        mdbrief.refine_matches(*args, radius=3)
    # A shift allowance below the true shift: every right match diverges.
    tight = mdbrief.refine_matches(*args, max_shift=0.05)
    assert "diverged" in tight.reasons
    # A bound on the standard deviation below every refined point's: each refined one fails.
    certain = mdbrief.refine_matches(*args, max_sigma_px=1e-6)
    assert not certain.ok.any()
    assert "uncertain: its standard deviation exceeds maxSigmaPx" in certain.reasons


def test_bad_input_names_the_python_argument(pair):
    features, a, b, ka, kb = pair["features"], pair["a"], pair["b"], pair["ka"], pair["kb"]
    one = [cv2.DMatch(0, 0, 0.0)]
    with pytest.raises(ValueError, match=rf"^refine_matches: matches\[1\]\.trainIdx = {len(kb)} is no index of "
                                         rf"keypoints_b \({len(kb)} keypoints\)$"):
        mdbrief.refine_matches(features, a, ka, b, kb, [cv2.DMatch(0, 0, 0.0), cv2.DMatch(1, len(kb), 0.0)])
    with pytest.raises(ValueError, match=r"matches\[0\]\.queryIdx = -1 is no index of keypoints_a"):
        mdbrief.refine_matches(features, a, ka, b, kb, [cv2.DMatch(-1, 0, 0.0)])
    with pytest.raises(ValueError, match=r"matches\[0\]\.train_idx = 4294967296 is outside the range of a C int"):
        mdbrief.refine_matches(features, a, ka, b, kb,
                               np.array([(0, 2**32)], dtype=[("query_idx", "<i8"), ("train_idx", "<i8")]))
    far = [cv2.KeyPoint(100.0, 100.0, 31.0, -1.0, 0.0, 40)]
    with pytest.raises(ValueError, match=r"^refine_matches: keypoints_a\[0\]\.octave 40 is no level of its pyramid"):
        mdbrief.refine_matches(features, a, far, b, kb, one)
    nan = [cv2.KeyPoint(math.nan, 100.0, 31.0)]
    with pytest.raises(ValueError, match=r"^refine_matches: keypoints_b\[0\] has a position or size that is not finite"):
        mdbrief.refine_matches(features, a, ka, b, nan, one)
    with pytest.raises(ValueError, match=r"^refine_matches: image_b is 377x240 but camera_b's image size is 754x480"):
        mdbrief.refine_matches(features, a, ka, cv2.resize(b, (377, 240)), kb, one)
    with pytest.raises(ValueError, match=r"^image_a must have dtype uint8"):
        mdbrief.refine_matches(features, a.astype(np.float32), ka, b, kb, one)
    with pytest.raises(ValueError, match=r"^image_b must have shape \(H, W\)"):
        mdbrief.refine_matches(features, a, ka, b[0], kb, one)
    with pytest.raises(ValueError, match=r"^matches must be a sequence of cv2\.DMatch or a 1-D structured array"):
        mdbrief.refine_matches(features, a, ka, b, kb, np.zeros((3, 2), np.int32))
    with pytest.raises(TypeError, match=r"^matches\[0\] is not a cv2\.DMatch"):
        mdbrief.refine_matches(features, a, ka, b, kb, [(0, 0)])
    with pytest.raises(TypeError, match=r"^keypoints_a must be a sequence of cv2\.KeyPoint"):
        mdbrief.refine_matches(features, a, 3, b, kb, one)


def test_uninitialised_objects_and_a_feature_without_camera_are_refused(pair):
    a, b, ka, kb, camera = pair["a"], pair["b"], pair["ka"], pair["kb"], pair["camera"]
    one = [cv2.DMatch(0, 0, 0.0)]
    with pytest.raises(TypeError, match=r"this mdbrief\.MdBrief object was never initialised"):
        mdbrief.refine_matches(mdbrief.MdBrief.__new__(mdbrief.MdBrief), a, ka, b, kb, one)
    with pytest.raises(TypeError, match=r"this mdbrief\.Camera object was never initialised"):
        mdbrief.refine_matches(pair["features"], a, ka, b, kb, one, camera_b=mdbrief.Camera.__new__(mdbrief.Camera))
    with pytest.raises(TypeError, match=r"this mdbrief\.RefinedMatches object was never initialised"):
        mdbrief.RefinedMatches.__new__(mdbrief.RefinedMatches).points_b
    plain = mdbrief.MdBrief(None, descriptor="brief")
    with pytest.raises(ValueError, match=r"^refine_matches: feature has no camera .*pass camera_a="):
        mdbrief.refine_matches(plain, a, ka, b, kb, one)
    assert len(mdbrief.refine_matches(plain, a, ka, b, kb, one, camera_a=camera)) == 1
