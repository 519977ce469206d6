"""mdbrief.match_guided: guided matching (libmdbrief/include/mdbrief/match/guided_matcher.hpp) from
Python: the matches of mdbrief.match whose prediction is within the radius (synthetic and on a
photo moved as a tracker sees it), predictions outside the image, the consistency checks, the
keywords and bad arguments."""
import math

import cv2
import numpy as np
import pytest

import mdbrief
from conftest import doc_image

WIDTH, HEIGHT = 640, 480


def scene(n=800, nbytes=32, error=10.0, seed=1):
    """Train keypoints over the image; each query a noisy copy of train i with a prediction
    within `error` pixels of its keypoint."""
    rng = np.random.default_rng(seed)
    d2 = rng.integers(0, 256, (n, nbytes), dtype=np.uint8)
    d1 = d2.copy()
    flips = rng.integers(0, nbytes * 8, (n, 6))
    for i, bits in enumerate(flips):
        for b in bits:
            d1[i, b // 8] ^= np.uint8(1 << (b % 8))
    xy = rng.uniform([0, 0], [WIDTH - 1, HEIGHT - 1], (n, 2))
    angles = rng.uniform(0, 360, n)
    keypoints2 = [cv2.KeyPoint(float(x), float(y), 7.0, float(a)) for (x, y), a in zip(xy, angles)]
    r = rng.uniform(0, error, n)
    t = rng.uniform(0, 2 * math.pi, n)
    # Kept inside the image (moving towards the keypoint): outside it a prediction has no candidates.
    predicted = np.clip(xy + np.stack([r * np.cos(t), r * np.sin(t)], axis=1), 0, [WIDTH - 0.01, HEIGHT - 0.01])
    masks1 = np.where(rng.random((n, nbytes)) < 0.9, 0xFF, 0xEF).astype(np.uint8)
    masks2 = np.where(rng.random((n, nbytes)) < 0.9, 0xFF, 0xF7).astype(np.uint8)
    return d1, d2, predicted, keypoints2, masks1, masks2


def test_a_tracked_real_image_keeps_the_right_brute_force_matches(camera):
    """A tracker's second frame: the photo moved by (6, -4) px, predictions within 6 px per axis
    of the true positions, the library's default features and matcher settings."""
    image = doc_image("graf1.png", camera.image_size)
    shift = np.array([6.0, -4.0])
    moved = cv2.warpAffine(image, np.float32([[1, 0, shift[0]], [0, 1, shift[1]]]), camera.image_size)
    features = mdbrief.MdBrief(camera)
    k1, d1, m1 = features.detect_and_compute(image)
    k2, d2, m2 = features.detect_and_compute(moved)
    p1, p2 = np.array([k.pt for k in k1]), np.array([k.pt for k in k2])
    predicted = p1 + shift + np.random.default_rng(3).uniform(-6, 6, p1.shape)

    def is_right(m):
        return np.hypot(*(p2[m.trainIdx] - p1[m.queryIdx] - shift)) < 2

    brute = mdbrief.match(d1, d2, m1, m2)
    guided = mdbrief.match_guided(d1, d2, predicted, k2, camera.image_size, m1, m2)
    found = {m.queryIdx: m.trainIdx for m in guided}
    width, height = camera.image_size
    inside = [m for m in brute if is_right(m) and 0 <= predicted[m.queryIdx][0] < width
              and 0 <= predicted[m.queryIdx][1] < height]
    assert len(inside) > 500
    assert all(found.get(m.queryIdx) == m.trainIdx for m in inside)
    right = sum(map(is_right, guided))
    assert right >= sum(map(is_right, brute)) and right >= 0.9 * len(guided)
    # The consistency checks, with this motion's orientations and sizes, keep nearly all of them.
    checked = mdbrief.match_guided(d1, d2, predicted, k2, camera.image_size, m1, m2, keypoints1=k1,
                                   max_angle_difference=20, max_scale_ratio=1.3)
    assert sum(map(is_right, checked)) >= 0.95 * right


@pytest.mark.parametrize("masked", [False, True])
def test_guided_keeps_the_brute_force_matches_within_the_radius(masked):
    d1, d2, predicted, keypoints2, masks1, masks2 = scene()
    masks = (masks1, masks2) if masked else (None, None)
    brute = mdbrief.match(d1, d2, *masks)
    guided = mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), *masks, radius=15)
    assert len(brute) > 600
    found = {m.queryIdx: (m.trainIdx, m.distance) for m in guided}
    for m in brute:
        assert found[m.queryIdx] == (m.trainIdx, m.distance)
    assert all(m.trainIdx == m.queryIdx for m in guided)
    array = mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), *masks, as_array=True)
    assert array["query_idx"].tolist() == [m.queryIdx for m in guided]
    assert array["train_idx"].tolist() == [m.trainIdx for m in guided]


def test_predictions_outside_the_image_or_nan_give_no_match():
    d1, d2, predicted, keypoints2, _, _ = scene(n=50)
    outside = np.array([[-1, 10], [WIDTH, 10], [10, HEIGHT], [np.nan, 5], [np.inf, 5]] * 10, np.float64)
    assert mdbrief.match_guided(d1, d2, outside, keypoints2, (WIDTH, HEIGHT), radius=10000) == []
    # Far from every keypoint with radius 0: no candidates either.
    assert mdbrief.match_guided(d1, d2, predicted + 0.5, keypoints2, (WIDTH, HEIGHT), radius=0) == []


def test_orientation_check_needs_and_uses_the_query_keypoints():
    d1, d2, predicted, keypoints2, _, _ = scene(n=200)
    turned = [cv2.KeyPoint(k.pt[0], k.pt[1], k.size, (k.angle + 90) % 360) for k in keypoints2]
    same = list(keypoints2)
    with pytest.raises(ValueError, match=r"^queryKeypoints: 0 given for 200 query rows$"):
        mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), max_angle_difference=30)
    kept = mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), keypoints1=same,
                                max_angle_difference=30)
    assert len(kept) > 150
    # The true trains are turned away; max_distance keeps a lone unrelated candidate (~128 bits
    # away, no second to fail the ratio test) from standing in.
    assert mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), keypoints1=turned,
                                max_angle_difference=30, max_distance=40) == []


def test_keywords_and_bad_arguments():
    d1, d2, predicted, keypoints2, masks1, _ = scene(n=20)
    keywords = [f["keyword"] for f in mdbrief.option_fields("match_guided")]
    assert keywords == ["radius", "max_angle_difference", "max_scale_ratio", "ratio", "cross_check",
                        "max_distance", "parallel"]
    with pytest.raises(ValueError, match=r"^radius must be in \[0, 10000\], got -1$"):
        mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), radius=-1)
    with pytest.raises(ValueError, match=r"^max_scale_ratio must be in \[1, 1000\], got 0\.5$"):
        mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), max_scale_ratio=0.5)
    with pytest.raises(TypeError, match="unexpected keyword argument 'radiu'"):
        mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), radiu=3)
    with pytest.raises(ValueError, match=r"^predicted: 19 given for 20 query rows$"):
        mdbrief.match_guided(d1, d2, predicted[:19], keypoints2, (WIDTH, HEIGHT))
    with pytest.raises(ValueError, match=r"^trainKeypoints: 19 given for 20 train rows$"):
        mdbrief.match_guided(d1, d2, predicted, keypoints2[:19], (WIDTH, HEIGHT))
    with pytest.raises(ValueError, match=r"^imageSize: 0x480 has no pixels$"):
        mdbrief.match_guided(d1, d2, predicted, keypoints2, (0, HEIGHT))
    with pytest.raises(ValueError, match="masks1 and masks2 must both be given"):
        mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), masks1)
    with pytest.raises(ValueError, match=r"must have shape \(N, 2\)"):
        mdbrief.match_guided(d1, d2, np.zeros((20, 3)), keypoints2, (WIDTH, HEIGHT))


@pytest.mark.parametrize("field", [f for f in mdbrief.option_fields("match_guided") if f["range"] is not None],
                         ids=lambda f: f["keyword"])
def test_every_numeric_keyword_just_outside_its_range_is_refused_naming_it(field):
    d1, d2, predicted, keypoints2, _, _ = scene(n=5)
    low, high, low_open, high_open, _, _ = field["range"]
    # The options are C++ floats: one float step outside (a double step would round back in).
    below = low if low_open else float(np.nextafter(np.float32(low), np.float32(-np.inf)))
    above = high if high_open else float(np.nextafter(np.float32(high), np.float32(np.inf)))
    for value in [below, above]:
        with pytest.raises(ValueError) as error:
            mdbrief.match_guided(d1, d2, predicted, keypoints2, (WIDTH, HEIGHT), **{field["keyword"]: value})
        assert str(error.value).startswith(f"{field['keyword']} must be {field['range_text']}, got "), error.value
