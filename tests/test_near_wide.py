"""``RegionGrowParams.near_wide`` (near65; off by default): a second growing with a wider normal
window adds planes only where the first left depth nearer than ``far_depth`` in no plane (a
rippled face whose ripples the first window follows); nothing already in a plane changes."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import independent_scenes as ind  # noqa: E402

from planerel.errors import InputError  # noqa: E402
from planerel.io.cloud import Cloud  # noqa: E402
from planerel.segment import segment  # noqa: E402
from planerel.segment.params import RegionGrowParams  # noqa: E402


@pytest.fixture(scope="module")
def rippled_box():
    """dev_small's scene 6 (four small boxes on a table, Kinect-like, 640x480) with every
    pixel moved along its ray by a 3 mm ripple of a 14 px period (a RealSense-like rippled
    depth): box 3's normals at the first growing's window follow the ripple, and the first
    growing leaves the box in no plane."""
    xyz, truth, side, *_ = ind.make_scene(6, 6401, (640, 480), kinds=("small_box",),
                                          sensor="kinect")
    h, w = truth.shape
    vv, uu = np.mgrid[0:h, 0:w]
    rip = 0.003 * np.sin(2 * np.pi * uu / 14) * np.sin(2 * np.pi * vv / (14 * 1.3))
    valid = np.isfinite(xyz[..., 2])
    xyz = xyz * (1 + rip / np.where(valid, xyz[..., 2], 1.0))[..., None]
    intr = side["intrinsics"]
    cloud = Cloud(xyz, (intr["width"], intr["height"], intr["fx"], intr["fy"], intr["cx"],
                        intr["cy"]), side["up"])
    # wide_fallback off: the ripple leaves most of this frame in no plane, and the fallback
    # (on by default since up66) would grow the whole frame again before near_wide is reached
    return (cloud, truth, segment(cloud, wide_fallback=0.0),
            segment(cloud, near_wide=2.0, wide_fallback=0.0))


def test_near_wide_is_off_by_default(rippled_box):
    cloud, _truth, first, _near = rippled_box
    assert RegionGrowParams().near_wide == 0.0
    assert "near_planes" not in first.info
    np.testing.assert_array_equal(first.labels,
                                  segment(cloud, near_wide=0.0, wide_fallback=0.0).labels)


def test_the_rippled_face_becomes_planes(rippled_box):
    _cloud, truth, first, near = rippled_box
    box = truth == 3
    assert (first.labels[box] >= 0).mean() < 0.1     # the first growing leaves it
    assert (near.labels[box] >= 0).mean() > 0.7      # the wide window's growing finds it
    assert near.info["near_planes"] >= 1
    assert near.info["near_window"][0] > first.info["settings"]["normal_smooth"]


def test_nothing_in_a_plane_changes(rippled_box):
    cloud, _truth, first, near = rippled_box
    kept = first.labels >= 0
    np.testing.assert_array_equal(near.labels[kept], first.labels[kept])
    added = (near.labels >= 0) & ~kept
    z = np.asarray(cloud.xyz[..., 2])[added]
    assert added.any() and float(np.nanmax(z)) <= RegionGrowParams().far_depth
    assert len(near.planes) == len(first.planes) + near.info["near_planes"]


def test_near_wide_is_deterministic(rippled_box):
    cloud, _truth, _first, near = rippled_box
    np.testing.assert_array_equal(segment(cloud, near_wide=2.0, wide_fallback=0.0).labels,
                                  near.labels)


def test_nothing_is_added_beyond_far_depth(rippled_box):
    cloud, _truth, _first, _near = rippled_box
    seg = segment(cloud, near_wide=2.0, far_depth=0.1)   # every pixel lies farther
    assert seg.info["near_planes"] == 0
    np.testing.assert_array_equal(seg.labels, segment(cloud, far_depth=0.1).labels)


@pytest.mark.parametrize("bad", [0.5, 1.0, 4.5, -1, float("nan"), "wide", True])
def test_near_wide_must_be_off_or_a_factor_above_one(bad):
    with pytest.raises(InputError, match="near_wide"):
        RegionGrowParams(near_wide=bad)
