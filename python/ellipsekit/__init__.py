"""ellipsekit: fast ellipse detection (Dong et al., IEEE T-RO 2018) for 8-bit camera frames.

    import ellipsekit
    detector = ellipsekit.Detector()                       # the C++ defaults, best backend
    ellipses = detector.detect(ellipsekit.read_gray("frame.png"))   # (N, 6): cx, cy, a, b, theta, score

Detector options are the fields of the C++ ``ellipsekit::Options`` under the same names as the
CLI's ``--option NAME=VALUE`` (include/ellipsekit/options.h), e.g.
``Detector(backend="scalar", split_angle_deg=30, center_method="arc_chords")``.

Batch runs over many files (a Dask cluster, one JSON line per image):
``python3 -m ellipsekit.batch INPUT... --out results.jsonl`` (see ``ellipsekit.batch``); every
combination of option values scored over a dataset:
``python3 -m ellipsekit.sweep DATASET --grid NAME=V1,V2,...`` (see ``ellipsekit.sweep``).
The robot adapter's camera model, circle pose and ``ellipsekit track`` are in ``ellipsekit.robot``.
"""

import errno as _errno
import numbers as _numbers
import os as _os

import numpy as _np

from ellipsekit import _ellipsekit
from ellipsekit._detections import Detections

__all__ = ["Detector", "Detections", "read_gray", "OPTION_NAMES"]
__version__ = "0.1.0"

# The option names (the fields of struct Options, in its order), for help() and completion; generated
# from include/ellipsekit/options.h by the build. Parsing and checking are the C++ library's
# (ellipsekit::SetOption, ValidateOptions), so a name missing here still works.
from ellipsekit._option_names import OPTION_NAMES


def _option_text(name, value):
    """One keyword argument as the "name=value" text ellipsekit::SetOption parses.

    Floats are written with repr(), the shortest text that reads back as the same double, so a
    value reaches the detector bit for bit as `--option NAME=VALUE` with that text would.
    """
    if isinstance(value, (bool, _np.bool_)):
        text = "true" if value else "false"
    elif isinstance(value, _numbers.Integral):
        text = str(int(value))
    elif isinstance(value, _numbers.Real):
        text = repr(float(value))
    elif isinstance(value, str):
        text = value
    else:
        raise ValueError(f"option {name}: bad value {value!r} of type {type(value).__name__}; "
                         "expected a number, a bool or a str")
    return f"{name}={text}"


class Detector:
    """An ellipse detector with its options fixed at construction.

    backend: "auto" (the SIMD kernels on this CPU), "scalar" (the reference), "simd" or "vulkan";
        every backend gives the same ellipses.
    options: any field of ellipsekit::Options by its name, as the CLI's --option NAME=VALUE
        (see ellipsekit.OPTION_NAMES and include/ellipsekit/options.h for meaning and defaults):
        numbers (split_angle_deg=30, max_triplets=2000), booleans (refine_fit=False) and the
        enumerations as strings (center_method="arc_chords", inlier_rule="algebraic",
        obb_rule="side_ratio", cluster_rule="relative"); simd_target="AVX2" picks a Highway target.

    Raises ValueError naming the option and what it accepts for an unknown name or a bad value
    (the C++ library's SetOption / ValidateOptions messages), RuntimeError when the backend asked
    for cannot run here (e.g. "vulkan" without a device).

    A Detector keeps its buffers between frames (no allocation after the first frame of a size).
    detect() releases the GIL: use one Detector per thread to run threads in parallel (a Detector
    shared between threads is safe, but its calls run one at a time).
    """

    def __init__(self, backend="auto", **options):
        assignments = [_option_text("backend", backend)]
        assignments += [_option_text(name, value) for name, value in options.items()]
        self._core = _ellipsekit.Detector(assignments)
        self._options = dict(options)
        self._options["backend"] = backend

    def detect(self, image):
        """Finds the ellipses in one frame.

        image: a numpy uint8 array, either (H, W) gray or (H, W, 3) colour in BGR order (OpenCV's,
            as cv2.imread returns it), converted to gray exactly as `ellipsekit detect` does
            (cv::cvtColor: 0.299 R + 0.587 G + 0.114 B). Any row stride: a slice of a larger
            frame is read in place when its pixels are contiguous within a row, and copied once
            otherwise (e.g. a column-strided view or a Fortran-ordered array).

        Returns a Detections array of shape (N, 6), float64: cx, cy, a, b, theta, score per row,
        best first (score: the share of the outline that edges back, 0-1; see types.h); the
        frame's figures are its attributes (timings, counts, caps_hit, backend, simd_target).
        Bit-identical to `ellipsekit detect` on the same pixels and options.

        Raises TypeError for anything but a uint8 array of those shapes, ValueError for a frame
        the detector refuses (e.g. 0 pixels, over max_image_pixels).
        """
        ellipses, figures = self._core.detect(image)
        return Detections._wrap(ellipses, figures)

    @property
    def options(self):
        """The options given at construction (name -> value), backend included."""
        return dict(self._options)

    @property
    def backend_note(self):
        """Why the backend or SIMD target that runs differs from the one asked for; "" when it does not."""
        return self._core.backend_note

    def __repr__(self):
        args = ", ".join(f"{k}={v!r}" for k, v in self._options.items())
        return f"ellipsekit.Detector({args})"


def _load_error(path, problem):
    """The exception for a loader problem: OSError subclasses for file-system problems, ValueError
    for files that are not (usable) images. The text is the CLI's: "PATH: problem"."""
    message = f"{path}: {problem}"
    kinds = {
        "no such file": (FileNotFoundError, _errno.ENOENT),
        "is a directory, not an image": (IsADirectoryError, _errno.EISDIR),
        "cannot read (permission denied)": (PermissionError, _errno.EACCES),
        "cannot read (I/O error)": (OSError, _errno.EIO),
    }
    if problem in kinds:
        cls, code = kinds[problem]
        err = cls(message)
        err.errno = code  # (strerror and filename stay unset: str(err) is then the CLI's text)
        return err
    return ValueError(message)


def read_gray(path):
    """Reads an image file as an 8-bit gray (H, W) numpy array, exactly as `ellipsekit detect` does.

    Any format OpenCV decodes (png, jpg, bmp, ...); colour is converted to gray (cv::cvtColor),
    alpha dropped, 16-bit scaled to 8-bit (value / 257). Damaged files (decoder warnings about
    corrupt or truncated data, a JPEG without its end marker) are errors, not images.

    Raises FileNotFoundError, IsADirectoryError, PermissionError or OSError for a file that cannot
    be read, ValueError for one that is not a usable image (empty, not decodable, truncated,
    corrupt, unsupported depth or channels, under 3 px a side); the message is the CLI's
    "PATH: problem" line without the "ellipsekit detect: " prefix.
    """
    path = _os.fspath(path)
    image, problem, _note = _ellipsekit.load_gray(path)
    if image is None:
        raise _load_error(path, problem)
    return image
