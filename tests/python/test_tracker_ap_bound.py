"""scripts/tracker_ap_bound.py: the per-pair best AP of the tracker benchmark's pipelines."""
import importlib.util

import pytest

from conftest import SOURCE

spec = importlib.util.spec_from_file_location("tracker_ap_bound", SOURCE / "scripts/tracker_ap_bound.py")
bound = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bound)

HEADER = "group,sequence,image_a,image_b,pipeline,ratio,average_precision\n"
# Two pairs, two ratios each (AP is per pair); A wins pair 1-2, B pair 1-3 and the poster pair
# shares image b with the first but is another group, where Z has AP 0 (no ratio to it).
ROWS = [
    ("oxford", "graf", 1, 2, "A", 0.5, 0.8), ("oxford", "graf", 1, 2, "A", 0.8, 0.8),
    ("oxford", "graf", 1, 2, "B", 0.8, 0.6), ("oxford", "graf", 1, 3, "A", 0.8, 0.2),
    ("oxford", "graf", 1, 3, "B", 0.8, 0.4), ("poster-dev", "graf", 1, 2, "A", 0.8, 0.1),
    ("poster-dev", "graf", 1, 2, "Z", 0.8, 0.0),
]


@pytest.fixture
def pairs(tmp_path):
    path = tmp_path / "tracker_pairs.csv"
    path.write_text(HEADER + "".join(",".join(map(str, r)) + "\n" for r in ROWS))
    return path


def test_the_bound_takes_each_pairs_best_pipeline(pairs):
    table = bound.read_ap(pairs, "oxford")
    assert sorted(table) == [("graf", "1", "2"), ("graf", "1", "3")]
    assert bound.pipeline_means(table) == pytest.approx({"A": 0.5, "B": 0.5})
    assert bound.best_of_all(table) == pytest.approx((0.8 + 0.4) / 2)
    assert bound.best_of_all(table, {("graf", "1", "3")}) == pytest.approx((0.8 + 1.0) / 2)


def test_prints_the_ratios_to_the_reference(pairs, capsys):
    assert bound.main([str(pairs), "--reference", "B", "--perfect", "graf:1-3"]) == 0
    out = capsys.readouterr().out
    assert "best of all, per pair                    0.600  1.20x" in out
    assert "0.900  1.80x" in out


@pytest.mark.parametrize("args, message", [
    (["--reference", "AKAZE"], "no pipeline 'AKAZE' with a mean AP above 0; there are: A, B"),
    (["--group", "poster-dev", "--reference", "Z"], "no pipeline 'Z' with a mean AP above 0"),
    (["--group", "rendered"], "has no pair of group 'rendered'"),
    (["--reference", "A", "--perfect", "graf:1-9"], "--perfect graf:1-9: no such pair"),
])
def test_bad_arguments_exit_2_and_say_why(pairs, capsys, args, message):
    assert bound.main([str(pairs), *args]) == 2
    assert message in capsys.readouterr().err


def test_a_missing_table_exits_2(tmp_path, capsys):
    assert bound.main([str(tmp_path / "none.csv")]) == 2
    assert "none.csv" in capsys.readouterr().err
