"""The scripts that read ../shared/data: without it each says so in one line and exits 0."""
import pytest

from conftest import run_data_script


@pytest.mark.parametrize("script, needs", [("refinement_poster_dev.py", "fisheye/poster-dev/ground_truth.json"),
                                           ("refinement_oxford.py", "oxford-affine/graf/H1to2p")])
def test_without_the_data_it_says_so_and_exits_0(tmp_path, script, needs):
    result = run_data_script(script, tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == f"{script}: skipped, no {tmp_path}/{needs}"
