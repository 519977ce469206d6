"""mdbrief.match_guided: guided matching (libmdbrief/include/mdbrief/guided_matcher.hpp) from
Python: the matches of mdbrief.match whose prediction is within the radius, predictions outside
the image, the consistency checks, the keywords and bad arguments."""
import math

import cv2
import numpy as np
import pytest

import mdbrief

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
