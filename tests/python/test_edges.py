"""Unusual but legitimate Python input (read-only and strided arrays, path types), and hostile
input (NUL in paths, undecodable messages, extreme numbers): accepted with the same results, or
refused with a clear exception."""
import os
import pathlib

import cv2
import numpy as np
import pytest

import mdbrief
from conftest import FISHEYE_CAMERA, PINHOLE_CAMERA


def read_only(array):
    copy = array.copy()
    copy.flags.writeable = False
    return copy


def strided(array):
    """The same values in a non-contiguous view (every second element of a wider array)."""
    wide = np.zeros(array.shape[:-1] + (2 * array.shape[-1],), array.dtype)
    wide[..., ::2] = array
    view = wide[..., ::2]
    assert not view.flags.c_contiguous
    return view


def read_only_strided(array):
    view = strided(array)
    view.flags.writeable = False
    return view


LAYOUTS = [read_only, strided, read_only_strided]


def same_features(a, b):
    assert [(k.pt, k.size, k.angle, k.octave) for k in a[0]] == [(k.pt, k.size, k.angle, k.octave) for k in b[0]]
    for x, y in zip(a[1:], b[1:]):
        assert (x is None and y is None) or np.array_equal(x, y)


@pytest.mark.parametrize("layout", LAYOUTS, ids=lambda f: f.__name__)
def test_every_array_argument_takes_read_only_and_strided_arrays(camera, image_pair, layout):
    features = mdbrief.MdBrief(camera, nfeatures=300)
    image = image_pair[0]
    grey = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    mask = np.zeros(grey.shape, np.uint8)
    mask[100:400, 150:600] = 255
    for picture in (image, grey):
        reference = features.detect_and_compute(picture, mask)
        assert len(reference[0]) > 50
        same_features(features.detect_and_compute(layout(picture), layout(mask)), reference)
        assert [k.pt for k in features.detect(layout(picture), layout(mask))] == [k.pt for k in reference[0]]
        same_features(features.compute(layout(picture), reference[0]), features.compute(picture, reference[0]))

    k1, d1, m1 = features.detect_and_compute(image_pair[0])
    k2, d2, m2 = features.detect_and_compute(image_pair[1])
    plain = [(m.queryIdx, m.trainIdx, m.distance) for m in mdbrief.match(d1, d2)]
    masked = [(m.queryIdx, m.trainIdx, m.distance) for m in mdbrief.match(d1, d2, m1, m2, ratio=0.9)]
    assert plain and masked
    assert [(m.queryIdx, m.trainIdx, m.distance) for m in mdbrief.match(layout(d1), layout(d2))] == plain
    assert [(m.queryIdx, m.trainIdx, m.distance)
            for m in mdbrief.match(layout(d1), layout(d2), layout(m1), layout(m2), ratio=0.9)] == masked

    pixels = np.array([[100.0, 200.0], [377.0, 240.0], [600.0, 50.0]])
    bearings = camera.pixel_to_bearing(pixels)
    np.testing.assert_array_equal(camera.pixel_to_bearing(layout(pixels)), bearings)
    np.testing.assert_array_equal(camera.bearing_to_pixel(layout(bearings)), camera.bearing_to_pixel(bearings))
    np.testing.assert_array_equal(camera.is_valid(layout(pixels)), camera.is_valid(pixels))


def test_paths_may_be_str_bytes_or_path_like(tmp_path):
    reference = mdbrief.load_camera(str(FISHEYE_CAMERA)).to_yaml()
    for path in (FISHEYE_CAMERA, os.fsencode(FISHEYE_CAMERA)):
        assert mdbrief.load_camera(path).to_yaml() == reference
    camera = mdbrief.load_camera(FISHEYE_CAMERA)
    camera.save(tmp_path / "a.yaml")
    camera.save(os.fsencode(tmp_path / "b.yaml"))
    assert (tmp_path / "a.yaml").read_text() == (tmp_path / "b.yaml").read_text() == reference

    builtin = mdbrief.load_pattern("brief_random_512")
    (tmp_path / "set.json").write_text('{"name": "set", "tests": %s}' % builtin.tests.tolist())
    for path in (tmp_path / "set.json", os.fsencode(tmp_path / "set.json"), str(tmp_path / "set.json")):
        assert np.array_equal(mdbrief.load_pattern(path).tests, builtin.tests)
        assert mdbrief.MdBrief(camera, pattern=path).options["pattern"] == str(tmp_path / "set.json")
    assert len(mdbrief.load_pattern(b"brief_random_512")) == 512

    class PathLike:
        def __fspath__(self):
            return str(PINHOLE_CAMERA)

    assert mdbrief.load_camera(PathLike()).model == "pinhole"
    with pytest.raises(TypeError, match="path"):
        mdbrief.load_camera(42)
    with pytest.raises(FileNotFoundError) as missing:
        mdbrief.load_camera(tmp_path / "missing.yaml")
    assert missing.value.filename == str(tmp_path / "missing.yaml")


def test_training_takes_path_like_arguments(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing"):
        mdbrief.train(images=tmp_path / "missing")
    with pytest.raises(FileNotFoundError, match="missing"):
        mdbrief.train(images=[os.fsencode(tmp_path / "missing")])
    (tmp_path / "images").mkdir()
    with pytest.raises(FileNotFoundError, match="nocam"):
        mdbrief.train(images=tmp_path / "images", camera=tmp_path / "nocam.yaml")
    with pytest.raises(FileNotFoundError, match="none.h5"):
        mdbrief.train(patches_file=tmp_path / "none.h5")
    with pytest.raises(FileNotFoundError, match="list.txt"):
        mdbrief.train(images=tmp_path / "images", held_out=[tmp_path / "list.txt"])
    # out reaches the tool as the folder named: a missing one is its error.
    with pytest.raises(ValueError, match="no_such_out"):
        mdbrief.train(images=tmp_path / "images", out=tmp_path / "no_such_out")


def test_paths_with_a_nul_byte_are_refused(tmp_path):
    camera = mdbrief.load_camera(FISHEYE_CAMERA)
    cut = str(tmp_path / "a.yaml") + "\0.txt"
    calls = [
        lambda: mdbrief.load_camera(str(FISHEYE_CAMERA) + "\0ignored"),
        lambda: mdbrief.load_camera(os.fsencode(FISHEYE_CAMERA) + b"\0ignored"),
        lambda: camera.save(cut),
        lambda: mdbrief.load_pattern(str(tmp_path / "set.json") + "\0"),
        lambda: mdbrief.MdBrief(camera, pattern="brief_random_512\0x"),
        lambda: mdbrief.train(images=str(tmp_path) + "\0x"),
        lambda: mdbrief.train(images=tmp_path, out=str(tmp_path) + "\0x"),
    ]
    for call in calls:
        with pytest.raises(ValueError, match="NUL"):
            call()
    assert not (tmp_path / "a.yaml").exists()


def test_messages_with_invalid_utf8_keep_their_text(tmp_path):
    (tmp_path / "key.yaml").write_bytes(b"model: pinhole\nwidth: 754\nheight: 480\nfx: 377\nfy: 377\n"
                                        b"cx: 380\ncy: 240\n\xff\xfe: 1\n")
    with pytest.raises(ValueError) as error:
        mdbrief.load_camera(tmp_path / "key.yaml")
    assert "key.yaml" in str(error.value) and "\\xff\\xfe" in str(error.value)
    (tmp_path / "utf16.json").write_bytes('{"name": "x", "tests": [[0, 0, 1, 1]]}'.encode("utf-16"))
    with pytest.raises(ValueError) as error:
        mdbrief.load_pattern(tmp_path / "utf16.json")
    assert "utf16.json" in str(error.value)
    # A file name that is not UTF-8 is named as the file system spells it.
    odd = os.fsencode(tmp_path) + b"/\xff.yaml"
    with pytest.raises(FileNotFoundError) as missing:
        mdbrief.load_camera(odd)
    assert os.fsencode(missing.value.filename) == odd


def test_bearings_of_any_finite_length_give_the_pixel_of_their_direction():
    for path in sorted(FISHEYE_CAMERA.parent.glob("*.yaml")):
        camera = mdbrief.load_camera(path)
        directions = np.array([[1.0, 1.0, 1.0], [0.0, 0.0, 1.0], [0.3, -0.2, 1.0]])
        expected = camera.bearing_to_pixel(directions)
        for length in (1e-300, 1e-200, 1e200, 1e308, 1.7e308):
            scaled = directions / np.abs(directions).max(axis=1, keepdims=True) * length
            np.testing.assert_allclose(camera.bearing_to_pixel(scaled), expected, rtol=1e-9, atol=1e-6,
                                       err_msg=f"{path.name} at length {length}")
        # Subnormal: only directions whose components are exact at that scale.
        np.testing.assert_allclose(camera.bearing_to_pixel(directions[:2] * 5e-324), expected[:2], rtol=1e-9,
                                   atol=1e-6, err_msg=path.name)
        bad = camera.bearing_to_pixel([[np.inf, 0, 1], [np.nan, 0, 1], [0, 0, 0]])
        assert np.isnan(bad).all(), path.name


def test_keypoint_fields_out_of_the_int_range_are_refused(camera, image_pair):
    class Lookalike:
        def __init__(self, octave=0, class_id=-1):
            self.pt, self.size, self.angle, self.response = (377.0, 240.0), 31.0, -1.0, 0.0
            self.octave, self.class_id = octave, class_id

    features = mdbrief.MdBrief(camera)
    assert len(features.compute(image_pair[0], [Lookalike(2**31 - 1), Lookalike(-2**31)])[0]) == 2
    for bad in (Lookalike(2**32 + 3), Lookalike(-2**31 - 1), Lookalike(2**70), Lookalike(class_id=2**40)):
        with pytest.raises(ValueError, match=r"keypoints\[0\].*outside"):
            features.compute(image_pair[0], [bad])


def test_border_margin_errors_name_border_margin(camera):
    # The range's lower end is set by the Harris window and the orientation radius: the message
    # still names the option that is out of it (it named harris_block_size).
    with pytest.raises(ValueError, match=r"^border_margin must be in \[15, 1024\], got -100$"):
        mdbrief.MdBrief(camera, border_margin=-100)


def test_descriptors_of_no_bytes_are_refused():
    with pytest.raises(ValueError, match="width"):
        mdbrief.match(np.zeros((5, 0), np.uint8), np.zeros((5, 0), np.uint8))
    assert mdbrief.match(np.zeros((0, 0), np.uint8), np.zeros((5, 32), np.uint8)) == []


UNINITIALISED = [
    ("Camera.width", lambda: mdbrief.Camera.__new__(mdbrief.Camera).width),
    ("Camera.pixel_to_bearing", lambda: mdbrief.Camera.__new__(mdbrief.Camera).pixel_to_bearing(np.zeros(2))),
    ("repr(Camera)", lambda: repr(mdbrief.Camera.__new__(mdbrief.Camera))),
    ("MdBrief.detect_and_compute",
     lambda: mdbrief.MdBrief.__new__(mdbrief.MdBrief).detect_and_compute(np.zeros((64, 64), np.uint8))),
    ("MdBrief.descriptor_size", lambda: mdbrief.MdBrief.__new__(mdbrief.MdBrief).descriptor_size),
    ("Vocabulary.word_count", lambda: mdbrief.Vocabulary.__new__(mdbrief.Vocabulary).word_count),
    ("Database.query", lambda: mdbrief.Database.__new__(mdbrief.Database).query(np.zeros((1, 32), np.uint8))),
    ("len(Database)", lambda: len(mdbrief.Database.__new__(mdbrief.Database))),
    ("ComparisonSet.name", lambda: mdbrief.ComparisonSet.__new__(mdbrief.ComparisonSet).name),
    ("len(ComparisonSet)", lambda: len(mdbrief.ComparisonSet.__new__(mdbrief.ComparisonSet))),
]


@pytest.mark.parametrize("case", [c for _, c in UNINITIALISED], ids=[name for name, _ in UNINITIALISED])
def test_an_object_made_with_new_alone_raises_instead_of_crashing(case):
    """Issue 29: Camera.__new__(Camera).width crashed (exit 139), Database.__new__(Database).query
    read garbage and ComparisonSet.__new__(ComparisonSet).name raised MemoryError. Run in a child process, so
    that a crash fails this test instead of ending the session."""
    import multiprocessing
    context = multiprocessing.get_context("fork")
    queue = context.Queue()

    def child():
        try:
            case()
            queue.put("no exception")
        except TypeError as e:
            queue.put("TypeError: " + str(e))
        except BaseException as e:  # noqa: BLE001 (any other exception is a failure, reported)
            queue.put(type(e).__name__ + ": " + str(e))

    process = context.Process(target=child)
    process.start()
    process.join(60)
    assert process.exitcode == 0, f"the child died (exit {process.exitcode})"
    message = queue.get(timeout=5)
    assert message.startswith("TypeError: ") and "never initialised" in message, message


def test_unpickling_still_initialises_the_objects():
    """Unpickling makes the object with __new__ and initialises it with __setstate__."""
    import pickle
    camera = mdbrief.load_camera(str(FISHEYE_CAMERA))
    again = pickle.loads(pickle.dumps(camera))
    assert again.width == camera.width and again.parameters == camera.parameters
    tests = mdbrief.load_pattern(mdbrief.default_pattern())
    assert len(pickle.loads(pickle.dumps(tests))) == len(tests)


def test_setstate_on_a_live_object_raises():
    """Issue 29: Camera.__setstate__(other) on a live object was silently ignored."""
    camera = mdbrief.load_camera(str(FISHEYE_CAMERA))
    other = mdbrief.load_camera(str(PINHOLE_CAMERA))
    with pytest.raises(TypeError, match="already"):
        camera.__setstate__(other.__getstate__())
    assert camera.model == "ocam"


def test_integers_beyond_a_c_int_get_the_range_error():
    """Issue 29: Camera('pinhole', 2**40, ...) and query(..., max_results=2**31) raised pybind11's
    "incompatible function arguments"; a width is refused by its range, a huge max_results means all."""
    with pytest.raises(ValueError, match="'width' must be a positive integer \\(got 1099511627776\\)"):
        mdbrief.Camera("pinhole", 2**40, 480, fx=400, fy=400, cx=320, cy=240)
    with pytest.raises(ValueError, match="'height' must be a positive integer"):
        mdbrief.Camera("pinhole", 640, -2**70, fx=400, fy=400, cx=320, cy=240)
    vocabulary = mdbrief.Vocabulary.load(str(pathlib.Path(__file__).resolve().parents[2] / "configs" / "vocabularies" /
                                             "tracking_k10_L4.mdbvoc"))
    database = mdbrief.Database(vocabulary)
    rng = np.random.default_rng(5)
    descriptors = rng.integers(0, 256, (50, vocabulary.bits // 8), dtype=np.uint8)
    database.add(descriptors, np.full_like(descriptors, 255) if vocabulary.masked else None)
    assert len(database.query(descriptors, np.full_like(descriptors, 255) if vocabulary.masked else None,
                              max_results=2**31)) == 1
    with pytest.raises(ValueError, match="maxResults must be >= 1"):
        database.query(descriptors, np.full_like(descriptors, 255) if vocabulary.masked else None, max_results=-2**40)


def test_a_set_name_the_registry_refuses_is_refused_at_once(tmp_path):
    """Issue 29: ComparisonSet('A B', ...) and train(name='A B') were accepted, then refused at save()."""
    with pytest.raises(ValueError, match="pattern name 'A B' must match"):
        mdbrief.ComparisonSet("A B", [[0, 0, 1, 1]] * 32)
    with pytest.raises(ValueError, match="pattern name 'A B' must match"):
        mdbrief.train(images=str(tmp_path), name="A B")
    assert mdbrief.ComparisonSet("a_b", [[0, 0, 1, 1]] * 32).name == "a_b"
