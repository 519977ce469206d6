"""scripts/stereo_pose_check.py: the correction of a stated stereo pose that the matches call for."""
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import SOURCE

SCRIPT = SOURCE / "scripts/stereo_pose_check.py"
MATCHES_HEADER = "set,image_a,image_b,pipeline,ratio,a_x,a_y,a_z,b_x,b_y,b_z,b_px_per_radian,residual_px\n"
POSES_HEADER = "set,image_a,image_b,r00,r01,r02,r10,r11,r12,r20,r21,r22,t_x,t_y,t_z\n"
PX_PER_RADIAN = 400.0


def rotation(vector):
    angle = np.linalg.norm(vector)
    k = vector / angle
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross


def write_set(folder, turn_mrad, noise_px):
    """A 12 cm stereo pair whose stated pose is the true one turned by turn_mrad about a's x axis
    (across the baseline); two pipelines' matches of points 1-5 m away, "REF" exact up to
    noise_px, "OTHER" with 5 times the noise. Returns the stated pose."""
    rng = np.random.default_rng(4)
    true_r, true_t = np.eye(3), np.array([0.12, 0.0, 0.0])  # X_a = R X_b + t
    stated_r = rotation(np.array([turn_mrad * 1e-3, 0.0, 0.0])) @ true_r
    normal_of = lambda a: a @ (np.array([[0, -true_t[2], true_t[1]], [true_t[2], 0, -true_t[0]],
                                         [-true_t[1], true_t[0], 0]]) @ stated_r)
    rows = []
    for pipeline, noise in (("REF", noise_px), ("OTHER", 5 * noise_px)):
        points = np.column_stack([rng.uniform(-1.5, 1.5, 400), rng.uniform(-1, 1, 400), rng.uniform(1, 5, 400)])
        a = points / np.linalg.norm(points, axis=1, keepdims=True)
        in_b = (points - true_t) @ true_r  # X_b = R^T (X_a - t)
        in_b += rng.normal(0, noise / PX_PER_RADIAN, in_b.shape) * np.linalg.norm(in_b, axis=1, keepdims=True)
        b = in_b / np.linalg.norm(in_b, axis=1, keepdims=True)
        normal = normal_of(a)
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        residual = np.arcsin(np.sum(b * normal, axis=1)) * PX_PER_RADIAN
        for k in range(len(a)):
            rows.append(",".join(map(str, ["pair", "a.png", "b.png", pipeline, 0.8, *a[k], *b[k], PX_PER_RADIAN,
                                           residual[k]])))
    (folder / "stereo_matches.csv").write_text(MATCHES_HEADER + "\n".join(rows) + "\n")
    (folder / "stereo_poses.csv").write_text(
        POSES_HEADER + ",".join(map(str, ["pair", "a.png", "b.png", *stated_r.ravel(), *true_t])) + "\n")


def run(folder, *args):
    return subprocess.run([sys.executable, str(SCRIPT), str(folder), "--set", "pair", *args], capture_output=True,
                          text=True, timeout=120)


# The stated pose turned by 1 mrad puts every match 0.4 px to one side of its plane; the correction
# fitted to one pipeline's matches finds the turn, and under it both pipelines' residuals are their
# noise again, the less noisy one the smaller.
def test_it_finds_the_turn_the_stated_pose_is_off_by(tmp_path):
    write_set(tmp_path, turn_mrad=1.0, noise_px=0.02)
    result = run(tmp_path, "--reference", "REF")
    assert result.returncode == 0, result.stderr
    turn = float(re.search(r"turn ([0-9.]+) mrad", result.stdout).group(1))
    assert turn == pytest.approx(1.0, abs=0.05), result.stdout
    table = {m.group(1): [float(x) for x in m.groups()[1:]] for m in re.finditer(
        r"^  (REF|OTHER)\s+\d+\s+([0-9.]+) / [0-9.]+ / ([-+0-9.]+)\s+([0-9.]+) / [0-9.]+ / ([-+0-9.]+)",
        result.stdout, re.M)}
    assert set(table) == {"REF", "OTHER"}, result.stdout
    for stated_median, stated_side, corrected_median, corrected_side in table.values():
        assert abs(stated_side) > 0.2 and stated_median > 0.2, result.stdout
        assert abs(corrected_side) < 0.02, result.stdout
    assert table["REF"][2] < 0.03 < table["OTHER"][2] < 0.15, result.stdout


def test_without_the_matches_file_it_says_how_to_make_it(tmp_path):
    result = run(tmp_path)
    assert result.returncode == 2
    assert "--stereo-matches" in result.stderr


def test_a_reference_pipeline_without_matches_is_refused(tmp_path):
    write_set(tmp_path, turn_mrad=0.5, noise_px=0.02)
    result = run(tmp_path, "--reference", "SIFT")
    assert result.returncode == 2
    assert "no right matches of SIFT" in result.stderr


# A damaged file is named with its line, and nothing is fitted: exit 2, never a traceback.
@pytest.mark.parametrize("damage, message", [
    (lambda text: text.replace(text.splitlines()[3].split(",")[5], "abc", 1), r"stereo_matches.csv:4: a_x, .* must be numbers"),
    (lambda text: text.replace(text.splitlines()[3].split(",")[12], "nan", 1), r"stereo_matches.csv:4: a_x, .* must be finite"),
    (lambda text: text.replace("a.png", "c.png"), r"stereo_matches.csv:2: pair c.png, b.png has no pose"),
    (lambda text: "", r"stereo_matches.csv: empty, no header"),
])
def test_a_damaged_matches_file_is_refused_with_its_line(tmp_path, damage, message):
    write_set(tmp_path, turn_mrad=0.5, noise_px=0.02)
    path = tmp_path / "stereo_matches.csv"
    path.write_text(damage(path.read_text()))
    result = run(tmp_path, "--reference", "REF")
    assert result.returncode == 2, result.stdout + result.stderr
    assert re.search(message, result.stderr), result.stderr
    assert "Traceback" not in result.stderr
