"""The Python API: options and their errors, input arrays (strides, copies, colour), read_gray, results."""
import ast
import os
import pickle
import re
import struct

import numpy as np
import pytest

import ellipsekit
from conftest import DATASETS, REPO, run_cli

SCENE_BMP = os.path.join(DATASETS, "smartphone_subset", "images", "04_00010.bmp")
PRASAD = os.path.join(DATASETS, "prasad_subset", "images")


def options_h_fields():
    """The field names of struct Options in include/ellipsekit/options.h (python/gen_option_names.py)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("gen", os.path.join(REPO, "python", "gen_option_names.py"))
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    return gen.option_names(open(os.path.join(REPO, "include", "ellipsekit", "options.h"), encoding="utf-8").read())


def read_bmp24(path):
    """A 24-bit uncompressed BMP as an (H, W, 3) BGR array (the file's own byte order)."""
    data = open(path, "rb").read()
    offset, = struct.unpack_from("<I", data, 10)
    width, height, _planes, bpp, compression = struct.unpack_from("<iiHHI", data, 18)
    assert bpp == 24 and compression == 0
    row = (width * 3 + 3) // 4 * 4
    rows = np.frombuffer(data, np.uint8, row * abs(height), offset).reshape(abs(height), row)[:, :width * 3]
    image = rows.reshape(abs(height), width, 3)
    return np.ascontiguousarray(image[::-1] if height > 0 else image)


@pytest.fixture(scope="module")
def gray():
    return ellipsekit.read_gray(SCENE_BMP)


@pytest.fixture(scope="module")
def detector():
    return ellipsekit.Detector()


# ---------------------------------------------------------------- options

def test_option_names_are_the_options_h_fields():
    fields = options_h_fields()
    assert len(fields) > 30, fields
    assert {"backend", "split_angle_deg", "center_method", "max_triplets", "refine_fit"} <= set(fields)
    assert list(ellipsekit.OPTION_NAMES) == fields  # the build regenerated them from this header


@pytest.mark.parametrize("name", [n for n in ellipsekit.OPTION_NAMES if n != "simd_target"])
def test_every_option_is_known_to_the_parser(name):
    # A value no field accepts: the parser must name the field and what it expects, not call it unknown.
    with pytest.raises(ValueError) as e:
        ellipsekit.Detector(**{name: "not-a-value"}) if name != "backend" else ellipsekit.Detector("not-a-value")
    assert f"option {name}: bad value 'not-a-value', expected " in str(e.value)


def test_unknown_option():
    with pytest.raises(ValueError, match=r"^unknown option 'split_angle'; the options are: ") as e:
        ellipsekit.Detector(split_angle=30)
    # Every accepted name is listed, and only those.
    listed = str(e.value).split("; the options are: ", 1)[1].split(", ")
    assert sorted(listed) == sorted(ellipsekit.OPTION_NAMES)


@pytest.mark.parametrize("kwargs, message", [
    ({"split_angle_deg": 75}, "split_angle_deg (T_theta) must be in (0, 60] degrees"),
    ({"split_angle_deg": float("nan")}, "split_angle_deg (T_theta) must be in (0, 60] degrees"),
    ({"canny_high_permille": 1001}, "canny_high_permille must be in [0, 1000]"),
    ({"min_curve_points": 2}, "min_curve_points (T_n) must be >= 3"),
    ({"max_triplets": 0}, "caps (max_arcs, max_pairs, max_triplets, max_candidates, max_mean_shift_iterations) must be >= 1"),
    ({"max_arcs": 1.5}, "option max_arcs: bad value '1.5', expected an integer"),
    ({"refine_fit": "maybe"}, "option refine_fit: bad value 'maybe', expected true or false"),
    ({"center_method": "best"}, "option center_method: bad value 'best', expected longest_chords or arc_chords"),
    ({"max_pairs": [1]}, "option max_pairs: bad value [1] of type list; expected a number, a bool or a str"),
])
def test_bad_values_name_the_option_and_range(kwargs, message):
    with pytest.raises(ValueError) as e:
        ellipsekit.Detector(**kwargs)
    assert str(e.value) == message


def test_options_reach_the_detector(gray):
    default = ellipsekit.Detector().detect(gray)
    noise = np.random.default_rng(5).integers(0, 256, (240, 320), dtype=np.uint8)
    capped = ellipsekit.Detector(max_arcs=1).detect(noise)
    assert "max_arcs" in capped.caps_hit and capped.counts["arcs"] <= 1
    assert "max_arcs" not in ellipsekit.Detector().detect(noise).caps_hit
    assert default.caps_hit == []
    # numpy scalars and bools are accepted like Python's
    same = ellipsekit.Detector(max_triplets=np.int64(6000), refine_fit=np.bool_(True),
                               split_angle_deg=np.float64(35.0)).detect(gray)
    np.testing.assert_array_equal(same, default)


def test_backends_agree(gray):
    simd = ellipsekit.Detector("auto").detect(gray)
    scalar = ellipsekit.Detector("scalar").detect(gray)
    assert scalar.backend == "scalar" and scalar.simd_target == ""
    np.testing.assert_array_equal(simd, scalar)


def test_options_property_and_repr():
    d = ellipsekit.Detector("scalar", refine_fit=False)
    assert d.options == {"backend": "scalar", "refine_fit": False}
    assert repr(d) == "ellipsekit.Detector(refine_fit=False, backend='scalar')"


# ---------------------------------------------------------------- results

def test_result_array_and_figures(gray, detector):
    r = detector.detect(gray)
    assert isinstance(r, ellipsekit.Detections) and isinstance(r, np.ndarray)
    assert r.dtype == np.float64 and r.ndim == 2 and r.shape[1] == 6 and r.shape[0] == 2
    assert np.all(r[:, 2] >= r[:, 3]) and np.all(r[:, 3] > 0)
    assert np.all((r[:, 4] >= -np.pi / 2) & (r[:, 4] < np.pi / 2))
    assert list(r[:, 5]) == sorted(r[:, 5], reverse=True)
    assert set(r.timings) == {"edges_ms", "curves_ms", "arcs_ms", "fit_ms", "validate_ms", "total_ms"}
    assert r.timings["total_ms"] > 0
    assert set(r.counts) == {"edge_pixels", "curves", "arcs", "pairs", "triplets", "candidates", "noise_sigma",
                             "denoise_passes"}
    assert 0 <= r.counts["noise_sigma"] < 5 and r.counts["denoise_passes"] == 0
    assert r.counts["edge_pixels"] > 1000 and r.counts["arcs"] > 0
    assert r.caps_hit == [] and r.backend == "simd" and r.simd_target != "" and r.input_copied is False
    # figures follow slices and survive pickling
    assert r[:1].counts == r.counts
    back = pickle.loads(pickle.dumps(r))
    np.testing.assert_array_equal(back, r)
    assert back.counts == r.counts and back.backend == r.backend


def test_frame_without_ellipses(detector):
    r = detector.detect(np.full((48, 64), 128, np.uint8))
    assert r.shape == (0, 6) and r.dtype == np.float64 and r.counts["edge_pixels"] == 0


# ---------------------------------------------------------------- input arrays

def test_slice_of_larger_frame_is_read_in_place(gray, detector):
    expected = detector.detect(gray)
    big = np.random.default_rng(1).integers(0, 256, (gray.shape[0] + 120, gray.shape[1] + 200), dtype=np.uint8)
    big[50:50 + gray.shape[0], 70:70 + gray.shape[1]] = gray
    view = big[50:50 + gray.shape[0], 70:70 + gray.shape[1]]
    assert view.strides == (big.shape[1], 1)
    r = detector.detect(view)
    assert r.input_copied is False
    np.testing.assert_array_equal(r, expected)
    # a read-only view is fine too
    view.flags.writeable = False
    np.testing.assert_array_equal(detector.detect(view), expected)


@pytest.mark.parametrize("make", [
    lambda g: np.asfortranarray(g),                       # column-major
    lambda g: np.repeat(g, 2, axis=1)[:, ::2],            # pixels 2 bytes apart
    lambda g: g[::-1][::-1],                               # (a view of a view; contiguous again)
    lambda g: np.ascontiguousarray(g[::-1])[::-1],         # negative row stride
], ids=["fortran", "column_step", "double_flip", "negative_stride"])
def test_strided_views_give_the_same_ellipses(gray, detector, make):
    view = make(gray)
    np.testing.assert_array_equal(view, gray)
    r = detector.detect(view)
    np.testing.assert_array_equal(r, detector.detect(gray))
    contiguous_rows = view.strides[1] == 1 and view.strides[0] >= view.shape[1]
    assert r.input_copied is (not contiguous_rows)


def test_bgr_array_is_converted_as_the_cli_converts(detector):
    bgr = read_bmp24(SCENE_BMP)
    assert bgr.shape == (480, 640, 3)
    from_file = ellipsekit.read_gray(SCENE_BMP)  # the CLI's loader: cv::cvtColor(BGR2GRAY)
    r = detector.detect(bgr)
    np.testing.assert_array_equal(r, detector.detect(from_file))
    # the same on a strided colour view (copied once), and the weights are BGR's, not RGB's
    wide = np.zeros((480, 700, 3), np.uint8)
    wide[:, 30:670] = bgr
    np.testing.assert_array_equal(detector.detect(wide[:, 30:670]), r)
    np.testing.assert_array_equal(detector.detect(np.asfortranarray(bgr)), r)
    weights = np.array([0.114, 0.587, 0.299])
    assert np.abs(bgr.astype(float) @ weights - from_file).max() <= 1.0


@pytest.mark.parametrize("image, what", [
    (np.zeros((20, 20), np.float32), "dtype float32 and shape (20, 20)"),
    (np.zeros((20, 20), np.int8), "dtype int8 and shape (20, 20)"),
    (np.zeros((20, 20), np.uint16), "dtype uint16 and shape (20, 20)"),
    (np.zeros((20, 20, 4), np.uint8), "dtype uint8 and shape (20, 20, 4)"),
    (np.zeros((20, 20, 1), np.uint8), "dtype uint8 and shape (20, 20, 1)"),
    (np.zeros(400, np.uint8), "dtype uint8 and shape (400,)"),
    (np.zeros((2, 20, 20, 3), np.uint8), "dtype uint8 and shape (2, 20, 20, 3)"),
])
def test_other_arrays_raise_type_error(detector, image, what):
    with pytest.raises(TypeError) as e:
        detector.detect(image)
    assert what in str(e.value) and "uint8" in str(e.value)


def test_non_arrays_raise_type_error(detector):
    with pytest.raises(TypeError, match="got list"):
        detector.detect([[0, 1], [2, 3]])
    with pytest.raises(TypeError, match="got NoneType"):
        detector.detect(None)


def test_refused_frames_raise_value_error(detector):
    with pytest.raises(ValueError, match=r"^image size 10x0 is not positive$"):
        detector.detect(np.zeros((0, 10), np.uint8))
    with pytest.raises(ValueError, match="more than max_image_pixels = 100"):
        ellipsekit.Detector(max_image_pixels=100).detect(np.zeros((20, 20), np.uint8))


# ---------------------------------------------------------------- read_gray

def test_read_gray_matches_the_cli_loader():
    img = ellipsekit.read_gray(os.path.join(PRASAD, "002_0038.jpg"))
    assert img.dtype == np.uint8 and img.shape == (235, 237) and img.flags.c_contiguous
    assert 20 < img.mean() < 235


def test_read_gray_errors_are_the_cli_errors(tmp_path):
    good = open(os.path.join(PRASAD, "002_0038.jpg"), "rb").read()
    (tmp_path / "empty.png").write_bytes(b"")
    (tmp_path / "text.png").write_text("not an image\n")
    (tmp_path / "cut.jpg").write_bytes(good[: len(good) // 2])
    (tmp_path / "adir").mkdir()
    cases = {
        "missing.png": FileNotFoundError,
        "adir": IsADirectoryError,
        "empty.png": ValueError,
        "text.png": ValueError,
        "cut.jpg": ValueError,
    }
    paths = [str(tmp_path / name) for name in cases]
    r = run_cli("detect", *paths, check=False)
    assert r.returncode == 1
    cli_lines = [line for line in r.stderr.splitlines() if line.startswith("ellipsekit detect: ")]
    assert len(cli_lines) == len(cases), r.stderr
    for (name, kind), path, line in zip(cases.items(), paths, cli_lines):
        with pytest.raises(kind) as e:
            ellipsekit.read_gray(path)
        assert "ellipsekit detect: " + str(e.value) == line
    with pytest.raises(FileNotFoundError) as e:
        ellipsekit.read_gray(tmp_path / "missing.png")  # a PathLike
    assert e.value.errno == 2


# ---------------------------------------------------------------- documentation

def test_docstrings_and_stub():
    import ellipsekit.robot
    for obj in (ellipsekit, ellipsekit.Detector, ellipsekit.Detector.detect, ellipsekit.read_gray,
                ellipsekit.Detections, ellipsekit.robot.circle_pose, ellipsekit.robot.track_sequence,
                ellipsekit.robot.CameraModel):
        assert obj.__doc__ and len(obj.__doc__) > 60, obj
    pkg = os.path.dirname(ellipsekit.__file__)
    stub = ast.parse(open(os.path.join(pkg, "__init__.pyi"), encoding="utf-8").read())
    names = {n.name for n in ast.walk(stub) if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    assert {"Detector", "Detections", "detect", "read_gray"} <= names
    init = next(n for n in ast.walk(stub) if isinstance(n, ast.FunctionDef) and n.name == "__init__")
    typed = {a.arg for a in init.args.kwonlyargs}
    assert len(typed) > 30 and typed <= set(ellipsekit.OPTION_NAMES)  # newer options: **options
    assert init.args.kwarg is not None
    assert os.path.exists(os.path.join(pkg, "py.typed")) and os.path.exists(os.path.join(pkg, "robot.pyi"))
