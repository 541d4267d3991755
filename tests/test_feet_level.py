"""No floor plane at all (feet44, docs/objects.md "A floor level from the feet of upright
faces"): a camera lying on the floor measures no floor, so neither ``solid.grounded`` nor
``floor_foot`` can ground a box's face.  ``RelationParams.tall_feet_level`` (off by default:
measured without a margin on the real frames) puts a virtual level floor at the lowest level
the feet of two or more shaped upright planes below the eye share (:func:`feet_level`) and
asks :func:`floor_foot` of it.

Rendered analytic scenes (640x480); no floor is rendered, so it measures nothing."""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, render, wall

from planerel.errors import InputError
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, feet_level, relate, tall_faces

ON = RelationParams(tall_feet_level=0.03)


def _tall(cloud, lab, params=None):
    ps = measure_planes(cloud, lab)
    return ps, tall_faces(ps, relate(ps, cloud, params), cloud)


def test_feet_level_is_the_lowest_level_two_feet_share():
    assert feet_level([-0.06, -0.05, -0.30, 0.1, float("nan")], 0.03)[2] == 2
    level, spread, n = feet_level([-0.30, -0.06, -0.05, -0.31], 0.03)
    assert n == 2 and level == pytest.approx(-0.305) and spread == pytest.approx(0.01)
    assert feet_level([-0.3, -0.1, 0.2, 0.25], 0.03) is None  # one foot each; above the eye
    assert feet_level([-0.3, -0.29, -0.28], 0.03, 3)[2] == 3


def test_two_boxes_with_no_floor_measured_stand_on_their_feet_level():
    # a Kinect lying on the floor (0.06 m up, level): two boxes 2 m away, tops out of sight
    # over the eye; the floor returns no depth
    rects = box(-0.5, 2.0, 0.5, 0.4, 0.5) + box(0.5, 2.2, 0.5, 0.4, 0.6, obj=2)
    cloud, lab, _, _ = render(rects, noise=0.0012, pitch=0.0, cam_height=0.06, width=640,
                              height=480)
    ps = measure_planes(cloud, lab)
    assert ps.floor is None
    fronts = {1, 6}
    assert all(ps.by_label(f).orientation == "vertical" for f in fronts)
    assert not _tall(cloud, lab)[1]  # the default: off
    assert fronts <= _tall(cloud, lab, ON)[1]
    # one box seen face on (no side in view) shares its feet with nothing: no level
    one, lab1, _, _ = render(box(0.0, 2.0, 0.5, 0.4, 0.5), noise=0.0012, pitch=0.0,
                             cam_height=0.06, width=640, height=480)
    assert not _tall(one, lab1, ON)[1]


def test_a_shelf_board_level_does_not_ground_a_face_hanging_over_open_space():
    # no floor measured, a camera 1.2 m up; a shelf board 0.6 m up (measured, no plane of
    # its own) with two boxes on it, and a panel whose foot is at the board's level but hangs
    # over open space: under it the wall behind, below the level
    board = Rect((-0.2, 2.0, 0.6), (1, 0, 0), (0, 1, 0), 0.7, 0.3)
    b1 = [Rect((c.center[0], c.center[1], c.center[2] + 0.6), c.e1, c.e2, c.a, c.b, c.obj)
          for c in box(-0.5, 2.0, 0.4, 0.3, 0.8)]
    b2 = [Rect((c.center[0], c.center[1], c.center[2] + 0.6), c.e1, c.e2, c.a, c.b, 2)
          for c in box(0.1, 2.05, 0.4, 0.3, 0.8)]
    panel = Rect((0.9, 2.0, 1.05), (1, 0, 0), (0, 0, 1), 0.25, 0.45, 3)
    rects = [board] + b1 + b2 + [panel, wall(y=3.5)]
    cloud, lab, _, _ = render(rects, noise=0.0012, pitch=10.0, cam_height=1.2, width=640,
                              height=480)
    lab = lab.copy()
    lab[lab == 0] = -1  # the board: measured, no plane
    ps = measure_planes(cloud, lab)
    assert ps.floor is None
    p_label = 11
    assert ps.by_label(p_label).orientation == "vertical"
    tall = _tall(cloud, lab, ON)[1]
    assert p_label not in tall
    assert {2, 7} <= tall  # the boxes' fronts on the board's level


def test_tall_feet_min_counts_planes():
    with pytest.raises(InputError):
        RelationParams(tall_feet_min=1)
    with pytest.raises(InputError):
        RelationParams(tall_feet_level=-0.1)
    assert np.isfinite(RelationParams(tall_feet_level=0.05).tall_feet_level)
