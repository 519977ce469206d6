"""Processes and their signals (issue 29). The tools under `ulimit -f` with SIGXFSZ at its default
(which killed the writer and left a hidden temporary): a write past the limit is a failed write,
exit 2 naming the file, the previous output unchanged, no temporary. The module under Ctrl-C:
KeyboardInterrupt, at once and without a crash, also in the middle of a long call."""
import os
import pathlib
import resource
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from conftest import FISHEYE_CAMERA, OPENCV_DOC


def limited(limit_bytes):
    """preexec_fn: a file size limit in the child. subprocess restores SIGXFSZ to its default there."""
    def apply():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, resource.RLIM_INFINITY))
    return apply


def tool(name):
    build = os.environ.get("MDBRIEF_BUILD_DIR")
    found = sorted(pathlib.Path(build).glob(f"*/{name}")) if build else []
    if not found:
        pytest.skip(f"{name} not found under MDBRIEF_BUILD_DIR: run through ctest")
    return str(found[0])


def hidden(folder):
    return sorted(p.name for p in pathlib.Path(folder).iterdir() if p.name.startswith("."))


def test_the_mdbrief_tool_under_a_file_size_limit_exits_2_and_keeps_the_output(cli, tmp_path):
    out = tmp_path / "camera.yaml"
    out.write_text("previous: 1\n")
    r = subprocess.run([cli, "camera", "convert", str(FISHEYE_CAMERA), "-o", str(out)], capture_output=True,
                       text=True, preexec_fn=limited(64))
    assert r.returncode == 2, r.stderr
    assert str(out) in r.stderr and "File too large" in r.stderr
    assert out.read_text() == "previous: 1\n"
    assert hidden(tmp_path) == []


def test_the_vocabulary_trainer_under_a_file_size_limit_exits_2_and_keeps_the_output(tmp_path):
    trainer = tool("mdbrief-train-vocabulary")
    rng = np.random.default_rng(3)
    inputs = []
    for i in range(2):
        path = tmp_path / f"d{i}.npy"
        np.save(path, rng.integers(0, 256, (200, 32), dtype=np.uint8))
        inputs.append(str(path))
    out = tmp_path / "v.mdbvoc"
    out.write_bytes(b"previous")
    r = subprocess.run([trainer, "--descriptors", *inputs, "--plain", "--branching", "4", "--depth", "2", "--out",
                        str(out)], capture_output=True, text=True, preexec_fn=limited(128))
    assert r.returncode == 2, r.stderr
    assert str(out) in r.stderr
    assert out.read_bytes() == b"previous"
    assert hidden(tmp_path) == []


def interrupted(code, delay):
    """Runs code in a child Python whose SIGINT raises KeyboardInterrupt, sends SIGINT `delay` s after
    the child prints "go"; returns the exit code, the child's other output and the seconds from the
    signal to the child's answer."""
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    answer, sent, answered = "", None, None
    for line in child.stdout:
        if line.startswith("go"):
            time.sleep(delay)
            sent = time.monotonic()
            child.send_signal(signal.SIGINT)
        else:
            answer, answered = line.strip(), time.monotonic()
    child.wait(60)
    return child.returncode, answer + child.stderr.read(), (answered or time.monotonic()) - (sent or 0.0)


INTERRUPTIBLE = """
import mdbrief, numpy as np
{setup}
print("go", flush=True)
try:
    {call}
    print("finished")
except KeyboardInterrupt:
    print("interrupted")
"""


def test_ctrl_c_during_the_first_match_raises_keyboard_interrupt_without_a_crash():
    """The first match probes cv2.DMatch's layout after the native matching; a signal that came
    during the matching made cv2's constructor crash (exit 139)."""
    code = INTERRUPTIBLE.format(setup="d = np.random.default_rng(1).integers(0, 256, (30000, 64), np.uint8)",
                                call="mdbrief.match(d, d)")
    for _ in range(2):
        returncode, output, _ = interrupted(code, 0.2)
        assert returncode == 0, output
        assert output in ("interrupted", "finished"), output


def test_ctrl_c_stops_a_long_training_at_once(tmp_path):
    """Training checks Python's signals between its batches: KeyboardInterrupt came 32 s after SIGINT."""
    names = ["box_in_scene.png", "building.jpg", "aero1.jpg", "HappyFish.jpg"]
    if not all((OPENCV_DOC / name).exists() for name in names):
        pytest.skip("opencv-doc photos not installed")
    for name in names:
        (tmp_path / name).write_bytes((OPENCV_DOC / name).read_bytes())
    code = INTERRUPTIBLE.format(setup="", call=f"mdbrief.train(images={str(tmp_path)!r}, patches=20000, tests=512, "
                                               "seed=1)")
    returncode, output, seconds = interrupted(code, 1.0)
    assert returncode == 0 and output == "interrupted", output
    assert seconds < 1.0, f"KeyboardInterrupt {seconds:.1f} s after SIGINT"
