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


def _detector(assignments):
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



def describe():
    """What a worker runs, checked by the client before any work is sent (a worker machine without
    the package, or with another version of it, would fail every chunk)."""
    import ellipsekit
    return ellipsekit.__version__
