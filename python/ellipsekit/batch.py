"""Batch detection over many image files on a Dask distributed cluster.

    python3 -m ellipsekit.batch INPUT... --out results.jsonl [--workers N | --scheduler tcp://HOST:PORT]
        [--chunk K] [--backend B] [--option NAME=VALUE ...] [--resume] [--gt DIR] [--no-progress]

INPUT: files, directories (searched recursively for .png .jpg .jpeg .bmp, sorted) or globs
("logs/**/*.png"). A file named explicitly is read whatever its extension.

Work goes to Dask in chunks of K images; each worker process keeps one Detector per thread. The
output gets one JSON line per image as each chunk finishes (in completion order, never a partial
line, nothing kept in memory after it is written):
    {"path": P, "status": "ok" | the problem, "ellipses": [[cx, cy, a, b, theta, score], ...],
     "ms": detect() wall time, "backend": "simd" | ...}
plus "caps_hit" when a cap bounded the work, and "gt": {"detected", "truth", "correct"} with --gt.
Ellipse values are the doubles detect() returned (JSON round-trips them exactly), the same values
`ellipsekit detect` prints rounded. A problem with an image ("no such file", "corrupt or truncated
image: ...") is its line's status; the run goes on. A worker process that dies mid-run costs only
time: Dask runs its chunks again elsewhere, and only the client writes, once per finished chunk, so
every image appears exactly once. A chunk that fails on its own (a worker dies on it again and
again) is retried image by image, and an image that still fails gets its error line.

--resume skips the images already in the output (an interrupted run continues; a partial last line
left by a kill is cut off first). --gt DIR (a dataset folder with gt/, or a folder of <stem>.txt)
scores each image as `ellipsekit eval` does and prints the same precision / recall / F-measure
over the whole output file. A progress bar shows on a terminal; a summary ends the run. Exit
status: 0, 1 when an image failed, 2 for a bad command line.
"""

import argparse
import glob
import json
import logging
import math
import os
import sys
import time

from ellipsekit import _ellipsekit
from ellipsekit import _option_text
from ellipsekit._batch_worker import describe, run_chunk

_GLOB_CHARS = set("*?[")


def _is_image(name):
    return _ellipsekit.is_image_extension(os.path.splitext(name)[1])


def _walk(directory):
    for root, dirs, files in os.walk(directory):
        dirs.sort()
        for name in sorted(files):
            if _is_image(name):
                yield os.path.join(root, name)


def iter_inputs(inputs, warn=None):
    """The image paths named by INPUT arguments, in order, each once."""
    seen = set()
    for item in inputs:
        if any(c in _GLOB_CHARS for c in item):
            matches = sorted(glob.glob(item, recursive=True))
            if not matches and warn:
                warn(f"{item}: matches nothing")
            paths = []
            for m in matches:
                paths.extend(_walk(m) if os.path.isdir(m) else ([m] if _is_image(m) else []))
        elif os.path.isdir(item):
            paths = _walk(item)
        else:
            paths = [item]  # a named file, whatever it is: a problem becomes its line's status
        for p in paths:
            if p not in seen:
                seen.add(p)
                yield p


def _read_done(out_path):
    """Paths already in the output; cuts off a partial last line (a run killed mid-write)."""
    done = set()
    if not os.path.exists(out_path):
        return done
    with open(out_path, "rb+") as f:
        data_end = 0
        for line in f:
            if not line.endswith(b"\n"):
                break
            try:
                done.add(json.loads(line)["path"])
            except (ValueError, KeyError, TypeError):
                break
            data_end += len(line)
        f.truncate(data_end)
    return done


def _gt_spec(gt_dir):
    """--gt DIR: a dataset folder (DIR/gt/, DIR/border_boxes.txt) or a folder of <stem>.txt files."""
    gt_dir = os.path.abspath(gt_dir)
    if not os.path.isdir(gt_dir):
        raise ValueError(f"--gt {gt_dir}: not a directory")
    dont_care = {}
    if os.path.isdir(os.path.join(gt_dir, "gt")):
        boxes = os.path.join(gt_dir, "border_boxes.txt")
        if os.path.exists(boxes):
            dont_care = _ellipsekit.read_dont_care(boxes)
        gt_dir = os.path.join(gt_dir, "gt")
    return {"dir": gt_dir, "dont_care": dont_care}


def add_cluster_arguments(p, chunk_help):
    """The flags of the cluster and the progress bar, shared by ellipsekit.batch and ellipsekit.sweep."""
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="LocalCluster of N worker processes (default: the cores, %d here)" % (os.cpu_count() or 1))
    p.add_argument("--threads", type=int, default=1, metavar="T", help="threads per local worker process (default 1; more threads share one "
                        "decoder at a time, since the CLI's loader redirects fd 2 while it decodes, so "
                        "prefer processes)")
    p.add_argument("--scheduler", metavar="ADDR", help="use the Dask cluster at ADDR (tcp://HOST:PORT) instead")
    p.add_argument("--chunk", type=int, default=None, metavar="K", help=chunk_help)
    p.add_argument("--progress", dest="progress", action="store_true", default=None,
                   help="progress bar even when stderr is not a terminal")
    p.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")


def check_cluster_arguments(p, args):
    """Usage errors (p.error) for the values of add_cluster_arguments' flags."""
    if args.workers is not None and args.workers < 1:
        p.error(f"--workers: bad value {args.workers}, expected >= 1")
    if args.threads < 1:
        p.error(f"--threads: bad value {args.threads}, expected >= 1")
    if args.chunk is not None and args.chunk < 1:
        p.error(f"--chunk: bad value {args.chunk}, expected >= 1")
    if args.scheduler and args.workers is not None:
        p.error("--workers and --scheduler exclude each other")


def _parse_args(argv):
    p = argparse.ArgumentParser(
        prog="python3 -m ellipsekit.batch",
        description="Detect ellipses in many images on a Dask cluster; one JSON line per image.",
        epilog=__doc__[__doc__.index("INPUT: "):], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="files, directories (recursive) or globs")
    p.add_argument("--out", required=True, metavar="FILE", help="output JSON lines file")
    add_cluster_arguments(p, "images per task (default: total / (8 x threads), between 16 and 64)")
    p.add_argument("--backend", default="auto", help="auto, scalar, simd or vulkan (as the CLI)")
    p.add_argument("--option", action="append", default=[], metavar="NAME=VALUE",
                   help="a detector option, as the CLI's --option (repeatable)")
    p.add_argument("--resume", action="store_true", help="skip images already in the output")
    p.add_argument("--gt", metavar="DIR", help="score against ground truth as `ellipsekit eval` does")
    args = p.parse_args(argv)
    check_cluster_arguments(p, args)
    args.assignments = tuple([_option_text("backend", args.backend)] + args.option)
    try:
        _ellipsekit.Detector(list(args.assignments))  # the options' errors, before any cluster starts
    except (ValueError, RuntimeError) as e:
        p.error(str(e))
    if args.gt:
        try:
            args.gt_spec = _gt_spec(args.gt)
        except ValueError as e:
            p.error(str(e))
    else:
        args.gt_spec = None
    return args


def _chunks(paths, size):
    chunk = []
    for p in paths:
        chunk.append(p)
        if len(chunk) == size:
            yield chunk
            chunk = []
    if chunk:
        yield chunk


def _write_all(fd, text):
    data = text.encode("utf-8")
    while data:
        n = os.write(fd, data)
        data = data[n:]


def _score_file(out_path, gt):
    """Sums `ellipsekit eval`'s counts over every ok line of the output (lines written without
    --gt, by an earlier run, are scored here). Returns (detected, truth, correct, images, missing)."""
    import numpy as np
    detected = truth = correct = images = 0
    missing = []
    with open(out_path, encoding="utf-8") as f:
        for line in f:
            rec = json.loads(line)
            if rec["status"] != "ok":
                continue
            score = rec.get("gt")
            if score is None:
                stem = os.path.splitext(os.path.basename(rec["path"]))[0]
                try:
                    t = _ellipsekit.read_ellipses(os.path.join(gt["dir"], stem + ".txt"))
                except ValueError as e:
                    score = {"error": str(e)}
                else:
                    d = np.asarray(rec["ellipses"], dtype=float).reshape(-1, 6)
                    n_det, n_truth, n_ok = _ellipsekit.match_counts(d, t, gt["dont_care"].get(stem, []))
                    score = {"detected": n_det, "truth": n_truth, "correct": n_ok}
            if "error" in score:
                missing.append(score["error"])
                continue
            detected += score["detected"]
            truth += score["truth"]
            correct += score["correct"]
            images += 1
    return detected, truth, correct, images, missing


def _start_cluster(args):
    from distributed import Client, LocalCluster
    if args.scheduler:
        client = Client(args.scheduler, timeout=30)
        client.wait_for_workers(1, timeout=120)
        return client, None
    n = args.workers or os.cpu_count() or 1
    # The workers' statistical profiler samples every thread's stack every 10 ms for the dashboard,
    # which this command does not serve: off, its CPU goes to detection.
    import dask
    dask.config.set({"distributed.worker.profile.enabled": False})
    cluster = LocalCluster(n_workers=n, threads_per_worker=args.threads, processes=True,
                           dashboard_address=None, silence_logs=logging.ERROR)
    return Client(cluster), cluster


def check_workers(client, prog):
    """Exits with a message unless every worker runs this version of ellipsekit: a worker machine
    without the package, or with another version of it, would fail every task."""
    from ellipsekit import __version__
    try:
        versions = client.run(describe)
    except Exception as e:  # noqa: BLE001 - e.g. ModuleNotFoundError raised on a worker
        raise SystemExit(f"{prog}: a worker cannot run ellipsekit ({type(e).__name__}: {e}); "
                         "install the package where the workers run (docs/python.md: Running on a cluster)")
    other = {w: v for w, v in versions.items() if v != __version__}
    if other:
        raise SystemExit(f"{prog}: workers run other versions of ellipsekit than {__version__}: {other}")


def run(args, log=None):
    """Runs a parsed command line; returns the exit status."""
    log = log or (lambda msg: print(f"ellipsekit.batch: {msg}", file=sys.stderr))
    from distributed import as_completed

    done = _read_done(args.out) if args.resume else set()
    todo = (p for p in iter_inputs(args.inputs, warn=log) if p not in done)
    total = sum(1 for p in iter_inputs(args.inputs) if p not in done)

    start = time.perf_counter()
    client, cluster = _start_cluster(args)
    fd = -1
    counts = {"images": 0, "ellipses": 0, "errors": 0}
    progress = None
    try:
        check_workers(client, "ellipsekit.batch")
        # The output is touched only once the cluster can do the work (a failed start leaves it be).
        fd = os.open(args.out, os.O_WRONLY | os.O_APPEND | os.O_CREAT | (0 if args.resume else os.O_TRUNC), 0o644)
        nthreads = client.nthreads()
        threads = sum(nthreads.values()) or 1
        # Dask costs ~3 ms per task here (client and scheduler; 11 ms a round trip, hidden by keeping
        # several chunks in flight); an image ~4 ms. 16 images or more keep that under 5 %; 8 chunks
        # per thread balance the load; 64 bounds what a killed worker takes with it.
        chunk = args.chunk or max(16, min(64, math.ceil(total / (8 * threads))))
        show = args.progress if args.progress is not None else sys.stderr.isatty()
        if show:
            from tqdm import tqdm
            progress = tqdm(total=total, unit="img", file=sys.stderr, smoothing=0.1)
        gt = args.gt_spec
        owner = {}  # future key -> its paths
        submit_start = time.perf_counter()

        def submit(paths):
            future = client.submit(run_chunk, paths, args.assignments, gt, pure=False)
            owner[future.key] = paths
            return future

        pending = _chunks(todo, chunk)
        window = as_completed()
        for paths in pending:  # keep 4 chunks per thread in flight: bounded memory, no idle worker
            window.add(submit(paths))
            if window.count() >= 4 * threads:
                break
        for future in window:
            paths = owner.pop(future.key)
            try:
                text = future.result()
            except Exception as e:  # noqa: BLE001 - the chunk failed as a whole (e.g. KilledWorker)
                future.release()
                if len(paths) > 1:
                    log(f"a chunk of {len(paths)} images failed ({type(e).__name__}); retrying them one by one")
                    for p in paths:
                        window.add(submit([p]))
                    continue
                text = json.dumps({"path": paths[0], "status": f"worker failed: {type(e).__name__}: {e}",
                                   "ellipses": [], "ms": None, "backend": None}, separators=(", ", ": ")) + "\n"
            future.release()
            _write_all(fd, text)
            for line in text.splitlines():
                rec = json.loads(line)
                counts["images"] += 1
                counts["ellipses"] += len(rec["ellipses"])
                if rec["status"] != "ok":
                    counts["errors"] += 1
                    if progress is not None:
                        progress.write(f"ellipsekit.batch: {rec['path']}: {rec['status']}", file=sys.stderr)
                    else:
                        log(f"{rec['path']}: {rec['status']}")
            if progress is not None:
                progress.update(len(paths))
            nxt = next(pending, None)
            if nxt is not None:
                window.add(submit(nxt))
        elapsed = time.perf_counter() - submit_start
    finally:
        if fd >= 0:
            os.close(fd)
        if progress is not None:
            progress.close()
        client.close()
        if cluster is not None:
            cluster.close()
    wall = time.perf_counter() - start

    rate = counts["images"] / elapsed if elapsed > 0 else 0.0
    print(f"images: {counts['images']}" + (f" (skipped {len(done)} already in {args.out})" if done else ""))
    print(f"ellipses: {counts['ellipses']}")
    print(f"errors: {counts['errors']}")
    print(f"workers: {len(nthreads)} processes, {threads} threads, chunk {chunk}")
    print(f"time: {elapsed:.2f} s detecting ({wall:.2f} s with the cluster's start and stop)")
    print(f"images per second: {rate:.1f}")
    if args.gt_spec is not None:
        detected, truth, correct, images, missing = _score_file(args.out, args.gt_spec)
        precision, recall, f = _ellipsekit.prf(detected, truth, correct)
        print(f"scored images: {images}")
        print(f"ground truth: {truth}")
        print(f"detected: {detected}")
        print(f"correct: {correct}")
        print(f"precision: {precision:.4f}")
        print(f"recall: {recall:.4f}")
        print(f"F-measure: {f:.4f}")
        for m in missing[:5]:
            log(f"no ground truth: {m}")
        if missing:
            log(f"{len(missing)} images without ground truth were not scored")
    sys.stdout.flush()
    return 1 if counts["errors"] else 0


def main(argv=None):
    args = _parse_args(sys.argv[1:] if argv is None else argv)
    return run(args)


if __name__ == "__main__":
    # Run through the module's real name, so the tasks pickle as ellipsekit._batch_worker.run_chunk.
    from ellipsekit.batch import main as _main
    sys.exit(_main())
