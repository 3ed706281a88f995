# Type stub of the ellipsekit package (the module's code: python/ellipsekit/__init__.py, the
# compiled core: python/src/module.cc).
from os import PathLike
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

__version__: str
OPTION_NAMES: tuple[str, ...]

_Backend = Literal["auto", "scalar", "simd", "vulkan"]
_OptionValue = bool | int | float | str

class Detections(np.ndarray[Any, np.dtype[np.float64]]):
    """(N, 6) float64: cx, cy, a, b, theta, score per row, best first; the frame's figures as attributes."""

    timings: dict[str, float]  # edges_ms, curves_ms, arcs_ms, fit_ms, validate_ms, total_ms
    counts: dict[str, int]  # edge_pixels, curves, arcs, pairs, triplets, candidates
    caps_hit: list[str]  # e.g. ["max_triplets"]; [] when no cap bounded the work
    backend: Literal["scalar", "simd", "vulkan"]
    simd_target: str  # "AVX2", ... when backend == "simd", else ""
    input_copied: bool  # the frame was gathered into a buffer (pixels not contiguous in a row)

class Detector:
    """An ellipse detector; options are ellipsekit::Options fields by name (the CLI's --option names)."""

    def __init__(
        self,
        backend: _Backend = "auto",
        *,
        simd_target: str = ...,
        gaussian_blur: bool = ...,
        canny_high_permille: int = ...,
        canny_low_permille: int = ...,
        canny_min_high: int = ...,
        canny_contrast_ref: int = ...,
        canny_tile: int = ...,
        min_curve_points: int = ...,
        obb_rule: Literal["min_side", "side_ratio"] = ...,
        obb_threshold: float = ...,
        polyline_tolerance: float = ...,
        split_angle_deg: float = ...,
        crowd_min_curve_points: int = ...,
        crowd_min_short_curves: int = ...,
        crowd_min_small_found: int = ...,
        crowd_max_minor_axis: float = ...,
        crowd_min_similar: int = ...,
        closed_min_support: float = ...,
        crowd_closed_min_support: float = ...,
        center_method: Literal["longest_chords", "arc_chords"] = ...,
        fit_pair_centers: bool = ...,
        pair_reach: float = ...,
        retire_found_arcs: bool = ...,
        center_distance: float = ...,
        mean_shift_bandwidth: float = ...,
        distance_ratio: float = ...,
        length_ratio: float = ...,
        inlier_rule: Literal["algebraic", "pixel"] = ...,
        inlier_threshold: float = ...,
        circumference_ratio: float = ...,
        cluster_rule: Literal["feature_distance", "relative"] = ...,
        cluster_distance: float = ...,
        cluster_relative: float = ...,
        cluster_outer_margin: float = ...,
        rim_min_coverage: float = ...,
        min_edge_coverage: float = ...,
        min_exclusive_coverage: float = ...,
        max_striped_share: float = ...,
        max_nested_striped_share: float = ...,
        cluster_pick_best_fit: bool = ...,
        cluster_recessed_rims: bool = ...,
        refit_to_edges: bool = ...,
        refine_fit: bool = ...,
        refined_circumference_ratio: float = ...,
        pair_candidates: bool = ...,
        pair_min_edge_coverage: float = ...,
        min_axis_ratio: float = ...,
        max_arcs: int = ...,
        max_pairs: int = ...,
        max_triplets: int = ...,
        max_candidates: int = ...,
        max_mean_shift_iterations: int = ...,
        max_image_pixels: int = ...,
        **options: _OptionValue,  # any other field of Options (ellipsekit.OPTION_NAMES)
    ) -> None: ...
    def detect(self, image: npt.NDArray[np.uint8]) -> Detections:
        """(H, W) gray or (H, W, 3) BGR uint8, any row stride; releases the GIL."""
    @property
    def options(self) -> dict[str, _OptionValue]: ...
    @property
    def backend_note(self) -> str: ...

def read_gray(path: str | PathLike[str]) -> npt.NDArray[np.uint8]:
    """An image file as (H, W) uint8, decoded as `ellipsekit detect` does; OSError / ValueError with the CLI's text."""
