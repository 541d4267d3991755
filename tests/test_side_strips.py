"""benchmarks/side_strips.py (strip42): the strip a box's side leaves on an upright face's
left or right edge when the segmentation dropped it (points no plane took, continuing the edge
behind the face at about 90 degrees).  A measuring tool (docs/objects.md "A box seen as one
upright face: the strip of its side, measured (strip42)"): no relation of the model reads it."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scenes_analytic import Rect, floor, render

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import side_strips  # noqa: E402

from planerel.features.planes import measure_planes  # noqa: E402


def _carton(x=0.25, y=0.8, front_half=0.045, depth=0.06, z1=0.25, side=True):
    """A carton's front (label 1, facing the sensor) and its left side (label 2, ``depth`` m
    deep), the carton ``x`` m right of the sensor: the left side is turned to it."""
    front = Rect((x, y, z1 / 2), (1, 0, 0), (0, 0, 1), front_half, z1 / 2, 1)
    rects = [floor(), front]
    if side:
        rects.append(Rect((x - front_half, y + depth / 2, z1 / 2), (0, 1, 0), (0, 0, 1),
                          depth / 2, z1 / 2, 1))
    return rects


def _front(rects, drop_side=True):
    cloud, lab, up, _ = render(rects, pitch=0.0, cam_height=0.2, width=640, height=480,
                               noise=0.0008)
    lab = lab.copy()
    if drop_side:
        lab[lab == 2] = -1              # the segmentation left the side's pixels unassigned
    lab[lab == 0] = -1                  # and the floor does not matter here
    ps = measure_planes(cloud, lab)
    face = next(p for p in ps if p.label == 1)
    return side_strips.side_strips(face, lab, cloud.xyz, up), face


def test_a_dropped_side_is_a_strip_on_the_edge_it_continues():
    res, face = _front(_carton())
    assert face.orientation == "vertical"
    left, right = res["L"], res["R"]
    assert left["view"] < -5                # the left side is turned to the sensor
    assert left["share"] > 0.9
    assert 0.04 <= left["depth"] <= 0.065   # the side is 6 cm deep
    assert right["view"] > 0 and right["share"] == 0.0   # the right side is hidden
    assert side_strips.has_strip(res)


def test_no_side_no_strip():
    # a lone upright rectangle (a board, a door, a picture): behind its edge is the floor
    # (a row or two at its foot meets the floor right behind the edge)
    res, _ = _front(_carton(side=False))
    assert res["L"]["share"] < 0.05 and res["R"]["share"] == 0.0
    assert not side_strips.has_strip(res)


def test_a_side_that_is_a_plane_is_no_strip():
    # a side the segmentation kept is a plane of its own (face_pair's business, pair41)
    res, _ = _front(_carton(), drop_side=False)
    assert res["L"]["share"] == 0.0


def test_a_shallow_side_is_under_the_depth():
    res, _ = _front(_carton(depth=0.02))
    assert res["L"]["share"] > 0.9 and res["L"]["depth"] < 0.03
    assert not side_strips.has_strip(res)
    assert side_strips.has_strip(res, depth=0.015)


def test_no_points_no_strip():
    class Face:
        label, normal, centroid, bbox = 5, np.array([0, 0, 1.0]), np.array([0, 0, 1.0]), (0, 0, 4, 4)

    lab = np.full((4, 4), -1, np.int32)
    xyz = np.full((4, 4, 3), np.nan)
    res = side_strips.side_strips(Face, lab, xyz, np.array([0, -1.0, 0]))
    assert res["L"]["share"] == 0.0 and res["R"]["rows"] == 0 and res["span"] == 0.0
