"""The robot adapter where a script needs it (include/ellipsekit/robot/).

    from ellipsekit.robot import CameraModel, circle_pose, track_sequence
    cam = CameraModel(fx=600, fy=600, cx=320, cy=240)
    pose = circle_pose(ellipses[0], radius=0.033, camera=cam, normal=(0, -0.5, -0.87))
    records = track_sequence("run/", radius=0.033)    # what `ellipsekit track` writes, per frame

Frames and units: the camera optical frame (x right, y down, z forward), metres; pixels with
centres at integer coordinates.
"""

import json as _json
import os as _os
import tempfile as _tempfile
from typing import NamedTuple

import numpy as _np

from ellipsekit import _ellipsekit
from ellipsekit._ellipsekit import CameraModel

__all__ = ["CameraModel", "CirclePose", "circle_pose", "track_sequence"]


class CirclePose(NamedTuple):
    """A circle's pose in the camera frame (metres)."""

    centre: _np.ndarray        # (3,) circle centre
    normal: _np.ndarray        # (3,) unit normal, towards the camera (normal . centre < 0)
    centre_pixel: _np.ndarray  # (2,) raw pixel where the centre projects (not the ellipse centre)


def _pose(d):
    return CirclePose(_np.asarray(d["centre"], dtype=float).reshape(3),
                      _np.asarray(d["normal"], dtype=float).reshape(3),
                      _np.asarray(d["centre_pixel"], dtype=float).reshape(2))


def circle_pose(ellipse, radius, camera, *, normal=None, depth_z=None):
    """Pose of a circle of known radius from its image (one ellipse; no depth image needed).

    ellipse: cx, cy, a, b, theta[, score] in raw pixels of `camera` (a row of Detector.detect()).
    radius: the circle's radius in metres. camera: a CameraModel.
    The projection of a circle has two solutions; pick one with
      normal=(nx, ny, nz): the expected plane normal in the camera frame (its sign does not matter),
      depth_z=z: a measured depth (metres) of the centre;
    with neither, both candidates are returned as a tuple.
    Returns a CirclePose (centre, normal, centre_pixel). Raises ValueError for a degenerate ellipse
    or a radius <= 0.
    """
    e = [float(v) for v in _np.asarray(ellipse, dtype=float).ravel()]
    if normal is not None and depth_z is not None:
        raise ValueError("circle_pose: give normal or depth_z, not both")
    if normal is not None:
        n = _np.asarray(normal, dtype=float).reshape(3)
        return _pose(_ellipsekit.circle_pose_by_normal(e, float(radius), camera, n))
    if depth_z is not None:
        return _pose(_ellipsekit.circle_pose_by_depth(e, float(radius), camera, float(depth_z)))
    first, second = _ellipsekit.circle_pose_candidates(e, float(radius), camera)
    return _pose(first), _pose(second)


def track_sequence(directory, *, conveyor=False, radius=None, latency=1.0):
    """Runs `ellipsekit track` on a sequence directory and returns its per-frame records.

    The same program (tools/cli/track_command.cc, compiled into this module): frames/NNNNNN.png,
    optional depth/NNNNNN.png (uint16 mm), timestamps.txt, camera.json, and conveyor.json with
    conveyor=True. radius (metres) gives the circle pose when there is no depth; latency (s) is the
    grasp planner's. Returns a list with one dict per frame, exactly the JSON objects
    `ellipsekit track DIR --out FILE` writes:
      {"t", "tracks": [{"id", "state", "pixel", "position", "velocity"}], "grasp": None | {...}}
    Raises ValueError with the program's message when the sequence cannot be tracked.
    """
    directory = _os.fspath(directory)
    with _tempfile.TemporaryDirectory(prefix="ellipsekit_track_") as tmp:
        out = _os.path.join(tmp, "track.jsonl")
        args = [directory, "--out", out, "--latency", repr(float(latency))]
        if conveyor:
            args.append("--conveyor")
        if radius is not None:
            args += ["--radius", repr(float(radius))]
        rc, err = _ellipsekit.run_track(args)
        if rc != 0:
            raise ValueError(err or f"ellipsekit track failed with status {rc}")
        with open(out, encoding="utf-8") as f:
            return [_json.loads(line) for line in f if line.strip()]
