"""The tools run as processes, where the shell's limits apply: under `ulimit -f` with SIGXFSZ at
its default (which kills the writer and left a hidden temporary, issue 29), a write past the limit
is a failed write: exit 2 naming the file, the previous output unchanged, no temporary."""
import os
import pathlib
import resource
import subprocess

import numpy as np
import pytest

from conftest import FISHEYE_CAMERA


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
