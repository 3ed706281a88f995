"""The result type of Detector.detect(): an (N, 6) float64 array carrying the frame's figures."""

import numpy as np

_FIGURES = ("timings", "counts", "caps_hit", "backend", "simd_target", "input_copied")


class Detections(np.ndarray):
    """Ellipses found in one frame: a float64 numpy array of shape (N, 6).

    Columns: cx, cy, a, b, theta, score -- centre (px), semi-axes a >= b (px), major-axis angle
    (rad, in [-pi/2, pi/2), OpenCV's RotatedRect angle), validation score. Rows are best score
    first, in the order and with the values `ellipsekit detect` prints for the same pixels.
    Pixel centres are at integer coordinates, x right, y down.

    Attributes (the frame's figures, also carried by slices and views of the array):
      timings      dict of stage wall times in ms: edges_ms, curves_ms, arcs_ms, fit_ms,
                   validate_ms, total_ms
      counts       dict: edge_pixels, curves, arcs, pairs, triplets, candidates, noise_sigma (the
                   frame's noise, grey levels), denoise_passes (extra smoothing passes it asked for)
      caps_hit     list of the caps that bounded the work ("max_triplets", ...); [] when none,
                   otherwise the result may be partial
      backend      the backend that ran: "scalar", "simd" or "vulkan"
      simd_target  the Highway target that ran ("AVX2", ...) when backend is "simd", else ""
      input_copied True when the frame had to be gathered into a buffer first (pixels not
                   contiguous within a row, or a negative stride); False when read in place
    """

    timings: dict
    counts: dict
    caps_hit: list
    backend: str
    simd_target: str
    input_copied: bool

    @classmethod
    def _wrap(cls, ellipses, figures):
        out = ellipses.view(cls)
        for name in _FIGURES:
            setattr(out, name, figures[name])
        return out

    def __array_finalize__(self, obj):
        if obj is None:
            return
        for name in _FIGURES:
            setattr(self, name, getattr(obj, name, None))

    def __reduce__(self):
        # Pickle the figures with the array (numpy's own reduce drops instance attributes).
        reconstruct, args, state = super().__reduce__()
        return reconstruct, args, (state, {n: getattr(self, n, None) for n in _FIGURES})

    def __setstate__(self, state):
        array_state, figures = state
        super().__setstate__(array_state)
        for name, value in figures.items():
            setattr(self, name, value)
