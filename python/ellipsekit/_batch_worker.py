"""What a Dask worker runs for `python3 -m ellipsekit.batch`: one chunk of images -> JSON lines.

Kept apart from ellipsekit.batch (the client) so that tasks pickle by reference to this module
even when the client runs as __main__. Each worker thread keeps one Detector per option set
(threading.local), so a worker process with several threads detects in parallel (the GIL is
released in decode and detect).
"""

import json
import os
import threading
import time

from ellipsekit import _ellipsekit

_local = threading.local()
_malloc_tuned = False


def _tune_malloc():
    """Keeps glibc from returning every freed decode buffer to the kernel.

    Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536 (distributed.nanny.pre-spawn-environ),
    which also freezes the mmap threshold at 128 KiB: each frame's file bytes and decoded pixels are
    then mmapped and unmapped, and faulted in again on the next frame (measured: ~375 page faults and
    ~0.8 ms of system time per 640x480 PNG, a fifth of the frame's work). A worker's memory is its
    Detectors' buffers, reused frame after frame, so this raises both thresholds (32 MiB mmap,
    64 MiB trim) in the worker process itself, whatever cluster started it.
    """
    global _malloc_tuned
    _malloc_tuned = True
    try:
        import ctypes
        libc = ctypes.CDLL(None)
        m_trim_threshold, m_mmap_threshold = -1, -3  # <malloc.h>
        libc.mallopt(m_mmap_threshold, 32 << 20)
        libc.mallopt(m_trim_threshold, 64 << 20)
    except (OSError, AttributeError):  # not glibc: nothing to tune
        pass


def _detector(assignments):
    if not _malloc_tuned:
        _tune_malloc()
    cache = getattr(_local, "detectors", None)
    if cache is None:
        cache = _local.detectors = {}
    detector = cache.get(assignments)
    if detector is None:
        detector = cache[assignments] = _ellipsekit.Detector(list(assignments))
    return detector


def _truth(gt, path):
    """(truth array, don't-care boxes) of `path` from the ground-truth folder, or an error text."""
    stem = os.path.splitext(os.path.basename(path))[0]
    truth_path = os.path.join(gt["dir"], stem + ".txt")
    try:
        truth = _ellipsekit.read_ellipses(truth_path)
    except ValueError as e:
        return None, None, str(e)
    return truth, gt["dont_care"].get(stem, []), None


def _record(path, assignments, gt):
    image, problem, _note = _ellipsekit.load_gray(path)
    if image is None:
        return {"path": path, "status": problem, "ellipses": [], "ms": None, "backend": None}
    try:
        start = time.perf_counter()
        ellipses, figures = _detector(assignments).detect(image)
        ms = (time.perf_counter() - start) * 1e3
    except (ValueError, RuntimeError) as e:
        return {"path": path, "status": f"detection failed: {e}", "ellipses": [], "ms": None, "backend": None}
    rec = {"path": path, "status": "ok", "ellipses": ellipses.tolist(), "ms": round(ms, 4),
           "backend": figures["backend"]}
    if figures["caps_hit"]:
        rec["caps_hit"] = figures["caps_hit"]
    if gt is not None:
        truth, boxes, error = _truth(gt, path)
        if error is not None:
            rec["gt"] = {"error": error}
        else:
            detected, n_truth, correct = _ellipsekit.match_counts(ellipses, truth, boxes)
            rec["gt"] = {"detected": detected, "truth": n_truth, "correct": correct}
    return rec


def run_chunk(paths, assignments, gt=None):
    """Decodes and detects each image of `paths`; returns their JSON lines as one str.

    assignments: tuple of "name=value" option texts (ellipsekit::SetOption). gt: None, or
    {"dir": folder of <stem>.txt, "dont_care": {stem: [(x0, y0, x1, y1), ...]}} to score each image
    as `ellipsekit eval` does. A problem with one image goes into its line; the chunk goes on.
    """
    lines = []
    for path in paths:
        try:
            rec = _record(path, assignments, gt)
        except Exception as e:  # noqa: BLE001 - one image must never lose the chunk
            rec = {"path": path, "status": f"error: {type(e).__name__}: {e}", "ellipses": [], "ms": None,
                   "backend": None}
        lines.append(json.dumps(rec, separators=(", ", ": ")) + "\n")
    return "".join(lines)


def _sweep_record(path, points, gt):
    image, problem, _note = _ellipsekit.load_gray(path)
    if image is None:
        return {"path": path, "status": problem}
    truth, boxes, error = _truth(gt, path)
    if error is not None:
        return {"path": path, "status": f"no ground truth: {error}"}
    counts = []
    sizes = getattr(_local, "sweep_sizes", None)
    if sizes is None:
        sizes = _local.sweep_sizes = {}
    for assignments in points:
        detector = _detector(assignments)
        # A Detector's first frame of a size allocates its buffers: an untimed detection first, as
        # `ellipsekit eval` warms up, so that ms is the frame's own work.
        if sizes.get(assignments) != image.shape:
            detector.detect(image)
            sizes[assignments] = image.shape
        start = time.perf_counter()
        ellipses, _figures = detector.detect(image)
        ms = (time.perf_counter() - start) * 1e3
        counts.append(list(_ellipsekit.match_counts(ellipses, truth, boxes)) + [ms])
    return {"path": path, "status": "ok", "counts": counts}


def sweep_chunk(paths, points, gt):
    """What `python3 -m ellipsekit.sweep` runs per task: each image of `paths` decoded once and
    detected with every option set of `points` (tuples of "name=value" texts), scored against `gt`
    ({"dir", "dont_care"}, as run_chunk's) as `ellipsekit eval` scores. Returns one record per image:
    {"path", "status": "ok", "counts": [[detected, truth, correct, ms], ...] (one per point)} or
    {"path", "status": the problem}; a problem with one image never loses the chunk."""
    records = []
    for path in paths:
        try:
            records.append(_sweep_record(path, points, gt))
        except Exception as e:  # noqa: BLE001 - one image must never lose the chunk
            records.append({"path": path, "status": f"error: {type(e).__name__}: {e}"})
    return records


def describe():
    """What a worker runs, checked by the client before any work is sent (a worker machine without
    the package, or with another version of it, would fail every chunk)."""
    import ellipsekit
    return ellipsekit.__version__
