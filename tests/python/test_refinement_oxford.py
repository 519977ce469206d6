"""scripts/refinement_oxford.py: refinement against the Oxford sequences' homographies."""
import os
import re

import cv2
import numpy as np
import pytest

from conftest import DATA, run_data_script


# Refined points lie nearer the homographies' truth than the keypoints, most where the views turn
# a slanted plane (graf); most right matches are refined (measured: 0.370 -> 0.213 px median over
# all, graf 0.562 -> 0.234, 7352 of 9613 refined).
def test_refinement_moves_the_points_nearer_the_truth():
    if not os.path.isfile(os.path.join(DATA, "oxford-affine/graf/H1to2p")):
        pytest.skip(f"no Oxford sequences under {DATA}")
    result = run_data_script("refinement_oxford.py", DATA)
    assert result.returncode == 0, result.stderr
    rows = {m.group(1): [float(x) for x in m.groups()[1:]] for m in re.finditer(
        r"^(\w+)\s+(\d+)\s+(\d+)\s+([0-9.]+) / ([0-9.]+)\s+([0-9.]+) / ([0-9.]+)$", result.stdout, re.M)}
    assert set(rows) == {"bikes", "boat", "graf", "leuven", "trees", "ubc", "all"}, result.stdout
    right, refined, before, _, after, _ = rows["all"]
    assert refined > 0.7 * right, result.stdout
    assert after < 0.7 * before, result.stdout
    assert rows["graf"][4] < 0.5 * rows["graf"][2], result.stdout


# Damaged data is named and refused (a non-zero exit, no traceback): images that cannot be read,
# a homography file that holds no 3 x 3 matrix.
@pytest.mark.parametrize("homography, message", [
    (None, "cannot read the images of"),
    ("1 2\n", "H1to2p is no 3 x 3 matrix of finite numbers"),
    ("1 0 0\n0 1 0\n0 0 nan\n", "H1to2p is no 3 x 3 matrix of finite numbers"),
])
def test_damaged_data_is_refused_with_its_file(tmp_path, homography, message):
    folder = tmp_path / "oxford-affine/bikes"
    folder.mkdir(parents=True)
    (tmp_path / "oxford-affine/graf").mkdir()
    (tmp_path / "oxford-affine/graf/H1to2p").write_text("1 0 0\n0 1 0\n0 0 1\n")
    if homography is not None:
        rng = np.random.default_rng(1)
        for k in range(1, 7):
            cv2.imwrite(str(folder / f"img{k}.png"), rng.integers(0, 255, (240, 320), dtype=np.uint8))
        (folder / "H1to2p").write_text(homography)
    result = run_data_script("refinement_oxford.py", tmp_path)
    assert result.returncode != 0, result.stdout
    assert message in result.stderr, result.stderr
    assert "Traceback" not in result.stderr
