"""Issue 19's Python API: cameras from parameters and from OpenCV's K / D, test sets passed and
saved as objects, pickling, a clean namespace and errors in Python's spelling."""
import pickle

import cv2
import numpy as np
import pytest

import mdbrief
from conftest import FISHEYE_CAMERA, SOURCE

CAMERA_FILES = sorted((SOURCE / "configs/cameras").glob("*.yaml")) + sorted(
    p for p in (SOURCE / "tests/data/camera_formats").glob("*") if p.is_file())


def loadable_cameras():
    """Every camera of the example and sample files, multi-camera files by camera_id."""
    cameras = {}
    for path in CAMERA_FILES:
        try:
            cameras[path.name] = mdbrief.load_camera(path)
            continue
        except ValueError as error:
            if "image_size=" in str(error):  # K and D alone (opencv_kd_fisheye.yaml): size and model from the caller
                cameras[path.name] = mdbrief.load_camera(path, image_size=(752, 480), opencv_model="fisheye")
                continue
            if "camera_id=" not in str(error):
                raise
        for camera_id in [f"cam{i}" for i in range(8)] + [str(i) for i in range(1, 8)] + ["0"]:
            try:
                cameras[f"{path.name}:{camera_id}"] = mdbrief.load_camera(path, camera_id=camera_id)
            except ValueError:
                pass
    return cameras


def grid(camera):
    xs, ys = np.meshgrid(np.linspace(0, camera.width - 1, 23), np.linspace(0, camera.height - 1, 17))
    return np.stack([xs.ravel(), ys.ravel()], axis=1)


def same_camera(a, b):
    assert (a.model, a.image_size) == (b.model, b.image_size)
    assert a.to_yaml() == b.to_yaml()
    pixels = grid(a)
    np.testing.assert_array_equal(a.pixel_to_bearing(pixels), b.pixel_to_bearing(pixels))


def test_every_model_is_built_from_its_yaml_keywords():
    cameras = loadable_cameras()
    assert set(mdbrief.camera_models()) <= {c.model for c in cameras.values()}
    for name, camera in cameras.items():
        # Optional keys (radtan's k4..k6, max_radius) appear only when the camera has them.
        assert set(camera.parameters) <= set(mdbrief.camera_models()[camera.model]), name
        same_camera(mdbrief.Camera(camera.model, camera.width, camera.height, **camera.parameters), camera)


def test_camera_from_opencv_fisheye_calibration_arrays():
    path = SOURCE / "tests/data/camera_formats/opencv_fisheye.yaml"
    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    K = storage.getNode("camera_matrix").mat()
    D = storage.getNode("distortion_coefficients").mat().reshape(4, 1)  # cv2.fisheye.calibrate's shape
    size = (int(storage.getNode("image_width").real()), int(storage.getNode("image_height").real()))
    same_camera(mdbrief.Camera.from_opencv(K, D, size), mdbrief.load_camera(path))
    standard = SOURCE / "tests/data/camera_formats/opencv_standard.yaml"
    storage = cv2.FileStorage(str(standard), cv2.FILE_STORAGE_READ)
    size = (int(storage.getNode("image_width").real()), int(storage.getNode("image_height").real()))
    same_camera(mdbrief.Camera.from_opencv(storage.getNode("camera_matrix").mat(),
                                           storage.getNode("distortion_coefficients").mat(), size, fisheye=False),
                mdbrief.load_camera(standard))
    with pytest.raises(ValueError, match="K"):
        mdbrief.Camera.from_opencv(np.eye(2), D, size)


def test_camera_errors_name_python_keywords():
    camera = mdbrief.load_camera(SOURCE / "configs/cameras/kannala_brandt_example.yaml")
    parameters = dict(camera.parameters)
    missing = dict(parameters)
    missing.pop("cx")
    with pytest.raises(ValueError, match="keyword 'cx'"):
        mdbrief.Camera(camera.model, camera.width, camera.height, **missing)
    with pytest.raises(ValueError, match="focal"):
        mdbrief.Camera(camera.model, camera.width, camera.height, **parameters, focal=1.0)
    with pytest.raises(TypeError, match="'cx'"):
        mdbrief.Camera(camera.model, camera.width, camera.height, **{**parameters, "cx": "middle"})
    with pytest.raises(ValueError, match="kannala_brandt"):
        mdbrief.Camera("fisheye", 640, 480, fx=1.0)
    with pytest.raises(ValueError, match="format"):
        mdbrief.load_camera(FISHEYE_CAMERA, format="matlab")
    with pytest.raises(ValueError, match=r"Camera\.resized"):
        camera.resized((0, 480))
    small = np.zeros((camera.height // 2, camera.width // 2), np.uint8)
    with pytest.raises(ValueError, match=r"camera\.resized") as error:
        mdbrief.MdBrief(camera).detect(small)
    assert "::" not in str(error.value)


def test_cameras_and_features_pickle(image_pair):
    for camera in loadable_cameras().values():
        same_camera(pickle.loads(pickle.dumps(camera)), camera)
    camera = mdbrief.load_camera(FISHEYE_CAMERA)
    feature = mdbrief.MdBrief(camera, preset="matching", nfeatures=300, bits=256)
    copy = pickle.loads(pickle.dumps(feature))
    assert copy.options == feature.options
    same_camera(copy.camera, camera)
    first, _ = image_pair
    kp1, d1, m1 = feature.detect_and_compute(first)
    kp2, d2, m2 = copy.detect_and_compute(first)
    assert [k.pt for k in kp1] == [k.pt for k in kp2]
    np.testing.assert_array_equal(d1, d2)
    np.testing.assert_array_equal(m1, m2)
    brief = pickle.loads(pickle.dumps(mdbrief.MdBrief(None, descriptor="brief", bits=128)))
    assert brief.camera is None and brief.options["descriptor"] == "brief" and brief.descriptor_size == 16


def test_test_sets_are_passed_saved_and_pickled(tmp_path, image_pair):
    camera = mdbrief.load_camera(FISHEYE_CAMERA)
    first, _ = image_pair
    default = mdbrief.load_pattern(mdbrief.default_pattern())
    by_name = mdbrief.MdBrief(camera, nfeatures=200)
    by_object = mdbrief.MdBrief(camera, nfeatures=200, pattern=default)
    assert by_object.options["pattern"] == default.name
    np.testing.assert_array_equal(by_name.detect_and_compute(first)[1], by_object.detect_and_compute(first)[1])

    # A set of our own (the default's tests reversed): saved, loaded and pickled it describes
    # the same, and differently from the default.
    own = mdbrief.ComparisonSet("reversed_set", default.tests[::-1])
    unpickled = pickle.loads(pickle.dumps(own))
    assert unpickled.name == own.name and unpickled.training_images == own.training_images
    np.testing.assert_array_equal(unpickled.tests, own.tests)
    path = tmp_path / "reversed_set.json"
    own.save(path)
    loaded = mdbrief.load_pattern(path)
    assert loaded.name == "reversed_set"
    np.testing.assert_array_equal(loaded.tests, own.tests)
    np.testing.assert_array_equal(own.tests, default.tests[::-1])
    from_object = mdbrief.MdBrief(camera, nfeatures=200, pattern=own)
    from_file = mdbrief.MdBrief(camera, nfeatures=200, pattern=str(path))
    d_object = from_object.detect_and_compute(first)[1]
    np.testing.assert_array_equal(d_object, from_file.detect_and_compute(first)[1])
    assert not np.array_equal(d_object, by_name.detect_and_compute(first)[1])
    # Pickled with its tests: the file is not needed to unpickle.
    blob = pickle.dumps(from_file)
    path.unlink()
    np.testing.assert_array_equal(pickle.loads(blob).detect_and_compute(first)[1], d_object)
    assert mdbrief.load_pattern(own) is not None

    with pytest.raises(ValueError, match="Not A Name"):
        mdbrief.ComparisonSet("Not A Name", default.tests).save(tmp_path / "bad.json")
    assert not (tmp_path / "bad.json").exists()
    with pytest.raises(ValueError, match="outside"):
        mdbrief.ComparisonSet("far", [[0, 0, 16, 0]])
    with pytest.raises(ValueError, match="4 ints"):
        mdbrief.ComparisonSet("short", [[0, 0, 1]])


def test_test_set_is_comparison_sets_deprecated_name():
    """Issue 46: the class was renamed ComparisonSet; TestSet, its name in 0.2, is the same class
    object, so isinstance checks, pickles and code written for 0.2 keep working."""
    assert mdbrief.TestSet is mdbrief.ComparisonSet
    assert mdbrief.ComparisonSet.__name__ == "ComparisonSet"
    assert "TestSet" in mdbrief.ComparisonSet.__doc__
    made = mdbrief.TestSet("old_name", [[0, 0, 1, 1]] * 32)
    assert isinstance(made, mdbrief.ComparisonSet)
    assert isinstance(pickle.loads(pickle.dumps(made)), mdbrief.TestSet)


def test_module_holds_only_its_own_names():
    public = {name for name in dir(mdbrief) if not name.startswith("_")}
    assert public == set(mdbrief.__all__)
    assert "cv2" not in public


def test_version_is_the_projects():
    # The version the project's CMakeLists.txt declares, as MAJOR.MINOR.PATCH.
    import re
    cmake = (SOURCE / "CMakeLists.txt").read_text()
    declared = re.search(r"project\(mdbrief VERSION (\d+\.\d+\.\d+)", cmake).group(1)
    assert mdbrief.__version__ == declared
