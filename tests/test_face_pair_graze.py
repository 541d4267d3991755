"""``relations.face_pair_graze`` (boxrec59, docs/objects.md "Real boxes missed, cause by cause,
by range, size and view"): a box's side seen near edge-on comes out turned towards the camera
(top44: the sensor smears the convex edge it shares with the front), so two faces meeting at
82 degrees are a ``face_pair`` when one of them is seen within ``face_pair_graze`` degrees of
edge-on, and not when both are seen more squarely.  Scenes ray-cast in code
(tests/scenes_analytic.py)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import Rect, floor, render  # noqa: E402

from planerel.errors import InputError  # noqa: E402
from planerel.features.planes import measure_planes  # noqa: E402
from planerel.features.relations import RelationParams, relate, view_angle  # noqa: E402


def _pair(turn, cx, cy, graze):
    """``(angle, view angle of the side, face_pair)`` of a 10 cm cube's front and right side,
    the side turned ``turn`` degrees off square (opening the corner), the cube's front centre at
    ``(cx, cy)`` on the floor, a camera 0.5 m up looking 35 degrees down."""
    s = 0.05
    t = math.radians(turn)
    front = Rect((cx, cy - s, s), (1, 0, 0), (0, 0, 1), s, s, 1)
    d = np.array([math.sin(t), math.cos(t), 0.0])
    side = Rect(tuple(np.array([cx + s, cy - s, s]) + d * s), tuple(d), (0, 0, 1), s, s, 1)
    cloud, lab, _, _ = render([floor(), front, side], pitch=35, cam_height=0.5, width=640,
                              height=480, noise=0.0005)
    ps = measure_planes(cloud, lab)
    r = relate(ps, cloud, RelationParams(face_pair_graze=graze)).get(1, 2)
    side_plane = next(q for q in ps if q.label == 2)
    return r.angle, view_angle(side_plane), r.face_pair


def test_a_side_seen_near_edge_on_pairs_at_82_degrees_only_with_the_graze_bound():
    angle, seen, off = _pair(8.0, -0.2, 1.0, 0.0)
    assert angle == pytest.approx(82.0, abs=0.5) and seen < 20.0
    assert not off
    assert _pair(8.0, -0.2, 1.0, 20.0)[2]


def test_a_side_seen_squarely_needs_the_usual_angle():
    angle, seen, fp = _pair(8.0, -0.5, 1.0, 20.0)
    assert angle == pytest.approx(82.0, abs=0.5) and seen > 25.0
    assert not fp
    assert _pair(0.0, -0.5, 1.0, 20.0)[2]      # a square corner is a pair either way


def test_view_angle_and_settings():
    class P:
        centroid = (0.0, 0.0, 2.0)
        normal = (0.0, 0.0, -1.0)
    assert view_angle(P) == pytest.approx(90.0)
    P.normal = (1.0, 0.0, 0.0)
    assert view_angle(P) == pytest.approx(0.0)
    with pytest.raises(InputError):
        RelationParams(face_pair_graze=-1.0)
