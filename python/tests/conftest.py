"""Shared fixtures of the ellipsekit Python suites.

Run by ctest (python/CMakeLists.txt) from the repository root with PYTHONPATH=<build>/python,
ELLIPSEKIT_CLI=<build>/bin/ellipsekit and ELLIPSEKIT_BUILD_DIR=<build>. By hand:
    PYTHONPATH=build-py/python ELLIPSEKIT_CLI=build-py/bin/ellipsekit python3 -m pytest python/tests
"""
import glob
import json
import os
import subprocess
import sys

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATASETS = os.path.join(REPO, "..", "shared", "datasets")


def cli_path():
    path = os.environ.get("ELLIPSEKIT_CLI") or os.path.join(REPO, "build", "bin", "ellipsekit")
    if not os.path.exists(path):
        pytest.skip(f"the ellipsekit CLI is not built ({path}); set ELLIPSEKIT_CLI")
    return path


def run_cli(*args, check=True):
    r = subprocess.run([cli_path(), *args], capture_output=True, text=True, cwd=REPO)
    if check and r.returncode != 0:
        raise AssertionError(f"ellipsekit {' '.join(args[:3])}... exit {r.returncode}: {r.stderr[-2000:]}")
    return r


def cli_detect_json(paths, *options):
    """`ellipsekit detect --format json --exact --warmup 0`: every ellipse number printed with 17
    significant digits, so float() of it is the detector's double, bit for bit."""
    r = run_cli("detect", "--format", "json", "--exact", "--warmup", "0", *options, *paths)
    return {rep["path"]: rep for rep in json.loads(r.stdout)}


def dataset_images():
    """Every shared dataset image, as paths relative to the repository root (../shared/datasets/...)."""
    found = sorted(glob.glob(os.path.join(DATASETS, "*", "images", "*")))
    return [os.path.relpath(p, REPO) for p in found]


def exact_rows(rows):
    """Rows (a detect() result or a batch record) as lists of Python floats, for == comparison."""
    return [[float(v) for v in row] for row in rows]


def cli_rows(report):
    return [[e["cx"], e["cy"], e["a"], e["b"], e["theta"], e["score"]] for e in report["ellipses"]]


@pytest.fixture(scope="session")
def repo():
    return REPO


@pytest.fixture(scope="session")
def scenes200(tmp_path_factory):
    """200 generated 640x480 scenes (seed 7): DIR/images/*.png, DIR/gt/*.txt."""
    out = tmp_path_factory.mktemp("scenes") / "sc200"
    run_cli("scenes", "--out", str(out), "--count", "200", "--seed", "7")
    return out


def batch(*args, env=None, timeout=240):
    """`python3 -m ellipsekit.batch ARGS`; returns the CompletedProcess."""
    e = dict(os.environ)
    e.update(env or {})
    return subprocess.run([sys.executable, "-m", "ellipsekit.batch", *args], capture_output=True, text=True,
                          cwd=REPO, env=e, timeout=timeout)


def read_jsonl(path):
    with open(path, encoding="utf-8") as f:
        return [json.loads(line) for line in f]
