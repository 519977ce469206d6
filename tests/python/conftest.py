"""Fixtures of the Python tests. ctest sets PYTHONPATH to <build>/python, MDBRIEF_SOURCE_DIR and
MDBRIEF_CLI (the C++ `mdbrief` tool, the reference the bindings are compared with)."""
import os
import pathlib

import cv2
import pytest

SOURCE = pathlib.Path(os.environ.get("MDBRIEF_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
OPENCV_DOC = pathlib.Path("/usr/share/doc/opencv-doc/examples/data")
FISHEYE_CAMERA = SOURCE / "configs/cameras/lafida_fisheye0.yaml"
PINHOLE_CAMERA = SOURCE / "configs/cameras/pinhole_example.yaml"


def doc_image(name, size):
    path = OPENCV_DOC / name
    if not path.exists():
        pytest.skip(f"opencv-doc photo {path} is not installed (scripts/setup-deps.sh installs it)")
    return cv2.resize(cv2.imread(str(path)), size, interpolation=cv2.INTER_AREA)


@pytest.fixture(scope="session")
def camera():
    import mdbrief
    return mdbrief.load_camera(str(FISHEYE_CAMERA))


@pytest.fixture(scope="session")
def image_pair(camera):
    """Two views of the same scene at the fisheye calibration's size (BGR)."""
    return doc_image("graf1.png", camera.image_size), doc_image("graf3.png", camera.image_size)


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("MDBRIEF_CLI")
    if not path or not pathlib.Path(path).exists():
        pytest.skip("MDBRIEF_CLI (the mdbrief tool) is not set: run through ctest")
    return path
