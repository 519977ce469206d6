"""mdbrief.MdBrief and mdbrief.match: the same bytes as the C++ tool, cv2 interop, options, threads."""
import os
import subprocess
import sys
import threading

import cv2
import numpy as np
import pytest

import mdbrief
from conftest import FISHEYE_CAMERA, SOURCE


def read_feature_file(path):
    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    keypoints = [cv2.KeyPoint(*row) for row in _keypoint_rows(storage.getNode("keypoints"))]
    return keypoints, storage.getNode("descriptors").mat(), storage.getNode("masks").mat()


def _keypoint_rows(node):
    rows = []
    for i in range(node.size()):
        item = node.at(i)
        values = [item.at(j).real() for j in range(item.size())]
        rows.append((values[0], values[1], values[2], values[3], values[4], int(values[5]), int(values[6])))
    return rows


def same_keypoints(a, b):
    assert len(a) == len(b)
    for p, q in zip(a, b):
        assert p.pt == pytest.approx(q.pt, abs=1e-3)
        assert p.size == pytest.approx(q.size, rel=1e-5)
        assert p.angle == pytest.approx(q.angle, abs=1e-3)
        assert p.octave == q.octave


@pytest.mark.parametrize("detector", ["modorb", "hessian"])
def test_detect_and_compute_gives_the_bytes_of_the_cpp_tool(tmp_path, camera, image_pair, cli, detector):
    image = image_pair[0]
    cv2.imwrite(str(tmp_path / "view.png"), image)
    subprocess.run([cli, "extract", "--camera", str(FISHEYE_CAMERA), "--nfeatures", "500", "--detector",
                    detector, str(tmp_path / "view.png"), "-o", str(tmp_path / "cpp.yml")], check=True,
                   capture_output=True)
    cpp_keypoints, cpp_descriptors, cpp_masks = read_feature_file(tmp_path / "cpp.yml")

    # The tool reads images as grey (cv::IMREAD_GRAYSCALE): give Python the same pixels.
    grey = cv2.imread(str(tmp_path / "view.png"), cv2.IMREAD_GRAYSCALE)
    keypoints, descriptors, masks = mdbrief.MdBrief(camera, nfeatures=500, detector=detector).detect_and_compute(grey)
    same_keypoints(keypoints, cpp_keypoints)
    assert descriptors.dtype == np.uint8 and descriptors.shape == (len(keypoints), 32)
    assert np.array_equal(descriptors, cpp_descriptors)
    assert np.array_equal(masks, cpp_masks)


def test_compute_on_given_keypoints_gives_the_bytes_of_the_cpp_tool(tmp_path, camera, image_pair, cli):
    image = image_pair[0]
    cv2.imwrite(str(tmp_path / "view.png"), image)
    given = cv2.ORB_create(300).detect(image)
    # The tool's keypoint node is cv::write's list of 7-tuples.
    rows = ", ".join("[ " + ", ".join(repr(float(v)) if j < 5 else str(int(v)) for j, v in enumerate(
        (k.pt[0], k.pt[1], k.size, k.angle, k.response, k.octave, k.class_id))) + " ]" for k in given)
    (tmp_path / "orb.yml").write_text(f"%YAML:1.0\n---\nkeypoints: [ {rows} ]\n")
    subprocess.run([cli, "extract", "--camera", str(FISHEYE_CAMERA), "--keypoints", str(tmp_path / "orb.yml"),
                    str(tmp_path / "view.png"), "-o", str(tmp_path / "cpp.yml")], check=True, capture_output=True)
    cpp_keypoints, cpp_descriptors, cpp_masks = read_feature_file(tmp_path / "cpp.yml")

    grey = cv2.imread(str(tmp_path / "view.png"), cv2.IMREAD_GRAYSCALE)
    keypoints, descriptors, masks = mdbrief.MdBrief(camera).compute(grey, given)
    assert 0 < len(keypoints) < len(given)  # those near the rim cannot be described
    same_keypoints(keypoints, cpp_keypoints)
    assert np.array_equal(descriptors, cpp_descriptors)
    assert np.array_equal(masks, cpp_masks)


def test_grey_and_bgr_images_give_the_same_features(camera, image_pair):
    features = mdbrief.MdBrief(camera, nfeatures=300)
    k1, d1, m1 = features.detect_and_compute(image_pair[0])
    k2, d2, m2 = features.detect_and_compute(cv2.cvtColor(image_pair[0], cv2.COLOR_BGR2GRAY))
    same_keypoints(k1, k2)
    assert np.array_equal(d1, d2) and np.array_equal(m1, m2)
    # A non-contiguous view is the same image too.
    k3, d3, _ = features.detect_and_compute(np.asfortranarray(cv2.cvtColor(image_pair[0], cv2.COLOR_BGR2GRAY)))
    assert np.array_equal(d1, d3)


def test_mask_restricts_detection_and_descriptor_kinds_shape_outputs(camera, image_pair):
    image = image_pair[0]
    mask = np.zeros(image.shape[:2], np.uint8)
    mask[:, : image.shape[1] // 2] = 255
    keypoints = mdbrief.MdBrief(camera, nfeatures=300).detect(image, mask)
    assert keypoints and all(k.pt[0] < image.shape[1] // 2 for k in keypoints)

    for kind, masked in [("brief", False), ("dbrief", False), ("mdbrief", True), ("mbrief", True)]:
        kp, d, m = mdbrief.MdBrief(camera, descriptor=kind, bits=128, nfeatures=200).detect_and_compute(image)
        assert d.shape == (len(kp), 16)
        assert (m is not None) == masked
        if masked:
            assert m.shape == d.shape
    # BRIEF needs no camera; then any image size works.
    kp, d, _ = mdbrief.MdBrief(None, descriptor="brief").detect_and_compute(image[:300, :400])
    assert d.shape == (len(kp), 32) and kp


def test_options_are_keywords_with_the_library_defaults(camera):
    defaults = mdbrief.MdBrief(camera).options
    assert defaults["nfeatures"] == 1000 and defaults["bits"] == 256 and defaults["descriptor"] == "mdbrief"
    # Every keyword shown in the docstring is accepted back with its default value.
    assert mdbrief.MdBrief(camera, **defaults).options == defaults
    changed = mdbrief.MdBrief(camera, detector="hessian", levels=6, scale_factor=1.25, bits=128,
                              orientation="keypoint", spread=True, support_scale=2.5).options
    assert changed["method"] == "hessian" and changed["levels"] == 6 and changed["scale_factor"] == 1.25
    assert changed["bits"] == 128 and changed["orientation"] == "keypoint" and changed["spread"] is True
    assert changed["support_scale"] == 2.5
    for name in defaults:
        assert f"{name}=" in mdbrief.MdBrief.__init__.__doc__


@pytest.mark.parametrize("options, error, text", [
    (dict(nfeatures=0), ValueError, "nfeatures"),
    (dict(bits=100), ValueError, "bits"),
    (dict(scale_factor=1.0), ValueError, "scale_factor"),
    (dict(orientation_radius=40), ValueError, "orientation_radius"),
    (dict(detector_orientation_radius=0), ValueError, "detector_orientation_radius"),
    (dict(detector="sift"), ValueError, "detector must be one of: modorb, hessian, got 'sift'"),
    (dict(pattern="no_such_set"), ValueError, "no_such_set"),
    (dict(nfeatures=2.5), TypeError, "nfeatures must be an int"),
    (dict(spread=1), TypeError, "spread must be True or False"),
    (dict(levels=2**40), ValueError, r"levels must be in \[3, 32\], got 1099511627776"),  # Hessian: 3 at least
    (dict(colour=True), TypeError, "unexpected keyword argument 'colour'"),
])
def test_bad_options_raise_naming_the_keyword(camera, options, error, text):
    with pytest.raises(error, match=text):
        mdbrief.MdBrief(camera, **options)


def test_bad_images_and_keypoints_raise_instead_of_crashing(camera, image_pair):
    features = mdbrief.MdBrief(camera)
    image = image_pair[0]
    cases = [
        (lambda: features.detect(image.astype(np.float32)), ValueError, "dtype uint8"),
        (lambda: features.detect(image[:100]), ValueError, "differs from the camera's 754x480"),
        (lambda: features.detect(np.zeros((0, 0), np.uint8)), ValueError, "empty"),
        (lambda: features.detect(np.zeros((480, 754, 2), np.uint8)), ValueError, r"\(H, W, 3\)"),
        (lambda: features.detect([[1, 2]]), TypeError, "numpy array"),
        (lambda: features.detect(image, np.zeros((10, 10), np.uint8)), ValueError, "mask"),
        (lambda: features.compute(image, [1, 2]), TypeError, r"keypoints\[0\] is not a cv2.KeyPoint"),
        (lambda: features.compute(image, "abc"), TypeError, "sequence of cv2.KeyPoint"),
        (lambda: mdbrief.MdBrief(None), ValueError, "need a camera"),
    ]
    for call, error, text in cases:
        with pytest.raises(error, match=text):
            call()
    # Keypoints no detector would give are dropped, never read out of bounds.
    odd = [cv2.KeyPoint(377, 240, 31), cv2.KeyPoint(-50, 9999, 31), cv2.KeyPoint(377, 240, float("nan")),
           cv2.KeyPoint(377, 240, 0), cv2.KeyPoint(377, 240, 31, 0, 0, 99)]
    keypoints, descriptors, _ = features.compute(image, odd)
    assert len(keypoints) == descriptors.shape[0] == 2


def test_matches_are_cv2_dmatch_and_agree_with_bfmatcher(camera, image_pair):
    features = mdbrief.MdBrief(camera, nfeatures=500)
    k1, d1, m1 = features.detect_and_compute(image_pair[0])
    k2, d2, m2 = features.detect_and_compute(image_pair[1])
    # Every query's nearest neighbour, as cv2.BFMatcher gives it: no ratio test, no mutual check.
    plain = mdbrief.match(d1, d2, ratio=None, cross_check=False)
    reference = cv2.BFMatcher(features.default_norm).match(d1, d2)
    assert len(plain) == len(reference) == len(k1)
    assert all(isinstance(m, cv2.DMatch) for m in plain)
    assert [m.distance for m in plain] == [r.distance for r in reference]
    # cv2 drawing takes the objects unchanged.
    canvas = cv2.drawMatches(image_pair[0], k1, image_pair[1], k2, plain[:20], None)
    assert canvas.shape[1] == 2 * image_pair[0].shape[1]
    assert cv2.drawKeypoints(image_pair[0], k1, None).shape == image_pair[0].shape

    masked = mdbrief.match(d1, d2, m1, m2, ratio=None, cross_check=False)
    assert len(masked) == len(k1) and [m.queryIdx for m in masked] == list(range(len(k1)))
    ratio = mdbrief.match(d1, d2, m1, m2, ratio=0.8, cross_check=False)
    checked = mdbrief.match(d1, d2, m1, m2, ratio=None)
    close = mdbrief.match(d1, d2, m1, m2, max_distance=40)
    assert 0 < len(ratio) < len(masked) and 0 < len(checked) < len(masked)
    assert all(m.distance <= 40 for m in close)
    # The defaults (preset 'tracking'): the ratio test and the mutual check, as MatchOptions{}.
    default = mdbrief.match(d1, d2, m1, m2)
    both = [m for m in mdbrief.match(d1, d2, m1, m2, ratio=0.55, cross_check=False)
            if (m.queryIdx, m.trainIdx) in {(c.queryIdx, c.trainIdx) for c in checked}]
    assert [(m.queryIdx, m.trainIdx) for m in default] == [(m.queryIdx, m.trainIdx) for m in both]
    assert len(mdbrief.match(d1, d2, m1, m2, preset="paper")) == len(masked)
    with pytest.raises(ValueError, match="preset 'fast' is not one of: tracking, matching, paper"):
        mdbrief.match(d1, d2, m1, m2, preset="fast")
    table = mdbrief.match(d1, d2, m1, m2, ratio=0.8, cross_check=False, as_array=True)
    assert table.dtype.names == ("query_idx", "train_idx", "distance") and len(table) == len(ratio)
    assert [tuple(row) for row in table.tolist()] == [(m.queryIdx, m.trainIdx, m.distance) for m in ratio]
    serial = mdbrief.match(d1, d2, m1, m2, ratio=0.8, cross_check=False, parallel=False)
    assert [(m.queryIdx, m.trainIdx, m.distance) for m in serial] == [(m.queryIdx, m.trainIdx, m.distance)
                                                                      for m in ratio]


def test_bad_match_arguments_raise(camera):
    d = np.zeros((5, 32), np.uint8)
    with pytest.raises(ValueError, match="both"):
        mdbrief.match(d, d, masks1=d)
    with pytest.raises(ValueError, match="differs"):
        mdbrief.match(d, d[:, :8])
    with pytest.raises(ValueError, match="ratio"):
        mdbrief.match(d, d, ratio=1.5)
    with pytest.raises(ValueError, match="dtype uint8"):
        mdbrief.match(d.astype(np.int32), d)
    assert mdbrief.match(np.zeros((0, 32), np.uint8), d) == []


def test_threads_give_the_serial_results(camera, image_pair):
    features = mdbrief.MdBrief(camera, nfeatures=500)
    serial = [features.detect_and_compute(image)[1] for image in image_pair]
    results = [None, None]

    def work(i):
        for _ in range(3):
            results[i] = features.detect_and_compute(image_pair[i])[1]

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(a, b) for a, b in zip(serial, results))


def test_the_example_matches_a_turned_view_and_draws_the_matches(tmp_path, camera, image_pair):
    cv2.imwrite(str(tmp_path / "view.png"), image_pair[0])
    result = subprocess.run([sys.executable, str(SOURCE / "examples/python/match_fisheye.py"), str(FISHEYE_CAMERA),
                             str(tmp_path / "view.png"), "-o", str(tmp_path / "matches.png")], capture_output=True,
                            text=True, env=dict(os.environ))
    assert result.returncode == 0, result.stderr
    drawn = cv2.imread(str(tmp_path / "matches.png"))
    assert drawn.shape[1] == 2 * image_pair[0].shape[1]
    line = next(l for l in result.stdout.splitlines() if l.startswith("correct"))
    correct, total = (int(w) for w in line.split(": ")[1].split(" of "))
    assert total > 50 and correct > total // 2, result.stdout
    # Right matches in green, wrong ones in red (BGR; lines are antialiased, so shades of them).
    blue, g, r = (drawn[..., i].astype(int) for i in range(3))
    green = ((g > 120) & (r < 60) & (blue < 60)).sum()
    red = ((r > 120) & (g < 60) & (blue < 60)).sum()
    assert green > 0 and (red > 0) == (correct < total), (green, red, result.stdout)


def test_the_example_checks_a_real_pair_with_the_relative_pose(tmp_path, image_pair):
    for i, image in enumerate(image_pair):
        cv2.imwrite(str(tmp_path / f"view{i}.png"), image)
    result = subprocess.run([sys.executable, str(SOURCE / "examples/python/match_fisheye.py"), str(FISHEYE_CAMERA),
                             str(tmp_path / "view0.png"), str(tmp_path / "view1.png"), "-o",
                             str(tmp_path / "matches.png")], capture_output=True, text=True, env=dict(os.environ))
    assert result.returncode == 0, result.stderr
    assert any(l.startswith(("right (the fitted relative pose", "no relative pose"))
               for l in result.stdout.splitlines()), result.stdout
    assert cv2.imread(str(tmp_path / "matches.png")) is not None


def test_every_simd_level_gives_the_same_features_and_matches(camera, image_pair):
    levels = mdbrief.supported_simd_levels()
    supported = mdbrief.supported_simd_level()
    assert levels[0] == "portable" and levels[-1] == supported
    assert mdbrief.simd_level() == supported
    features = mdbrief.MdBrief(camera, nfeatures=500)
    results = []
    try:
        for level in levels:
            mdbrief.limit_simd_level(level)
            assert mdbrief.simd_level() == level
            kp1, d1, m1 = features.detect_and_compute(image_pair[0])
            kp2, d2, m2 = features.detect_and_compute(image_pair[1])
            matches = mdbrief.match(d1, d2, m1, m2, ratio=0.8, as_array=True)
            results.append(([k.pt + (k.angle,) for k in kp1], d1, m1, matches))
    finally:
        mdbrief.limit_simd_level("avx512")
    assert len(results[0][0]) > 100 and len(results[0][3]) > 20
    for other in results[1:]:
        assert other[0] == results[0][0]
        for a, b in zip(other[1:], results[0][1:]):
            np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError, match="not one of: portable, sse4, neon, avx2, avx512"):
        mdbrief.limit_simd_level("sse9")


def test_keypoint_lookalikes_are_read_like_cv2_keypoints(camera, image_pair):
    # cv2.KeyPoint values are read from the object itself, anything else through its attributes.
    class Lookalike:
        def __init__(self, k):
            self.pt, self.size, self.angle = k.pt, k.size, k.angle
            self.response, self.octave, self.class_id = k.response, k.octave, k.class_id

    given = cv2.ORB_create(300).detect(image_pair[0])
    for i, k in enumerate(given):
        k.class_id = 1000 + i  # passed through to the described keypoints
    features = mdbrief.MdBrief(camera)
    kp_a, d_a, m_a = features.compute(image_pair[0], given)
    kp_b, d_b, m_b = features.compute(image_pair[0], [Lookalike(k) for k in given])
    assert len(kp_a) > 100
    assert [(k.pt, k.size, k.angle, k.response, k.octave, k.class_id) for k in kp_a] == \
        [(k.pt, k.size, k.angle, k.response, k.octave, k.class_id) for k in kp_b]
    np.testing.assert_array_equal(d_a, d_b)
    np.testing.assert_array_equal(m_a, m_b)
    ids = [k.class_id for k in kp_a]
    assert ids == sorted(set(ids)) and ids[0] >= 1000


def test_presets_are_starting_points_of_the_options(camera, image_pair):
    assert mdbrief.presets() == ["tracking", "matching", "paper"]
    default = mdbrief.MdBrief(camera)
    assert default.descriptor_size == mdbrief.MdBrief(camera, preset="tracking").descriptor_size == 32
    matching = mdbrief.MdBrief(camera, preset="matching")
    assert matching.descriptor_size == 64
    assert mdbrief.MdBrief(camera, preset="matching", bits=128).descriptor_size == 16
    paper = mdbrief.MdBrief(camera, preset="paper", nfeatures=300)
    kp, d, m = paper.detect_and_compute(image_pair[0])
    # The paper's modORB: sizes 31 * 1.2^octave.
    assert 0 < len(kp) <= 300
    assert all(abs(np.log(k.size / 31.0) / np.log(1.2) - round(np.log(k.size / 31.0) / np.log(1.2))) < 1e-3 for k in kp)
    with pytest.raises(ValueError, match="preset 'fast' is not one of: tracking, matching, paper"):
        mdbrief.MdBrief(camera, preset="fast")
