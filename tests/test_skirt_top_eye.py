"""A skirt's top is never seen from below (furn44, docs/objects.md "Room furniture seen from a
low camera"): a shelf over a row of books, a table's top over its apron, seen from a camera
near the floor, show their underside over a face hanging below it, the way a box shows its top
over its side.  ``RelationParams.skirt_top_eye`` (0.3 m) refuses a top more than that above the
sensor's eye, and ``skirt_underside`` (under80) one whose normal towards the sensor points
down, at any level; the same pair seen from above is a skirt as before.

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
    # before furn44 (and under80): the underside is one
    assert _skirt(LOW, RelationParams(skirt_top_eye=0.0, skirt_underside=False))
    assert not _skirt(LOW)
    # 0.4 m over the eye: within 0.5, so only the underside's normal refuses it (under80)
    assert _skirt(LOW, RelationParams(skirt_top_eye=0.5, skirt_underside=False))
    assert not _skirt(LOW, RelationParams(skirt_top_eye=0.5))
    assert not _skirt(LOW, RelationParams(skirt_top_eye=0.0))


#: the top 0.15 m over the eye: under ``skirt_top_eye``, its underside in view (under80: a
#: bookcase's shelf 0.17 m over a camera 0.56 m up)
NEAR = {"pitch": 0.0, "cam_height": 0.40}


def test_an_underside_just_over_the_eye_is_no_skirt_top():
    """``skirt_underside`` (under80): the top's normal towards the sensor points down, so the
    camera sees its underside, however close to the eye's level it lies."""
    assert _skirt(NEAR, RelationParams(skirt_underside=False))  # 0.15 m: within 0.3
    assert not _skirt(NEAR)


def test_a_box_top_under_a_gravity_some_degrees_off_is_still_seen_from_above():
    """The normal's side does not depend on the gravity estimate's small errors: a box's top
    seen from above keeps its normal on the upper side under an up tilted 8 or 15 degrees
    (towards the camera and away from it), and the switch changes no skirt there (under 3
    degrees the top and front stay a skirt; further off the skirt's own tilt test decides)."""
    import numpy as np

    from planerel.io.cloud import Cloud

    cloud, lab, _, _ = render(_shelf(0.0), noise=0.0005, width=640, height=480, **HIGH)
    up = np.asarray(cloud.up, float)
    side = np.cross(up, [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    for deg in (3.0, 8.0, 15.0):
        for sign in (1, -1):
            a = np.radians(deg) * sign
            tilted = np.cos(a) * up + np.sin(a) * side
            c = Cloud(cloud.xyz, cloud.intrinsics, tilted, "analytic")
            ps = measure_planes(c, lab)
            assert float(np.asarray(ps.by_label(1).normal) @ tilted) > 0.9
            on = relate(ps, c).get(1, 2).skirt
            assert on == relate(ps, c, RelationParams(skirt_underside=False)).get(1, 2).skirt
            assert on or deg > 3.0


def test_skirt_top_eye_is_a_distance_and_skirt_underside_a_switch():
    with pytest.raises(InputError):
        RelationParams(skirt_top_eye=-0.1)
    with pytest.raises(InputError):
        RelationParams(skirt_underside="yes")
    assert RelationParams().skirt_underside is True
