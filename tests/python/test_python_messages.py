"""Issues 45 and 46: Python inputs that were taken silently or refused in pybind11's or the C++
library's words, and MdBrief's `method` keyword."""
import pickle

import cv2
import numpy as np
import pytest

import mdbrief
from conftest import PINHOLE_CAMERA

RNG = np.random.default_rng(45)
A = RNG.normal(size=(30, 3))
A /= np.linalg.norm(A, axis=1, keepdims=True)
R = cv2.Rodrigues(np.array([0.05, 0.3, -0.04]))[0]
T = np.array([0.5, -0.1, 0.15])
# Points of a scene seen from both cameras: b is each point in camera b's frame (X_a = R X_b + t).
POINTS = A * RNG.uniform(2, 6, size=(30, 1))
B = (POINTS - T) @ R
B /= np.linalg.norm(B, axis=1, keepdims=True)


@pytest.fixture(scope="module")
def pinhole():
    return mdbrief.load_camera(str(PINHOLE_CAMERA))


@pytest.mark.parametrize("call, argument", [
    (lambda c: mdbrief.fit_essential(A > 0, B), "bearings_a"),
    (lambda c: mdbrief.fit_homography(A, B > 0), "bearings_b"),
    (lambda c: mdbrief.check_known_pose(A, B, R, T > 0), "translation"),
    (lambda c: c.bearing_to_pixel(np.array([[True, False, True]])), "bearings"),
    (lambda c: c.pixel_to_bearing([[True, False]]), "pixels"),
    (lambda c: c.is_valid(np.ones((3, 2), bool)), "pixels"),
    (lambda c: mdbrief.pixels_per_radian(c, np.ones((3, 2), bool)), "pixels"),
    (lambda c: mdbrief.match_guided(np.zeros((2, 32), np.uint8), np.zeros((2, 32), np.uint8), np.ones((2, 2), bool),
                                    [cv2.KeyPoint(1, 1, 7)] * 2, (640, 480)), "predicted"),
])
def test_boolean_arrays_are_not_points(pinhole, call, argument):
    """Issue 45: numpy cast True to 1.0, so a boolean mask passed by mistake was taken as bearings."""
    with pytest.raises(TypeError, match=rf"^{argument} must be an array of numbers, got booleans$"):
        call(pinhole)


def test_extreme_bearing_lengths_keep_their_direction():
    """Issue 45: bearings of length 1e200 or 1e-170 are finite and non-zero, yet were refused
    (in the library's words: "fitEssential: bearing b[0]"), as was a translation of 1e200."""
    reference = mdbrief.fit_essential(A, B)
    assert reference.ok
    for scale in (1e200, 1e-170):
        fit = mdbrief.fit_essential(A, B * scale)
        assert fit.ok and np.array_equal(fit.inliers, reference.inliers)
        np.testing.assert_allclose(fit.rotation, reference.rotation, atol=1e-9)
        assert mdbrief.fit_homography(A * scale, B).inlier_count == mdbrief.fit_homography(A, B).inlier_count
    known = mdbrief.check_known_pose(A, B, R, T)
    far = mdbrief.check_known_pose(A, B, R, T * 1e200)
    assert known.inlier_count == 30 and np.array_equal(far.inliers, known.inliers)
    np.testing.assert_allclose(far.residuals, known.residuals, atol=1e-12)
    np.testing.assert_array_equal(far.translation, T * 1e200)  # the pose as given


def test_two_view_errors_name_the_python_function_and_argument():
    with pytest.raises(ValueError, match=r"^fit_essential: bearings_b\[2\] must be finite and non-zero$"):
        mdbrief.fit_essential(A, np.vstack([B[:2], [0, 0, 0], B[3:]]))
    with pytest.raises(ValueError, match=r"^fit_homography: bearings_a\[0\] must be finite and non-zero$"):
        mdbrief.fit_homography(np.vstack([[np.inf, 0, 1], A[1:]]), B)
    with pytest.raises(ValueError, match=r"^check_known_pose: rotation is not a rotation \(R\^T R = I"):
        mdbrief.check_known_pose(A, B, 2 * R, T)
    with pytest.raises(ValueError, match=r"^check_known_pose: translation must be finite and non-zero"):
        mdbrief.check_known_pose(A, B, R, [np.nan, 0, 0])


def tracker_case():
    """One query whose two candidates are 9 and 10 bits away: the ratio test (0.8) refuses it."""
    d1 = np.zeros((1, 32), np.uint8)
    d2 = np.zeros((2, 32), np.uint8)
    d2[0, :2] = [0xFF, 0x01]  # 9 bits
    d2[1, :2] = [0xFF, 0x03]  # 10 bits
    return d1, d2, np.array([[50.0, 50.0]]), [cv2.KeyPoint(50, 50, 7), cv2.KeyPoint(52, 50, 7)], (100, 100)


def test_match_guided_takes_none_as_match_does():
    """Issue 45: match_guided(..., ratio=None) raised TypeError although its docstring, like
    match's, says None turns the ratio test off; max_distance=None too."""
    d1, d2, predicted, keypoints2, size = tracker_case()
    assert mdbrief.match(d1, d2) == [] and mdbrief.match_guided(d1, d2, predicted, keypoints2, size) == []
    plain = mdbrief.match(d1, d2, ratio=None)
    guided = mdbrief.match_guided(d1, d2, predicted, keypoints2, size, ratio=None, max_distance=None)
    assert [(m.queryIdx, m.trainIdx, m.distance) for m in guided] == [(0, 0, 9.0)]
    assert [(m.queryIdx, m.trainIdx, m.distance) for m in plain] == [(0, 0, 9.0)]


@pytest.mark.parametrize("cls, state", [
    ("Camera", (1, 2, 3, {})),
    ("Camera", ("pinhole", 640, 480, 4)),
    ("ComparisonSet", (1, [[0, 0, 0, 0]], [])),
    ("ComparisonSet", ("t", [[0, 0, 0, 0]], 5)),
    ("MdBrief", ("not a camera", {}, None)),
])
def test_bad_pickled_states_are_named(cls, state):
    """Issue 45: these raised pybind11's "Unable to cast Python instance to C++ type (#define
    PYBIND11_DETAILED_ERROR_MESSAGES ...)"."""
    target = getattr(mdbrief, cls)
    with pytest.raises(ValueError, match=rf"^{cls}: bad pickled state \({cls}.__getstate__ gives \("):
        target.__new__(target).__setstate__(state)


def test_a_pickled_feature_with_an_uninitialised_camera_names_the_camera(pinhole):
    """Issue 45: "Unable to cast from non-held to held instance (T& to Holder<T>)"."""
    state = mdbrief.MdBrief(pinhole).__getstate__()
    with pytest.raises(TypeError, match=r"^this mdbrief\.Camera object was never initialised"):
        mdbrief.MdBrief.__new__(mdbrief.MdBrief).__setstate__((mdbrief.Camera.__new__(mdbrief.Camera),) + state[1:])


def test_method_is_the_keyword_of_the_detection_method(pinhole):
    """Issue 46: MdBrief(camera, method='modorb') was refused; C++ (DetectorOptions::method) and the
    README say method."""
    feature = mdbrief.MdBrief(pinhole, method="modorb")
    assert feature.options["method"] == "modorb" and "detector" not in feature.options
    assert mdbrief.MdBrief(pinhole, method="hessian").options["method"] == "hessian"
    keywords = [f["keyword"] for f in mdbrief.option_fields("MdBrief")]
    assert "method" in keywords and "detector" not in keywords
    assert "    method='hessian'  keypoint detector" in mdbrief.MdBrief.__init__.__doc__
    with pytest.raises(ValueError, match=r"^method must be one of: modorb, hessian, got 'sift'$"):
        mdbrief.MdBrief(pinhole, method="sift")
    assert pickle.loads(pickle.dumps(feature)).options == feature.options


def test_detector_is_a_deprecated_name_of_method(pinhole):
    image = np.zeros(pinhole.image_size[::-1], np.uint8)
    cv2.circle(image, (320, 240), 60, 255, -1)
    cv2.rectangle(image, (100, 100), (200, 180), 128, -1)
    with pytest.warns(DeprecationWarning, match="detector= is deprecated, use method="):
        old = mdbrief.MdBrief(pinhole, detector="modorb")
    new = mdbrief.MdBrief(pinhole, method="modorb")
    assert old.options == new.options
    kp_old, d_old, _ = old.detect_and_compute(image)
    kp_new, d_new, _ = new.detect_and_compute(image)
    assert [k.pt for k in kp_old] == [k.pt for k in kp_new] and np.array_equal(d_old, d_new)
    with pytest.raises(TypeError, match="both method= and detector="):
        mdbrief.MdBrief(pinhole, method="modorb", detector="hessian")


@pytest.mark.parametrize("offset", [2**63, 2**31, -2**63 - 1, 16])
def test_an_offset_out_of_range_is_named_as_given(offset):
    """Issue 45: an offset beyond a C int was "not a row of 4 ints", though it is one; it is out of range."""
    with pytest.raises(ValueError, match=rf"ComparisonSet: test 1 has offset {offset} outside \[-16, 15\]"):
        mdbrief.ComparisonSet("big", [[0, 0, 1, 1], [0, 1, offset, 0]] + [[0, 0, 1, 1]] * 30)
