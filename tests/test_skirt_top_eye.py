"""A skirt's top is never seen from below (furn44, docs/objects.md "Room furniture seen from a
low camera"): a shelf over a row of books, a table's top over its apron, seen from a camera
near the floor, show their underside over a face hanging below it, the way a box shows its top
over its side.  ``RelationParams.skirt_top_eye`` (0.3 m) refuses a top more than that above the
sensor's eye; the same pair seen from above is a skirt as before.

Rendered analytic scenes (640x480): a horizontal rectangle 0.55 m over the floor, 0.6 m deep,
and a vertical one hanging 0.35 m under it, set back ``back`` m from its front edge (0.25 m: a
shelf over books, its underside in view from below; 0: a box's top and front)."""

from __future__ import annotations

import pytest
from scenes_analytic import Rect, floor, render

from planerel.errors import InputError
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate


def _shelf(back):
    top = Rect((0.0, 2.3, 0.55), (1, 0, 0), (0, 1, 0), 0.35, 0.3, 1)
    front = Rect((0.0, 2.0 + back, 0.375), (1, 0, 0), (0, 0, 1), 0.35, 0.175, 1)
    return [floor(), top, front]


def _skirt(view, params=None, back=0.25):
    cloud, lab, _, _ = render(_shelf(back), noise=0.0005, width=640, height=480, **view)
    ps = measure_planes(cloud, lab)
    assert ps.by_label(1).orientation == "horizontal" and ps.by_label(2).orientation == "vertical"
    r = relate(ps, cloud, params).get(1, 2)
    return r is not None and r.skirt


LOW = {"pitch": 0.0, "cam_height": 0.15}  # the top 0.4 m over the eye: its underside seen
HIGH = {"pitch": 30.0, "cam_height": 1.3}  # the top 0.75 m under the eye


def test_a_top_seen_from_below_is_no_skirt_top():
    assert _skirt(LOW, RelationParams(skirt_top_eye=0.0))  # before furn44: the underside is one
    assert not _skirt(LOW)
    assert _skirt(LOW, RelationParams(skirt_top_eye=0.5))  # 0.4 m over the eye: within 0.5


def test_a_box_top_and_front_seen_from_above_are_a_skirt():
    # (with the front set back 0.25 m the top hides it from above: no skirt either way)
    assert _skirt(HIGH, back=0.0) and _skirt(HIGH, RelationParams(skirt_top_eye=0.0), back=0.0)


def test_skirt_top_eye_is_a_distance():
    with pytest.raises(InputError):
        RelationParams(skirt_top_eye=-0.1)
