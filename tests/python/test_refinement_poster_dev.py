"""scripts/refinement_poster_dev.py: refinement against poster-dev's ground truth, by sigma."""
import os
import re

import pytest

from conftest import DATA, run_data_script


# The default smoothing places the refined points nearer the truth than the descriptors' sigma 2,
# and both nearer than the keypoints (measured: 0.110, 0.179 and 0.347 px median).
def test_the_default_sigma_refines_closer_to_the_truth_than_sigma_2():
    if not os.path.isfile(os.path.join(DATA, "fisheye/poster-dev/ground_truth.json")):
        pytest.skip(f"no poster-dev under {DATA}")
    result = run_data_script("refinement_poster_dev.py", DATA, "--sigmas", "0.6", "2")
    assert result.returncode == 0, result.stderr
    medians = {name: float(value) for name, value in
               re.findall(r"^  (keypoints|refined sigma [0-9.]+)\s+median ([0-9.]+) px", result.stdout, re.M)}
    assert set(medians) == {"keypoints", "refined sigma 0.6", "refined sigma 2"}, result.stdout
    assert medians["refined sigma 0.6"] < 0.85 * medians["refined sigma 2"], result.stdout
    assert medians["refined sigma 2"] < 0.85 * medians["keypoints"], result.stdout
