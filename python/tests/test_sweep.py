"""python3 -m ellipsekit.sweep on Dask distributed: every combination's counts equal to
`ellipsekit eval` with the same options, the best row, images left out, usage errors.

40 generated 640x480 scenes (seed 3); LocalClusters of 2 worker processes.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

import pytest

from conftest import REPO, run_cli


def sweep(*args, timeout=240):
    return subprocess.run([sys.executable, "-m", "ellipsekit.sweep", *args], capture_output=True, text=True,
                          cwd=REPO, timeout=timeout)


def eval_counts(dataset, *options):
    out = run_cli("eval", str(dataset), *[a for o in options for a in ("--option", o)]).stdout
    return {k: re.search(rf"^{k}: (.+)$", out, re.M).group(1) for k in ("detected", "correct", "F-measure")}


@pytest.fixture(scope="module")
def scenes(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep") / "sc40"
    run_cli("scenes", "--out", str(out), "--count", "40", "--seed", "3")
    return out


GRID = ("--grid", "min_edge_coverage=0.5,0.9", "--grid", "split_angle_deg=25,35")


@pytest.fixture(scope="module")
def reference(scenes, tmp_path_factory):
    table = tmp_path_factory.mktemp("sweep") / "table.csv"
    r = sweep(str(scenes), *GRID, "--option", "refine_fit=false", "--workers", "2", "--out", str(table))
    assert r.returncode == 0, r.stderr
    with open(table, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    return {"stdout": r.stdout, "rows": rows}


def test_every_combination_scores_as_eval(reference, scenes):
    rows = reference["rows"]
    combos = [(row["min_edge_coverage"], row["split_angle_deg"]) for row in rows]
    assert combos == [("0.5", "25"), ("0.5", "35"), ("0.9", "25"), ("0.9", "35")]  # the first --grid slowest
    for row in rows:
        want = eval_counts(scenes, f"min_edge_coverage={row['min_edge_coverage']}",
                           f"split_angle_deg={row['split_angle_deg']}", "refine_fit=false")
        assert (row["detected"], row["correct"], row["f_measure"]) == \
               (want["detected"], want["correct"], want["F-measure"]), row
        assert int(row["truth"]) > 80 and float(row["median_ms"]) > 0
    # The options matter here (a sweep that ignored them would give four equal rows).
    assert len({row["detected"] for row in rows}) > 1


def test_prints_the_table_and_the_best_combination(reference):
    rows = reference["rows"]
    best = max(rows, key=lambda row: float(row["f_measure"]))
    assert re.search(rf"^best F-measure: {best['f_measure']} with min_edge_coverage={best['min_edge_coverage']} "
                     rf"split_angle_deg={best['split_angle_deg']}$", reference["stdout"], re.M), reference["stdout"]
    assert re.search(r"^images: 40 scored, 0 left out; combinations: 4$", reference["stdout"], re.M)
    assert reference["stdout"].splitlines()[0].split() == [
        "min_edge_coverage", "split_angle_deg", "detected", "truth", "correct", "precision", "recall", "f_measure",
        "median_ms"]


def test_images_that_cannot_be_scored_are_left_out(scenes, tmp_path):
    data = tmp_path / "data"
    shutil.copytree(scenes, data)
    stems = sorted(p.stem for p in (data / "images").iterdir())
    (data / "images" / f"{stems[0]}.png").write_bytes(b"not a png")  # corrupt
    os.remove(data / "gt" / f"{stems[1]}.txt")  # no truth
    table = tmp_path / "t.csv"
    r = sweep(str(data), "--grid", "split_angle_deg=30,35", "--workers", "2", "--out", str(table))
    assert r.returncode == 1, r.stderr
    assert f"{stems[0]}.png: " in r.stderr and f"{stems[1]}.png: no ground truth" in r.stderr
    assert "images: 38 scored, 2 left out; combinations: 2" in r.stdout
    # The 38 others are scored: as eval scores the set without those two images.
    for stem in stems[:2]:
        os.remove(data / "images" / f"{stem}.png")
        if os.path.exists(data / "gt" / f"{stem}.txt"):
            os.remove(data / "gt" / f"{stem}.txt")
    with open(table, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        want = eval_counts(data, f"split_angle_deg={row['split_angle_deg']}")
        assert (row["detected"], row["correct"]) == (want["detected"], want["correct"])


def test_no_image_scored_writes_no_table(scenes, tmp_path):
    data = tmp_path / "data"
    shutil.copytree(scenes, data)
    for p in (data / "gt").iterdir():
        os.remove(p)
    table = tmp_path / "t.csv"
    r = sweep(str(data), "--grid", "split_angle_deg=30,35", "--workers", "1", "--out", str(table))
    assert r.returncode == 1 and "no image of" in r.stderr and "could be scored" in r.stderr, r.stderr
    assert not table.exists()


@pytest.mark.parametrize("args, message", [
    (("--grid", "split_angle_deg"), "expected NAME=V1,V2"),
    (("--grid", "split_angle_deg=30,,35"), "empty value"),
    (("--grid", "split_angle_deg=30,30"), "listed twice"),
    (("--grid", "no_such_option=1,2"), "no_such_option"),
    (("--grid", "split_angle_deg=30,90"), "split_angle_deg"),
    (("--grid", "split_angle_deg=30", "--grid", "split_angle_deg=35"), "named twice"),
    (("--grid", "split_angle_deg=30", "--option", "split_angle_deg=35"), "both set split_angle_deg"),
])
def test_usage_errors_name_the_problem_and_write_nothing(scenes, tmp_path, args, message):
    table = tmp_path / "t.csv"
    r = sweep(str(scenes), *args, "--out", str(table), timeout=60)
    assert r.returncode == 2 and message in r.stderr, r.stderr
    assert not table.exists()


def test_a_folder_without_images_is_a_usage_error(tmp_path):
    (tmp_path / "gt").mkdir()
    r = sweep(str(tmp_path), "--grid", "split_angle_deg=30", "--out", str(tmp_path / "t.csv"), timeout=60)
    assert r.returncode == 2 and "no images/ folder" in r.stderr, r.stderr
