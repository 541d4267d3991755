"""A far surface the sensor bends below the floor does not take the scene's floor away
(``planes.floor_range_slack``, slack49; docs/gravity.md "The floor beside a far piece the
sensor bends").

A D435 0.34 m over a room's floor (hunt49 vreloc) saw a wall piece 4.4 m away reaching 8.5 cm
under the floor: the floor rule wants the floor's lowest point within ``floor_tol`` (5 cm) of the
scene's lowest, each raised by two sigmas of the depth noise measured on small patches, which
does not show an active-stereo sensor's systematic range error (about 2 % of range at 4 m), and
the scene had no floor.  Beyond 3 m a plane's lowest point now counts as 2 % of its range
higher again; nearer, nothing changes (a flight's riser 1.4 m away under its lowest tread).

Scenes ray-cast in code (tests/scenes_analytic.py): the floor ends 3 m ahead and a wall piece
4.2 m ahead is seen through the gap down to 13 cm under it.
"""

from __future__ import annotations

import pytest
from scenes_analytic import Rect, render

from planerel.errors import InputError
from planerel.features.planes import PlaneParams, measure_planes

VIEW = {"pitch": 5.0, "cam_height": 0.34, "width": 320, "height": 240, "noise": 0.0012}


def _room():
    floor = Rect((0.0, 1.75, 0.0), (1, 0, 0), (0, 1, 0), 2.0, 1.25)  # y 0.5-3.0
    wall = Rect((0.0, 4.2, 0.4), (1, 0, 0), (0, 0, 1), 1.0, 0.6)  # z -0.2-1.0
    return [floor, wall]


# The ground rule's riser test counts a plane reaching up from below only within
# ``ground_reach`` of the candidate (table50): these walls, 1.0-1.2 m beyond the floor's end,
# no longer keep the floor from being the ground, so the floor rule is isolated here with
# ``ground_reach=0`` (the riser test at any distance, as when slack49 was measured).
ISOLATED = {"ground_reach": 0.0}


def test_a_far_piece_bent_below_the_floor_keeps_the_floor():
    cloud, lab, _, _ = render(_room(), **VIEW)
    before = measure_planes(cloud, lab, params=PlaneParams(floor_range_slack=0.0, **ISOLATED))
    after = measure_planes(cloud, lab, params=PlaneParams(**ISOLATED))
    assert before.floor is None
    assert after.floor == 0
    # with the default ground_reach the ground rule finds the same floor without the slack
    assert measure_planes(cloud, lab, params=PlaneParams(floor_range_slack=0.0)).floor == 0


def test_a_near_piece_below_the_floor_still_takes_it():
    # a piece 2.5 m ahead seen 23 cm under a floor ending 1.5 m ahead: within 3 m the range
    # slack adds nothing, the rule is as before
    floor = Rect((0.0, 1.0, 0.0), (1, 0, 0), (0, 1, 0), 2.0, 0.5)  # y 0.5-1.5
    wall = Rect((0.0, 2.5, 0.4), (1, 0, 0), (0, 0, 1), 1.0, 0.6)
    cloud, lab, _, _ = render([floor, wall], **VIEW)
    assert measure_planes(cloud, lab, params=PlaneParams(**ISOLATED)).floor is None
    assert measure_planes(cloud, lab, params=PlaneParams(floor_range_slack=0.0, **ISOLATED)).floor is None
    # the wall stands 1.0 m beyond the floor's end: the ground rule takes the floor (table50)
    assert measure_planes(cloud, lab).floor == 0


def test_the_slack_is_checked():
    with pytest.raises(InputError):
        PlaneParams(floor_range_slack=-0.01)
