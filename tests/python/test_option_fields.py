"""Python's surface of the option field tables (mdbrief.option_fields): every numeric keyword of
MdBrief, train and match, set just outside its range, raises ValueError naming the keyword, the
range and the value, the message the C++ struct, FileStorage and the command line give
(tests/test_option_fields.cpp)."""
import math

import numpy as np
import pytest

import mdbrief


def values_just_outside(field):
    low, high, low_open, high_open, _, _ = field["range"]
    if field["type"] == "int":
        return [int(low) - 1, int(high) + 1]
    return [low if low_open else math.nextafter(low, -math.inf), high if high_open else math.nextafter(high, math.inf)]


def numeric_fields(callable_name):
    fields = [f for f in mdbrief.option_fields(callable_name) if f["range"] is not None]
    assert fields, callable_name
    return fields


@pytest.mark.parametrize("field", numeric_fields("MdBrief"), ids=lambda f: f["keyword"])
def test_mdbrief_keywords_out_of_range_name_keyword_range_and_value(camera, field):
    for value in values_just_outside(field):
        expected = f"{field['keyword']} must be {field['range_text']}, got "
        with pytest.raises(ValueError) as error:
            mdbrief.MdBrief(camera, **{field["keyword"]: value})
        message = str(error.value)
        assert message.startswith(expected), message
        assert float(message[len(expected):]) == value, message


@pytest.mark.parametrize("field", numeric_fields("train"), ids=lambda f: f["keyword"])
def test_train_keywords_out_of_range_are_refused_before_any_work(field):
    for value in values_just_outside(field):
        expected = f"{field['keyword']} must be {field['range_text']}, got {value}"
        with pytest.raises(ValueError) as error:
            mdbrief.train(images="/no/such/folder", **{field["keyword"]: value})
        message = str(error.value)
        if field["type"] == "int":
            assert message == expected
        else:
            assert message.startswith(f"{field['keyword']} must be {field['range_text']}, got "), message


def test_match_keywords_out_of_range_name_the_keyword():
    d = np.zeros((3, 32), np.uint8)
    with pytest.raises(ValueError, match=r"^ratio must be in \(0, 1\], got 1\.5$"):
        mdbrief.match(d, d, ratio=1.5)
    with pytest.raises(ValueError, match=r"^max_distance must be in \[0, 512\], got -1$"):
        mdbrief.match(d, d, max_distance=-1)


def test_sizes_are_bounded_before_any_work(camera):
    # Before: patches=-1 became 18446744073709551615 and the run exited normally, and a
    # 99999-pixel smoothing kernel was accepted (and ran for minutes).
    with pytest.raises(ValueError, match=r"^patches must be in \[1, 200000\], got -1$"):
        mdbrief.train(patches=-1)
    with pytest.raises(ValueError, match=r"^tests must be a multiple of 32 in \[32, 512\], got -32$"):
        mdbrief.train(tests=-32)
    with pytest.raises(ValueError, match=r"^smoothing_kernel must be an odd number in \[1, 31\], got 99999$"):
        mdbrief.MdBrief(camera, smoothing_kernel=99999)
    # border_margin was reported as harris_block_size (its message mentioned both).
    with pytest.raises(ValueError, match=r"^border_margin must be in \[15, 1024\], got -100$"):
        mdbrief.MdBrief(camera, border_margin=-100)


def test_train_exposes_every_option_with_the_shipped_criterion_by_default():
    keywords = {f["keyword"]: f for f in mdbrief.option_fields("train")}
    for name in ["images", "detector", "camera", "patches", "tests", "seed", "selection", "name", "out", "patches_file",
                 "save_patches", "keypoints_per_image", "render_through_camera", "held_out", "make_default",
                 "counterparts", "view_tilt", "correlation_start", "pool", "non_matching_sigmas", "matching_sigmas",
                 "covariance_words"]:
        assert name in keywords, name
        assert f"{name}=" in mdbrief.train.__doc__
    assert keywords["selection"]["default"] == "separation"
    assert keywords["selection"]["choices"] == ["paper", "stability", "separation"]
