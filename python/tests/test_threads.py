"""The GIL is released while detecting: other Python threads run, and two Detectors in two threads
finish a batch of frames faster than one.

The speed-up test runs on a shared 2-core machine (other builds may run beside it), so it asks
for 1.3x (two idle cores give about 1.9x) and takes the best of up to five attempts of
2 x 240 frames of 640x480 each; when it falls short while the 1-minute load average shows other
work leaving fewer than two cores free, it is skipped with the figures instead of failing.
"""
import os
import threading
import time

import numpy as np
import pytest

import ellipsekit
from conftest import DATASETS

FRAMES = sorted(os.path.join(DATASETS, "smartphone_subset", "images", f)
                for f in os.listdir(os.path.join(DATASETS, "smartphone_subset", "images")))


@pytest.fixture(scope="module")
def frames():
    return [ellipsekit.read_gray(p) for p in FRAMES]


def test_python_runs_while_a_frame_is_detected():
    # A large scalar frame takes tens of ms; the main thread counts how long it ran meanwhile.
    rng = np.random.default_rng(3)
    frame = rng.integers(0, 256, (1080, 1920), dtype=np.uint8)
    detector = ellipsekit.Detector("scalar")
    detector.detect(frame)  # buffers sized
    started, finished = threading.Event(), threading.Event()
    span = {}

    def work():
        started.set()
        t0 = time.perf_counter()
        detector.detect(frame)
        span["detect"] = time.perf_counter() - t0
        finished.set()

    t = threading.Thread(target=work)
    t.start()
    started.wait()
    ran = 0.0
    while not finished.is_set():
        t0 = time.perf_counter()
        sum(range(200))  # pure Python: needs the GIL
        ran += time.perf_counter() - t0
    t.join()
    assert span["detect"] > 0.02, span
    # With the GIL held through detect() the main thread could run for at most one switch
    # interval (5 ms) of it; released, it runs through most of it.
    assert ran > 0.5 * span["detect"], (ran, span)


def test_two_detectors_in_two_threads_scale(frames):
    work = frames * 60  # 240 frames per thread: ~0.2 s each (thread start-up and noise stay small)

    def run(detector, out):
        for f in work:
            out.append(detector.detect(f))

    ratios = []
    for _attempt in range(5):
        d1, d2 = ellipsekit.Detector(), ellipsekit.Detector()
        run(d1, []), run(d2, [])  # warm: buffers sized
        t0 = time.perf_counter()
        one = []
        run(d1, one)
        run(d1, one)
        serial = time.perf_counter() - t0
        outs = ([], [])
        threads = [threading.Thread(target=run, args=(d, o)) for d, o in zip((d1, d2), outs)]
        t0 = time.perf_counter()
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        parallel = time.perf_counter() - t0
        for a, b in zip(one, outs[0] + outs[1]):
            np.testing.assert_array_equal(a, b)
        ratios.append(serial / parallel)
        if ratios[-1] >= 1.3:
            break
    if os.cpu_count() < 2:
        pytest.skip("one core: no parallel speed-up possible")
    load = os.getloadavg()[0]
    if max(ratios) < 1.3 and load > os.cpu_count() - 1:
        # The 1-minute load average is other work (this test runs for about a second): when it
        # leaves less than two cores free, no speed-up can be measured. (That the GIL is released
        # is checked by test_python_runs_while_a_frame_is_detected, whatever the load.)
        pytest.skip(f"machine busy (load average {load:.1f} on {os.cpu_count()} cores); speed-ups {ratios}")
    assert max(ratios) >= 1.3, f"two threads / one thread speed-ups: {ratios} (load average {load:.1f})"


def test_one_detector_shared_by_threads_stays_correct(frames):
    detector = ellipsekit.Detector()
    expected = [detector.detect(f) for f in frames]
    errors = []

    def run():
        for _ in range(5):
            for f, e in zip(frames, expected):
                if not np.array_equal(detector.detect(f), e):
                    errors.append("mismatch")

    threads = [threading.Thread(target=run) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
