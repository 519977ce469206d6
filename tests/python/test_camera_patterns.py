"""mdbrief.Camera, the test sets and off-line learning from Python."""
import json
import os

import numpy as np
import pytest

import mdbrief
from conftest import FISHEYE_CAMERA, OPENCV_DOC, PINHOLE_CAMERA, SOURCE


@pytest.mark.parametrize("path", sorted((SOURCE / "configs/cameras").glob("*.yaml")), ids=lambda p: p.stem)
def test_pixels_round_trip_through_bearings(path):
    camera = mdbrief.load_camera(str(path))
    width, height = camera.image_size
    u, v = np.meshgrid(np.linspace(0, width - 1, 40), np.linspace(0, height - 1, 30))
    pixels = np.stack([u.ravel(), v.ravel()], axis=1)
    valid = camera.is_valid(pixels)
    assert valid.dtype == bool and valid.shape == (len(pixels),) and valid.sum() > 100
    bearings = camera.pixel_to_bearing(pixels[valid])
    assert bearings.shape == (valid.sum(), 3)
    assert np.allclose(np.linalg.norm(bearings, axis=1), 1.0)
    assert np.allclose(camera.bearing_to_pixel(bearings), pixels[valid], atol=1e-3)
    # One point in, one point out.
    centre = np.array([width / 2, height / 2])
    assert camera.pixel_to_bearing(centre).shape == (3,)
    assert camera.bearing_to_pixel(camera.pixel_to_bearing(centre)) == pytest.approx(centre, abs=1e-3)
    assert camera.is_valid(centre) is True


def test_unprojectable_rays_are_nan_and_cameras_save_and_resize(tmp_path):
    pinhole = mdbrief.load_camera(str(PINHOLE_CAMERA))
    pixels = pinhole.bearing_to_pixel([[0, 0, 1], [0, 0, -1], [0, 0, 0]])
    assert np.all(np.isfinite(pixels[0])) and np.all(np.isnan(pixels[1:]))
    assert pinhole.model == "pinhole" and (pinhole.width, pinhole.height) == (754, 480)

    fisheye = mdbrief.load_camera(str(FISHEYE_CAMERA))
    fisheye.save(str(tmp_path / "copy.yaml"))
    copy = mdbrief.load_camera(str(tmp_path / "copy.yaml"))
    probe = np.array([[100.0, 200.0], [377.0, 240.0], [600.0, 50.0]])
    assert np.allclose(copy.pixel_to_bearing(probe), fisheye.pixel_to_bearing(probe), atol=1e-9)
    assert copy.to_yaml() == fisheye.to_yaml()
    half = fisheye.resized((377, 240))
    assert half.image_size == (377, 240)
    assert np.allclose(half.pixel_to_bearing(probe / 2 - 0.25), fisheye.pixel_to_bearing(probe), atol=1e-6)


def test_camera_errors_are_python_exceptions(tmp_path):
    with pytest.raises(FileNotFoundError):
        mdbrief.load_camera(str(tmp_path / "missing.yaml"))
    # Something that is not a file is named for what it is, and a FIFO is never opened (it would block).
    with pytest.raises(IsADirectoryError, match="is a folder"):
        mdbrief.load_camera(str(tmp_path))
    os.mkfifo(tmp_path / "fifo.yaml")
    with pytest.raises(OSError, match="is a FIFO"):
        mdbrief.load_camera(str(tmp_path / "fifo.yaml"))
    os.symlink("loop.yaml", tmp_path / "loop.yaml")
    with pytest.raises(OSError, match="symbolic links"):
        mdbrief.load_pattern(str(tmp_path / "loop.yaml"))
    (tmp_path / "bad.yaml").write_text("model: kannala_brandt\nwidth: 640\nheight: 480\nfx: 300\nfy: 300\n"
                                       "cx: 320\ncy: 240\nk1: 1e30\nk2: 0\nk3: 0\nk4: 0\n")
    with pytest.raises(ValueError, match="k1"):
        mdbrief.load_camera(str(tmp_path / "bad.yaml"))
    camera = mdbrief.load_camera(str(FISHEYE_CAMERA))
    with pytest.raises(ValueError, match=r"shape \(N, 2\)"):
        camera.pixel_to_bearing(np.zeros((4, 3)))
    with pytest.raises(ValueError, match=r"shape \(N, 3\)"):
        camera.bearing_to_pixel(np.zeros(2))


def test_builtin_and_json_test_sets(tmp_path, camera, image_pair):
    names = mdbrief.patterns()
    assert mdbrief.default_pattern() in names and "brief_random_512" in names
    builtin = mdbrief.load_pattern("brief_random_512")
    assert len(builtin) == 512 and builtin.tests.shape == (512, 4) and builtin.tests.dtype == np.int8
    assert builtin.tests.min() >= -16 and builtin.tests.max() <= 15
    assert len(builtin.first(64)) == 64
    with pytest.raises(ValueError, match="32"):
        builtin.first(33)

    # The same tests from a JSON file describe exactly as the compiled-in set.
    path = tmp_path / "copy.json"
    path.write_text(json.dumps({"name": "copy", "tests": builtin.tests.tolist()}))
    loaded = mdbrief.load_pattern(str(path))
    assert loaded.name == "copy" and np.array_equal(loaded.tests, builtin.tests)
    a = mdbrief.MdBrief(camera, pattern="brief_random_512", nfeatures=200).detect_and_compute(image_pair[0])
    b = mdbrief.MdBrief(camera, pattern=str(path), nfeatures=200).detect_and_compute(image_pair[0])
    assert np.array_equal(a[1], b[1])

    with pytest.raises(FileNotFoundError):
        mdbrief.load_pattern(str(tmp_path / "missing.json"))
    (tmp_path / "bad.json").write_text('{"name": "bad", "tests": [[0, 0, 99, 0]]}')
    with pytest.raises(ValueError, match="bad.json"):
        mdbrief.load_pattern(str(tmp_path / "bad.json"))


def small_image_folder(tmp_path):
    folder = tmp_path / "images"
    folder.mkdir()
    for name in ["box_in_scene.png", "building.jpg", "aero1.jpg", "HappyFish.jpg"]:
        if not (OPENCV_DOC / name).exists():
            pytest.skip(f"opencv-doc photo {OPENCV_DOC / name} is not installed")
        (folder / name).write_bytes((OPENCV_DOC / name).read_bytes())
    return folder


def test_training_is_deterministic_and_writes_what_the_tool_writes(tmp_path):
    images = small_image_folder(tmp_path)
    (tmp_path / "out").mkdir()
    first = mdbrief.train(images=str(images), patches=800, tests=64, seed=3, name="tiny_64", out=str(tmp_path / "out"))
    again = mdbrief.train(images=[images], patches=800, tests=64, seed=3, name="tiny_64")
    assert first.name == "tiny_64" and len(first) == 64
    assert np.array_equal(first.tests, again.tests)
    assert first.training_images and first.training_images == again.training_images
    header = (tmp_path / "out" / "tiny_64.hpp").read_text()
    # The default criterion is the shipped sets' (configs/training/*.toml).
    assert "--seed 3 --counterparts 1 --selection separation --tests 64 --name tiny_64" in header
    assert np.array_equal(mdbrief.load_pattern(str(tmp_path / "out" / "tiny_64.json")).tests, first.tests)
    # The trained set saves as the trainer's JSON and describes as a pattern.
    again.save(tmp_path / "saved.json")
    assert np.array_equal(mdbrief.load_pattern(tmp_path / "saved.json").tests, first.tests)
    assert mdbrief.load_pattern(tmp_path / "saved.json").training_images == first.training_images
    assert mdbrief.MdBrief(None, descriptor="brief", bits=64, pattern=again).test_set.name == "tiny_64"
    other = mdbrief.train(images=str(images), patches=800, tests=64, seed=4)
    assert not np.array_equal(other.tests, first.tests)


def test_training_errors_raise(tmp_path):
    with pytest.raises(FileNotFoundError):
        mdbrief.train(images=str(tmp_path / "missing"))
    images = small_image_folder(tmp_path)
    with pytest.raises(ValueError, match="detector"):
        mdbrief.train(images=str(images), detector="sift", patches=800, tests=64)
    with pytest.raises(ValueError, match="out"):
        mdbrief.train(images=str(images), make_default=True)
