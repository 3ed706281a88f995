"""Detector.detect() against `ellipsekit detect --format json` on every shared dataset image.

With --exact the CLI prints each ellipse number with 17 significant digits; each double detect()
returns must equal the CLI's bit for bit, in the same order, with the same counts, caps and backend.
"""
import numpy as np
import pytest

import ellipsekit
from conftest import cli_detect_json, cli_rows, dataset_images, exact_rows

IMAGES = dataset_images()


def test_there_are_shared_images():
    assert len(IMAGES) >= 30, IMAGES


@pytest.mark.parametrize("options, cli_options", [
    ({}, []),
    ({"backend": "scalar", "split_angle_deg": 30.1, "center_method": "arc_chords", "refine_fit": False},
     ["--backend", "scalar", "--option", "split_angle_deg=30.1", "--option", "center_method=arc_chords",
      "--option", "refine_fit=false"]),
], ids=["defaults", "options"])
def test_same_ellipses_as_the_cli(options, cli_options):
    reports = cli_detect_json(IMAGES, *cli_options)
    assert set(reports) == set(IMAGES)
    detector = ellipsekit.Detector(**options)
    total = 0
    for path in IMAGES:
        rep = reports[path]
        r = detector.detect(ellipsekit.read_gray(path))
        assert exact_rows(r) == cli_rows(rep), path
        counts = dict(rep["counts"])
        assert counts.pop("caps_hit") == r.caps_hit, path
        assert counts == r.counts, path
        assert rep["backend"] == r.backend, path
        total += len(r)
    assert total > 50  # ~75 on the paper's path, ~150 by default; a broken loader would find none


def test_a_frame_and_its_copy_in_a_larger_buffer_agree_with_the_cli():
    path = IMAGES[0]
    rep = cli_detect_json([path])[path]
    gray = ellipsekit.read_gray(path)
    big = np.zeros((gray.shape[0] + 3, gray.shape[1] + 5), np.uint8)
    big[1:-2, 2:-3] = gray
    r = ellipsekit.Detector().detect(big[1:-2, 2:-3])
    assert not r.input_copied
    assert exact_rows(r) == cli_rows(rep)
