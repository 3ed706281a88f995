"""A parameter sweep over a dataset on a Dask distributed cluster: P / R / F per option set.

    python3 -m ellipsekit.sweep DATASET --grid NAME=V1,V2,... [--grid NAME=...] [--option NAME=VALUE ...]
        [--backend B] [--workers N | --scheduler tcp://HOST:PORT] [--threads T] [--chunk K]
        [--out FILE.csv] [--no-progress]

DATASET is a folder as `ellipsekit eval` reads it: images/ and gt/<stem>.txt (and border_boxes.txt).
Each --grid names one detector option and the values to try; the sweep runs every combination
(the first --grid varies slowest), each with the --option settings too, on every image, and scores
each combination as `ellipsekit eval DATASET --option ...` does (the same matching, the same counts).

Work goes to Dask in chunks of K images: a task decodes each image once and detects on it with every
combination (each worker thread keeps one Detector per combination, so its memory grows with the
number of combinations: ~15 MB each at 640x480). The client sums each combination's counts and writes
FILE.csv (default: sweep.csv), one row per combination, in the grid's order:
    NAME..., detected, truth, correct, precision, recall, f_measure, median_ms
then prints the same table and the combination of the highest F-measure (the first such).
An image that cannot be read, or has no ground truth, is reported and left out of every
combination's counts; the others are scored (when none is, no table is written). A worker process
that dies costs only time (Dask runs its chunk again). Exit status: 0, 1 when an image was left
out, 2 for a bad command line.
"""

import argparse
import csv
import itertools
import logging
import math
import os
import statistics
import sys
import time

from ellipsekit import _ellipsekit
from ellipsekit import _option_text
from ellipsekit._batch_worker import sweep_chunk
from ellipsekit.batch import (_chunks, _gt_spec, _start_cluster, add_cluster_arguments, check_cluster_arguments,
                             check_workers, iter_inputs)

_COLUMNS = ("detected", "truth", "correct", "precision", "recall", "f_measure", "median_ms")


def _parse_grid(text):
    """'NAME=V1,V2,...' -> (NAME, [V1, V2, ...]); ValueError naming the problem."""
    name, sep, values = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise ValueError(f"--grid {text!r}: expected NAME=V1,V2,...")
    listed = [v.strip() for v in values.split(",")]
    if not listed or any(v == "" for v in listed):
        raise ValueError(f"--grid {text!r}: empty value in the list")
    if len(set(listed)) != len(listed):
        raise ValueError(f"--grid {text!r}: a value is listed twice")
    return name, listed


def _parse_args(argv):
    p = argparse.ArgumentParser(
        prog="python3 -m ellipsekit.sweep",
        description="Score every combination of detector options over a dataset, on a Dask cluster.",
        epilog=__doc__[__doc__.index("DATASET is"):], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dataset", metavar="DATASET", help="a folder with images/ and gt/ (as `ellipsekit eval` reads)")
    p.add_argument("--grid", action="append", required=True, metavar="NAME=V1,V2,...",
                   help="an option and the values to try (repeatable: every combination runs)")
    p.add_argument("--option", action="append", default=[], metavar="NAME=VALUE",
                   help="a detector option held fixed, as the CLI's --option (repeatable)")
    p.add_argument("--backend", default="auto", help="auto, scalar, simd or vulkan (as the CLI)")
    add_cluster_arguments(p, "images per task (default: images / (4 x threads), between 1 and 16)")
    p.add_argument("--out", default="sweep.csv", metavar="FILE", help="the table as CSV (default sweep.csv)")
    args = p.parse_args(argv)
    check_cluster_arguments(p, args)
    try:
        grid = [_parse_grid(g) for g in args.grid]
    except ValueError as e:
        p.error(str(e))
    names = [name for name, _ in grid]
    if len(set(names)) != len(names):
        p.error("--grid: an option is named twice")
    fixed = {o.partition("=")[0].strip() for o in args.option}
    if fixed & set(names):
        p.error(f"--grid and --option both set {sorted(fixed & set(names))[0]}")
    args.names = names
    args.values = list(itertools.product(*[values for _, values in grid]))
    base = [_option_text("backend", args.backend)] + args.option
    args.points = [tuple(base + [f"{n}={v}" for n, v in zip(names, combo)]) for combo in args.values]
    for point in args.points:  # every combination's errors, before any cluster starts
        try:
            _ellipsekit.Detector(list(point))
        except (ValueError, RuntimeError) as e:
            p.error(str(e))
    images = os.path.join(args.dataset, "images")
    for folder in ("images", "gt"):
        if not os.path.isdir(os.path.join(args.dataset, folder)):
            p.error(f"{args.dataset}: no {folder}/ folder (a dataset as `ellipsekit eval` reads it)")
    args.gt_spec = _gt_spec(args.dataset)
    args.paths = list(iter_inputs([images]))
    if not args.paths:
        p.error(f"{images}: no images")
    return args


def _table(args, sums, times):
    """One row per combination: its grid values and eval's figures."""
    rows = []
    for combo, (detected, truth, correct), ms in zip(args.values, sums, times):
        precision, recall, f = _ellipsekit.prf(detected, truth, correct)
        median = statistics.median(ms) if ms else float("nan")
        rows.append(list(combo) + [detected, truth, correct, f"{precision:.4f}", f"{recall:.4f}", f"{f:.4f}",
                                   f"{median:.3f}"])
    return rows


def run(args, log=None):
    """Runs a parsed command line; returns the exit status."""
    log = log or (lambda msg: print(f"ellipsekit.sweep: {msg}", file=sys.stderr))
    from distributed import as_completed

    n_points = len(args.points)
    sums = [[0, 0, 0] for _ in range(n_points)]
    times = [[] for _ in range(n_points)]
    left_out = 0
    start = time.perf_counter()
    client, cluster = _start_cluster(args)
    progress = None
    try:
        check_workers(client, "ellipsekit.sweep")
        threads = sum(client.nthreads().values()) or 1
        # A task is chunk images x every combination: fewer images per task than batch's, so that
        # a sweep of many combinations still spreads over every thread.
        chunk = args.chunk or max(1, min(16, math.ceil(len(args.paths) / (4 * threads))))
        show = args.progress if args.progress is not None else sys.stderr.isatty()
        if show:
            from tqdm import tqdm
            progress = tqdm(total=len(args.paths), unit="img", file=sys.stderr, smoothing=0.1)
        futures = [client.submit(sweep_chunk, paths, args.points, args.gt_spec, pure=False)
                   for paths in _chunks(args.paths, chunk)]
        for future in as_completed(futures):
            records = future.result()
            future.release()
            for rec in records:
                if rec["status"] != "ok":
                    left_out += 1
                    log(f"{rec['path']}: {rec['status']} (left out)")
                    continue
                for i, (detected, truth, correct, ms) in enumerate(rec["counts"]):
                    sums[i][0] += detected
                    sums[i][1] += truth
                    sums[i][2] += correct
                    times[i].append(ms)
            if progress is not None:
                progress.update(len(records))
    finally:
        if progress is not None:
            progress.close()
        client.close()
        if cluster is not None:
            cluster.close()
    wall = time.perf_counter() - start
    if left_out == len(args.paths):  # eval's conventions would score nothing as P = R = 1
        log(f"no image of {args.dataset} could be scored; no table written")
        return 1

    header = list(args.names) + list(_COLUMNS)
    rows = _table(args, sums, times)
    tmp = args.out + ".tmp"
    with open(tmp, "w", newline="", encoding="utf-8") as f:  # written whole, then renamed: never half
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(rows)
    os.replace(tmp, args.out)

    widths = [max(len(str(h)), *(len(str(r[i])) for r in rows)) for i, h in enumerate(header)]
    for line in [header] + rows:
        print("  ".join(str(v).rjust(w) for v, w in zip(line, widths)))
    best = max(range(len(rows)), key=lambda i: (float(rows[i][len(args.names) + 5]), -i))
    setting = " ".join(f"{n}={v}" for n, v in zip(args.names, args.values[best]))
    print(f"best F-measure: {rows[best][len(args.names) + 5]} with {setting}")
    print(f"images: {len(args.paths) - left_out} scored, {left_out} left out; combinations: {n_points}")
    print(f"time: {wall:.2f} s with the cluster's start and stop; table: {args.out}")
    sys.stdout.flush()
    return 1 if left_out else 0


def main(argv=None):
    args = _parse_args(sys.argv[1:] if argv is None else argv)
    logging.getLogger("distributed").setLevel(logging.ERROR)
    return run(args)


if __name__ == "__main__":
    # Run through the module's real name, so the tasks pickle as ellipsekit._batch_worker.sweep_chunk.
    from ellipsekit.sweep import main as _main
    sys.exit(_main())
