"""Fixtures of the Python tests. ctest sets PYTHONPATH to <build>/python, MDBRIEF_SOURCE_DIR and
MDBRIEF_CLI (the C++ `mdbrief` tool, the reference the bindings are compared with).

As in the C++ tests (tests/test_data.hpp), MDBRIEF_OPENCV_DOC names the opencv-doc photos' folder,
and under MDBRIEF_NO_SKIPS=1 (set by CI, .ci/run) every skip is a failure: a machine without the
photos, or a run outside ctest, must not pass by skipping."""
import os
import pathlib
import subprocess
import sys

import cv2
import pytest

SOURCE = pathlib.Path(os.environ.get("MDBRIEF_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
OPENCV_DOC = pathlib.Path(os.environ.get("MDBRIEF_OPENCV_DOC") or "/usr/share/doc/opencv-doc/examples/data")
SKIPS_FAIL = os.environ.get("MDBRIEF_NO_SKIPS") == "1"
# The shared data (../shared/data beside the checkout, or MDBRIEF_DATA).
DATA = os.environ.get("MDBRIEF_DATA", str(SOURCE.parent / "shared/data"))


def run_data_script(name, data, *args):
    """scripts/<name> run with MDBRIEF_DATA set to `data`."""
    return subprocess.run([sys.executable, str(SOURCE / "scripts" / name), *args], capture_output=True, text=True,
                          timeout=300, env=dict(os.environ, MDBRIEF_DATA=str(data)))


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    report = (yield).get_result()
    if SKIPS_FAIL and report.skipped:
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        report.outcome = "failed"
        report.longrepr = f"{reason} (a failure, not a skip: MDBRIEF_NO_SKIPS=1)"
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
