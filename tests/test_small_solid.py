"""The small pass keeps no patch that fills under :data:`planerel.segment.params.SMALL_SOLID`
of its convex hull in the image (solid103): a block's top is convex, a strip along a board's
edge (0.17 on hunt67's Kinect frame, where it joined three cubes into one object) or the half
of a ring is not."""

from __future__ import annotations

import numpy as np
import pytest

import planerel.segment.params as P
from planerel.io.cloud import Cloud, Intrinsics
from planerel.segment import segment
from planerel.segment.shape import mask_solidity as _solidity

W, H, F = 640, 480, 480.0


def _tops():
    """A board 1 m under the camera (looking straight down) with two 3 cm high tops, each
    too small for the first growing (360 px at 640x480): a 15 x 15 px square and a crescent
    (the right half of a ring 11.5-17.5 px in radius), 0.5 mm noise."""
    yy, xx = np.mgrid[:H, :W]
    square = (abs(yy - 160) < 7.5) & (abs(xx - 200) < 7.5)
    r = np.hypot(yy - 300, xx - 440)
    crescent = (r <= 17.5) & (r >= 11.5) & (xx >= 440)
    z = np.full((H, W), 1.0)
    z[square | crescent] = 0.97
    z = z + np.random.default_rng(0).normal(0.0, 0.0005, z.shape)
    intr = Intrinsics(W, H, F, F, (W - 1) / 2, (H - 1) / 2)
    xyz = np.dstack([(xx - intr.cx) / F * z, (yy - intr.cy) / F * z, z])
    return Cloud(xyz, intr, (0.0, 0.0, -1.0), "tops"), square, crescent


def test_solidity_of_squares_rings_and_lines():
    m = np.zeros((20, 20), bool)
    m[3:13, 4:14] = True
    assert _solidity(m) == pytest.approx(1.0)
    _, square, crescent = _tops()
    assert _solidity(square) == pytest.approx(1.0)
    assert 0.5 < _solidity(crescent) < 0.6
    assert _solidity(np.ones((1, 5), bool)) == pytest.approx(1.0)  # a row of pixels: whole
    assert _solidity(np.zeros((4, 4), bool)) == 1.0 and _solidity(np.eye(2, dtype=bool)) == 1.0
    ell = np.zeros((10, 10), bool)
    ell[:, 0] = ell[-1, :] = True
    assert _solidity(ell) == pytest.approx(19 / 59.5)  # the hull: the square less a triangle of 9 x 9 / 2


def test_the_small_pass_keeps_the_square_top_not_the_crescent(monkeypatch):
    cloud, square, crescent = _tops()
    seg = segment(cloud, small_pitch=0, up=(0.0, 0.0, -1.0), raised_min=0)
    assert seg.info["min_region_size"] > max(square.sum(), crescent.sum())
    assert seg.info["small_planes"] == 1
    assert len(np.unique(seg.labels[square])) == 1 and seg.labels[square][0] >= 0
    assert (seg.labels[crescent] < 0).all()
    monkeypatch.setattr(P, "SMALL_SOLID", 0.0)  # the rule before: both tops kept
    before = segment(cloud, small_pitch=0, up=(0.0, 0.0, -1.0), raised_min=0)
    assert before.info["small_planes"] == 2 and (before.labels[crescent] >= 0).all()
