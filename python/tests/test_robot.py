"""The robot adapter from Python: camera model, circle pose from a projected circle, track_sequence
equal to `ellipsekit track`."""
import json

import numpy as np
import pytest

from conftest import run_cli
from ellipsekit.robot import CameraModel, CirclePose, circle_pose, track_sequence


def fit_ellipse(points):
    """Exact conic through points (N >= 5) -> cx, cy, a, b, theta (a >= b, theta in [-pi/2, pi/2))."""
    x, y = points[:, 0], points[:, 1]
    A = np.column_stack([x * x, x * y, y * y, x, y, np.ones_like(x)])
    a, b, c, d, e, f = np.linalg.svd(A)[2][-1]
    M = np.array([[a, b / 2], [b / 2, c]])
    centre = np.linalg.solve(2 * M, [-d, -e])
    k = -(f + 0.5 * (d * centre[0] + e * centre[1]))
    w, v = np.linalg.eigh(M / k)
    axes = 1 / np.sqrt(w)  # ascending eigenvalues: major axis first
    theta = np.arctan2(v[1, 0], v[0, 0])
    theta = (theta + np.pi / 2) % np.pi - np.pi / 2
    return [centre[0], centre[1], axes[0], axes[1], theta]


def project_circle(camera, centre, normal, radius, n=64):
    normal = normal / np.linalg.norm(normal)
    u = np.cross(normal, [1.0, 0, 0])
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    pts = centre + radius * (np.outer(np.cos(t), u) + np.outer(np.sin(t), v))
    return np.array([camera.project(p) for p in pts])


def test_camera_model():
    cam = CameraModel(600.0, 610.0, 320.0, 240.0, width=640, height=480)
    assert (cam.fx, cam.fy, cam.cx, cam.cy, cam.width, cam.has_distortion) == (600, 610, 320, 240, 640, False)
    np.testing.assert_allclose(cam.K, [[600, 0, 320], [0, 610, 240], [0, 0, 1]])
    np.testing.assert_allclose(cam.project([0.1, -0.05, 1.0]), [380.0, 209.5])
    ray = cam.pixel_to_ray([380.0, 209.5])
    np.testing.assert_allclose(ray / ray[2], [0.1, -0.05, 1.0])
    with pytest.raises(ValueError):
        cam.project([0.0, 0.0, -1.0])
    with pytest.raises(ValueError, match="fx and fy must be > 0"):
        CameraModel(0.0, 600.0, 320.0, 240.0)
    distorted = CameraModel(600.0, 600.0, 320.0, 240.0, d=[-0.2, 0.05])
    assert distorted.has_distortion


def test_circle_pose_recovers_a_projected_circle():
    cam = CameraModel(600.0, 600.0, 320.0, 240.0)
    centre = np.array([0.08, 0.05, 0.7])
    normal = np.array([0.0, -0.6, -0.8])
    ellipse = fit_ellipse(project_circle(cam, centre, normal, 0.04))
    pose = circle_pose(ellipse, 0.04, cam, normal=normal)
    assert isinstance(pose, CirclePose)
    np.testing.assert_allclose(pose.centre, centre, atol=1e-6)
    np.testing.assert_allclose(pose.normal, normal, atol=1e-6)
    np.testing.assert_allclose(pose.centre_pixel, cam.project(centre), atol=1e-4)
    by_depth = circle_pose(ellipse, 0.04, cam, depth_z=0.7)
    np.testing.assert_allclose(by_depth.centre, centre, atol=1e-6)
    both = circle_pose(ellipse, 0.04, cam)
    assert len(both) == 2
    assert min(np.linalg.norm(p.centre - centre) for p in both) < 1e-6
    with pytest.raises(ValueError):
        circle_pose([320, 240, 10, 0, 0], 0.04, cam, normal=normal)  # b = 0: degenerate
    with pytest.raises(ValueError):
        circle_pose(ellipse, -1.0, cam, normal=normal)


def test_track_sequence_returns_what_the_cli_writes(tmp_path):
    seq = tmp_path / "stack"
    run_cli("scenes", "--stack", "--frames", "6", "--seed", "3", "--out", str(seq))
    out = tmp_path / "cli.jsonl"
    run_cli("track", str(seq), "--out", str(out))
    expected = [json.loads(line) for line in open(out)]
    got = track_sequence(seq)
    assert got == expected
    assert len(got) == 6 and len(got[-1]["tracks"]) >= 1
    assert {"t", "tracks", "grasp"} <= set(got[0])
    with pytest.raises(ValueError, match="not a directory"):
        track_sequence(tmp_path / "none")
