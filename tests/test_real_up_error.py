"""``benchmarks/real_up_error.py``'s floor truth (up66): hunt45's floors measured from the image's
bottom third, in the repository instead of a file outside it."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import real_up_error  # noqa: E402


def _view(pitch_deg: float, height: float, wall: float | None, speckle: float = 0.0, seed: int = 3,
          w: int = 160, h: int = 120, f: float = 120.0):
    """An organized cloud (H, W, 3) of a camera ``height`` m over a floor, pitched
    ``pitch_deg`` down, with a wall ``wall`` m ahead (or none) and ``speckle`` of the pixels
    without depth; and the floor's up in the camera frame."""
    t = math.radians(pitch_deg)
    # camera axes in the world (y up): x right, y down, z forward pitched down
    down = np.array([0.0, -math.cos(t), -math.sin(t)])  # camera y in world coords
    fwd = np.array([0.0, -math.sin(t), math.cos(t)])    # camera z in world coords
    right = np.array([1.0, 0.0, 0.0])
    u, v = np.meshgrid(np.arange(w) - (w - 1) / 2, np.arange(h) - (h - 1) / 2)
    rays = (u[..., None] * right + v[..., None] * down) / f + fwd          # world directions
    cam = np.array([0.0, height, 0.0])
    dist = np.full((h, w), np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        floor_t = np.where(rays[..., 1] < 0, -height / rays[..., 1], np.inf)
        dist = np.minimum(dist, floor_t)
        if wall is not None:
            dist = np.minimum(dist, np.where(rays[..., 2] > 0, wall / rays[..., 2], np.inf))
    world = cam + rays * dist[..., None]
    rel = world - cam
    xyz = np.stack([rel @ right, rel @ down, rel @ fwd], axis=-1)
    xyz[~np.isfinite(dist)] = np.nan
    rng = np.random.default_rng(seed)
    xyz = xyz + rng.normal(0, 0.003, xyz.shape)
    xyz[rng.random((h, w)) < speckle] = np.nan
    up_cam = np.array([np.array([0.0, 1.0, 0.0]) @ a for a in (right, down, fwd)])
    return xyz, up_cam


@pytest.mark.parametrize("pitch,height,speckle", [(0.0, 0.2, 0.0), (10.0, 0.3, 0.6), (-8.0, 0.15, 0.8)])
def test_the_floor_under_a_low_camera_is_measured(pitch, height, speckle):
    xyz, up = _view(pitch, height, wall=3.0, speckle=speckle)
    n = real_up_error.floor_truth(xyz)
    assert n is not None and n[1] < 0
    assert real_up_error.angle(n, up) < 1.0


def test_no_floor_in_the_bottom_third_is_no_truth():
    # a camera facing a wall 1 m ahead, no floor in view: no plane within the prior
    h, w, f = 120, 160, 120.0
    u, v = np.meshgrid(np.arange(w) - (w - 1) / 2, np.arange(h) - (h - 1) / 2)
    z = 1.0 + 0.002 * np.random.default_rng(0).standard_normal((h, w))
    wall = np.stack([u / f * z, v / f * z, z], axis=-1)
    assert real_up_error.floor_truth(wall) is None
    assert real_up_error.floor_truth(np.full((30, 40, 3), np.nan)) is None


def test_the_measurement_is_deterministic():
    xyz, _ = _view(5.0, 0.25, wall=2.5, speckle=0.5)
    assert np.array_equal(real_up_error.floor_truth(xyz), real_up_error.floor_truth(xyz))


def test_truth_of_takes_the_given_floors_over_the_measured_one():
    xyz, up = _view(0.0, 0.2, wall=3.0)

    class Cloud:
        pass

    c = Cloud()
    c.xyz = xyz
    given = {"mbot/a.png": [0.0, -0.6, 0.8]}
    v, how = real_up_error.truth_of("hunt45/mbot/a.png", ("floors", "mbot/a.png"), [], up, c, given)
    assert how == "grav45" and np.allclose(v, given["mbot/a.png"])
    v, how = real_up_error.truth_of("hunt45/mbot/a.png", ("floors", "mbot/a.png"), [], up, c, None)
    assert how == "grav45" and real_up_error.angle(v, up) < 1.0
