"""The user guide's Python walk-through (examples/guide/first_steps.py, shown part for part in
docs/guide/README.md) runs to its end on the synthetic scene: its matches are right, guided
matching keeps them, a trained set describes, and the vocabulary finds the revisited place."""
import os
import subprocess
import sys

from conftest import FISHEYE_CAMERA, SOURCE


def test_the_guides_python_example_runs_and_checks_what_it_shows(tmp_path):
    result = subprocess.run(
        [sys.executable, str(SOURCE / "examples/guide/first_steps.py"), str(FISHEYE_CAMERA),
         str(SOURCE / "configs/vocabularies/tracking_k10_L4.mdbvoc"), str(tmp_path)],
        capture_output=True, text=True, env=dict(os.environ), timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "correct" in result.stdout and "query: [(2," in result.stdout
    assert (tmp_path / "my_tests_64.json").exists()
