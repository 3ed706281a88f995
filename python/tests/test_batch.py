"""python3 -m ellipsekit.batch on Dask distributed: results equal to the CLI, --gt equal to
`ellipsekit eval`, --resume, bad files, a worker killed mid-run, usage errors.

200 generated 640x480 scenes (seed 7, generated once per run of this file); LocalClusters of 2
worker processes.
"""
import json
import os
import re
import signal
import subprocess
import sys
import time

import pytest

from conftest import REPO, batch, cli_detect_json, cli_rows, exact_rows, read_jsonl, run_cli


def by_path(records):
    out = {}
    for rec in records:
        assert rec["path"] not in out, f"{rec['path']} appears twice"
        out[rec["path"]] = rec
    return out


@pytest.fixture(scope="module")
def images(scenes200):
    return sorted(str(p) for p in (scenes200 / "images").iterdir())


@pytest.fixture(scope="module")
def reference(scenes200, tmp_path_factory):
    """One full run: --workers 2 over the scenes' images folder, with --gt."""
    out = tmp_path_factory.mktemp("batch") / "full.jsonl"
    r = batch(str(scenes200 / "images"), "--out", str(out), "--workers", "2", "--gt", str(scenes200))
    assert r.returncode == 0, r.stderr
    return {"out": out, "stdout": r.stdout, "records": read_jsonl(out)}


def test_every_image_once_and_equal_to_the_cli(reference, images):
    recs = by_path(reference["records"])
    assert sorted(recs) == images
    cli = cli_detect_json(images)
    found = 0
    for path in images:
        rec = recs[path]
        assert rec["status"] == "ok" and rec["backend"] == "simd" and rec["ms"] > 0
        assert exact_rows(rec["ellipses"]) == cli_rows(cli[path]), path
        found += len(rec["ellipses"])
    assert found > 300  # ~550 (a loader or detector that failed would find none)
    assert re.search(rf"^images: 200\nellipses: {found}\nerrors: 0\nworkers: 2 processes, 2 threads",
                     reference["stdout"], re.M), reference["stdout"]
    assert re.search(r"^images per second: [0-9.]+$", reference["stdout"], re.M)


def test_gt_gives_the_same_scores_as_eval(reference, scenes200):
    ev = run_cli("eval", str(scenes200)).stdout
    keys = ("ground truth", "detected", "correct", "precision", "recall", "F-measure")
    want = {k: re.search(rf"^{k}: (.+)$", ev, re.M).group(1) for k in keys}
    got = {k: re.search(rf"^{k}: (.+)$", reference["stdout"], re.M).group(1) for k in keys}
    assert got == want
    assert float(want["F-measure"]) > 0.5  # (a scoring that matched nothing would give 0)
    assert all("gt" in rec and "correct" in rec["gt"] for rec in reference["records"])


def test_resume_continues_an_interrupted_run(reference, scenes200, tmp_path):
    out = tmp_path / "part.jsonl"
    lines = open(reference["out"], encoding="utf-8").read().splitlines(keepends=True)
    kept = lines[:50]
    out.write_text("".join(kept) + lines[50][:40])  # a run killed mid-write: 50 lines and a partial one
    r = batch(str(scenes200 / "images"), "--out", str(out), "--workers", "2", "--resume", "--gt", str(scenes200))
    assert r.returncode == 0, r.stderr
    assert f"images: 150 (skipped 50 already in {out})" in r.stdout
    text = out.read_text()
    assert text.startswith("".join(kept))  # what was there stays, byte for byte
    recs = by_path(json.loads(line) for line in text.splitlines())
    ref = by_path(reference["records"])
    assert sorted(recs) == sorted(ref)
    for path, rec in recs.items():
        assert rec["ellipses"] == ref[path]["ellipses"]
    # P / R / F are over the whole file, earlier lines included
    for k in ("precision", "recall", "F-measure"):
        assert re.search(rf"^{k}: .+$", r.stdout, re.M).group(0) in reference["stdout"]
    # resuming a finished run does nothing
    r = batch(str(scenes200 / "images"), "--out", str(out), "--workers", "1", "--resume")
    assert r.returncode == 0 and "images: 0 (skipped 200" in r.stdout
    assert out.read_text() == text


def test_bad_files_get_their_error_and_the_run_goes_on(images, tmp_path):
    good = open(images[0], "rb").read()
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "empty.png").write_bytes(b"")
    (bad / "text.png").write_text("not an image\n")
    (bad / "cut.png").write_bytes(good[: len(good) // 3])
    (bad / "notes.txt").write_text("skipped: not an image extension\n")
    missing = str(tmp_path / "missing.png")
    inputs = [str(bad), missing, *images[:6]]
    out = tmp_path / "out.jsonl"
    r = batch(*inputs, "--out", str(out), "--workers", "2", "--chunk", "2", "--progress")
    assert r.returncode == 1, r.stderr
    recs = by_path(read_jsonl(out))
    bad_paths = [str(bad / n) for n in ("cut.png", "empty.png", "text.png")] + [missing]
    assert sorted(recs) == sorted(bad_paths + images[:6])  # notes.txt: not listed from a folder
    cli = run_cli("detect", *bad_paths, check=False)
    cli_errors = dict(re.findall(r"^ellipsekit detect: (.+?): (.+)$", cli.stderr, re.M))
    for p in bad_paths:
        assert recs[p]["status"] == cli_errors[p], p
        assert recs[p]["ellipses"] == [] and recs[p]["ms"] is None
    assert "libpng error" in recs[str(bad / "cut.png")]["status"]  # the decoder's own words kept
    assert all(recs[p]["status"] == "ok" for p in images[:6])
    assert "errors: 4" in r.stdout
    assert "10/10" in r.stderr  # the progress bar (tqdm)
    for p in bad_paths:
        assert f"{p}: {cli_errors[p]}" in r.stderr


def test_usage_errors_exit_2_before_any_cluster(tmp_path):
    out = str(tmp_path / "o.jsonl")
    for args, message in [
        (["--option", "split_angle_deg=99"], "split_angle_deg (T_theta) must be in (0, 60] degrees"),
        (["--option", "nope=1"], "unknown option 'nope'"),
        (["--backend", "gpu"], "option backend: bad value 'gpu', expected auto, scalar, simd or vulkan"),
        (["--workers", "0"], "--workers: bad value 0"),
        (["--gt", str(tmp_path / "none")], "not a directory"),
    ]:
        r = batch("x.png", "--out", out, *args, timeout=60)
        assert r.returncode == 2 and message in r.stderr, (args, r.stderr)
    assert not os.path.exists(out)


def test_a_killed_worker_costs_nothing(reference, scenes200, tmp_path):
    """A worker process is killed (SIGKILL) while it holds chunks; every image still appears once,
    with the same ellipses. The cluster is this test's own (--scheduler), so it can pick the victim."""
    from distributed import Client, LocalCluster

    out = tmp_path / "killed.jsonl"
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=50) as cluster, Client(cluster) as client:
        proc = subprocess.Popen(
            [sys.executable, "-m", "ellipsekit.batch", str(scenes200 / "images"), "--out", str(out),
             "--scheduler", cluster.scheduler_address, "--chunk", "4", "--backend", "scalar"],
            cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        killed_at = None
        deadline = time.monotonic() + 120
        while proc.poll() is None and killed_at is None and time.monotonic() < deadline:
            time.sleep(0.02)
            written = sum(1 for _ in open(out)) if out.exists() else 0
            if written == 0:
                continue
            busy = [w for w, keys in client.processing().items() if keys]
            if not busy:
                continue
            pid = client.run(os.getpid, workers=[busy[0]])[busy[0]]
            os.kill(pid, signal.SIGKILL)
            killed_at = written
        stdout, stderr = proc.communicate(timeout=180)
    assert killed_at is not None, "the run ended before a worker could be killed mid-run"
    assert killed_at < 200
    assert proc.returncode == 0, stderr
    recs = by_path(read_jsonl(out))  # asserts: no image twice
    ref = by_path(reference["records"])
    assert sorted(recs) == sorted(ref)
    for path, rec in recs.items():
        assert rec["status"] == "ok" and rec["backend"] == "scalar"
        assert rec["ellipses"] == ref[path]["ellipses"], path
    assert "images: 200\n" in stdout


def test_inputs_files_folders_and_globs(tmp_path):
    from ellipsekit.batch import iter_inputs
    (tmp_path / "a" / "b").mkdir(parents=True)
    for name in ("a/2.png", "a/1.JPG", "a/b/3.bmp", "a/notes.txt", "c.jpeg"):
        (tmp_path / name).write_bytes(b"x")
    t = str(tmp_path)
    assert list(iter_inputs([f"{t}/a"])) == [f"{t}/a/1.JPG", f"{t}/a/2.png", f"{t}/a/b/3.bmp"]
    assert list(iter_inputs([f"{t}/**/*.png", f"{t}/c.jpeg", f"{t}/a/2.png"])) == [f"{t}/a/2.png", f"{t}/c.jpeg"]
    assert list(iter_inputs([f"{t}/a/notes.txt", f"{t}/none.png"])) == [f"{t}/a/notes.txt", f"{t}/none.png"]
    warned = []
    assert list(iter_inputs([f"{t}/*.tif"], warn=warned.append)) == [] and warned == [f"{t}/*.tif: matches nothing"]
