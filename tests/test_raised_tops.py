"""``RegionGrowParams.raised_min`` (raised102, on at 0.012 m): in a view from above, the depth the
growings left in no plane and standing over the largest level plane falls into components whose
top band becomes a plane -- a block's top the sensor smoothed into a dome, whose normals turn
through its rim so that no growing keeps it whole (hunt67/hunt90's RealSense boards)."""

from __future__ import annotations

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Cloud
from planerel.segment import segment
from planerel.segment.params import RegionGrowParams

W, H, F = 640, 480, 600.0
BOARD = 1.0           # the board's depth under a camera looking straight down (m)
UP = (0.0, 0.0, -1.0)  # towards the camera


def _board(cubes=(), caps=(), noise=0.0003, seed=0):
    """A board ``BOARD`` m under a camera looking straight down, with domed cube tops and
    spherical caps standing on it: ``(cloud, {name: (H, W) bool top mask})``.

    ``cubes``: ``(u, v, side_m, height_m)`` at the pixel ``(u, v)``; the top is a dome, its
    centre 3 mm over the top's plane and its rim falling 6 mm over the outer 6 px (a
    RealSense's smoothed edge, session 101).  ``caps``: ``(u, v, radius_m, height_m)``, a
    sphere's cap (a fruit, a bowl upside down)."""
    rng = np.random.default_rng(seed)
    v, u = np.mgrid[0:H, 0:W].astype(float)
    z = np.full((H, W), BOARD)
    tops = {}
    for i, (cu, cv, side, height) in enumerate(cubes):
        half = side / 2 * F / (BOARD - height)                  # px
        d = np.maximum(np.abs(u - cu), np.abs(v - cv))           # square distance, px
        inside = d <= half
        rim = np.clip((d - (half - 6.0)) / 6.0, 0.0, 1.0)        # 0 in the core, 1 at the edge
        r = np.hypot(u - cu, v - cv) / half
        dome = 0.003 * (1 - np.clip(r, 0, 1) ** 2) - 0.006 * rim ** 2
        z = np.where(inside, BOARD - height - dome, z)
        tops[f"cube{i}"] = inside
    for i, (cu, cv, rad, height) in enumerate(caps):
        rr = np.hypot(u - cu, v - cv) * (BOARD - height) / F   # m from the axis
        big = (rad * rad + height * height) / (2 * height)     # the sphere's radius
        inside = rr <= rad
        zz = BOARD - (np.sqrt(np.maximum(big * big - rr * rr, 0)) - (big - height))
        z = np.where(inside, zz, z)
        tops[f"cap{i}"] = inside
    z = z + rng.normal(0.0, noise, z.shape)
    xyz = np.stack([(u - W / 2) * z / F, (v - H / 2) * z / F, z], -1)
    return Cloud(xyz, (W, H, F, F, W / 2, H / 2), UP), tops


def _own(labels, mask, n_before=0) -> bool:
    """Whether one plane (label >= ``n_before``) holds 70 % of ``mask`` and lies 90 % in it."""
    labs, counts = np.unique(labels[mask], return_counts=True)
    return any(lab >= n_before and c >= 0.7 * mask.sum() and c >= 0.9 * (labels == lab).sum()
               for lab, c in zip(labs, counts, strict=True))


@pytest.fixture(scope="module")
def blocks():
    cubes = [(160, 140, 0.04, 0.04), (470, 150, 0.04, 0.04), (170, 350, 0.03, 0.025),
             (460, 340, 0.05, 0.06)]
    caps = [(320, 240, 0.035, 0.03)]
    return _board(cubes, caps)


def test_domed_block_tops_are_planes(blocks):
    cloud, tops = blocks
    on = segment(cloud, up=UP)
    off = segment(cloud, up=UP, raised_min=0.0)
    assert RegionGrowParams().raised_min == 0.012
    cubes = [k for k in tops if k.startswith("cube")]
    # without the pass the domes' rims break the smaller tops below the small pass's size
    # (the 6 cm cube's flat core is a plane, its rim in none) ...
    lost = [k for k in cubes if (off.labels[tops[k]] >= 0).mean() < 0.3]
    assert len(lost) >= 3, lost
    # ... with it each is a plane of its own, level with the board
    assert all(_own(on.labels, tops[k], len(off.planes)) for k in lost), on.info
    assert on.info["raised_planes"] == len(lost)
    for pl in on.planes[len(off.planes):]:
        assert abs(float(np.asarray(pl.normal) @ np.asarray(UP))) >= np.cos(np.radians(15))
    # nothing already in a plane changes, and a rim around a plane's top stays in none
    kept = off.labels >= 0
    np.testing.assert_array_equal(on.labels[kept], off.labels[kept])
    np.testing.assert_array_equal(on.labels[tops["cube3"]], off.labels[tops["cube3"]])


def test_a_round_cap_gets_no_plane(blocks):
    # a fruit's or an upturned bowl's cap: its upper band is a small part of it
    cloud, tops = blocks
    on = segment(cloud, up=UP)
    off = segment(cloud, up=UP, raised_min=0.0)
    new = on.labels >= len(off.planes)
    assert (new & tops["cap0"]).sum() <= 0.05 * tops["cap0"].sum()


def test_only_views_from_above_and_only_with_an_up(blocks):
    cloud, _ = blocks
    base = segment(cloud, raised_min=0.0, up=UP).labels
    # no up: no small pass, no raised pass
    assert "raised_planes" not in segment(cloud).info
    # a level camera (the same depth read as a wall): the small pass's pitch rule holds it
    level = segment(cloud, up=(0.0, -1.0, 0.0))
    assert "raised_planes" not in level.info
    np.testing.assert_array_equal(segment(cloud, up=UP, raised_min=0.0).labels, base)


def test_raised_tops_are_deterministic(blocks):
    cloud, _ = blocks
    np.testing.assert_array_equal(segment(cloud, up=UP).labels, segment(cloud, up=UP).labels)


def test_a_flat_board_adds_nothing():
    cloud, _ = _board()
    assert segment(cloud, up=UP).info["raised_planes"] == 0


@pytest.mark.parametrize("bad", [-0.01, 0.2, "x", float("nan"), True])
def test_bad_raised_min(bad):
    with pytest.raises(InputError, match="raised_min"):
        RegionGrowParams(raised_min=bad)
