"""scripts/refinement_oxford.py: refinement against the Oxford sequences' homographies."""
import os
import re

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
