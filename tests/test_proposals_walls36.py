"""walls36: a stairwell's room walls, facing each other across a flight seen from its top, are
no sides of the flight (``ProposalParams.channel_room_walls``; docs/objects.md "A stairwell's
walls are no flight's sides (walls36)").

Rendered scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py).
"""

from __future__ import annotations

import math

from scenes_analytic import Rect, render

from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams
from planerel.features.walls import room_wall, top_at_border, top_line

RISE, RUN, STEPS, WIDTH, EDGE = 0.16, 0.28, 7, 1.1, 1.5


def _stairwell(wall_top=0.75, follow=None):
    """A flight going down along +y from a landing (z = 0, the camera's floor) whose drop edge
    is at y = ``EDGE``, ``STEPS`` treads ``RISE`` apart, between two walls at x = +-WIDTH/2
    that stand on the lower floor and end ``wall_top`` m above the landing (a stairwell's room
    walls: their top is level, above the camera's view).  ``follow`` (metres): instead, the
    walls' tops run that high above the nosings, at the flight's pitch (closed strings).  The
    camera 1.4 m above the landing, pitched 50 degrees down, 320x240.

    Labels: 0 landing, 1..STEPS treads, then the risers, the lower floor, the two walls."""
    w2 = WIDTH / 2
    drop = (STEPS + 1) * RISE  # the lower floor, one rise under the last tread
    rects = [Rect((0, EDGE - 2.0, 0), (1, 0, 0), (0, 1, 0), 3.0, 2.0)]
    for k in range(STEPS):
        y = EDGE + (k + 0.5) * RUN
        rects.append(Rect((0, y, -(k + 1) * RISE), (1, 0, 0), (0, 1, 0), w2, RUN / 2, 1))
    for k in range(STEPS + 1):
        rects.append(Rect((0, EDGE + k * RUN, -(k + 0.5) * RISE), (1, 0, 0), (0, 0, 1), w2, RISE / 2, 1))
    length = STEPS * RUN
    rects.append(Rect((0, EDGE + length + 2.0, -drop), (1, 0, 0), (0, 1, 0), 3.0, 2.0))
    if follow is None:
        lo, hi = -drop, wall_top
        for s in (-1, 1):
            rects.append(Rect((s * w2, EDGE + length / 2, (lo + hi) / 2), (0, 1, 0), (0, 0, 1),
                              length / 2 + 0.2, (hi - lo) / 2))
    else:
        pitch = math.atan2(RISE, RUN)
        e1 = (0.0, math.cos(pitch), -math.sin(pitch))
        e2 = (0.0, math.sin(pitch), math.cos(pitch))
        b = 1.0
        ym = EDGE + length / 2
        ztop = follow - (ym - EDGE) * math.tan(pitch)  # the string's top over the flight's middle
        for s in (-1, 1):
            c = (s * w2, ym - b * e2[1], ztop - b * e2[2])
            rects.append(Rect(c, e1, e2, length / 2 + 0.1, b, 1))
    cloud, lab, _up, objs = render(rects, pitch=50, cam_height=1.4, width=320, height=240)
    walls = (len(rects) - 2, len(rects) - 1)
    return cloud, lab, walls


def _flight(d):
    treads = set(range(1, STEPS + 1))
    return max((set(o.planes) for o in d.objects), key=lambda s: len(s & treads))


def test_a_stairwells_walls_stay_out_of_the_flight():
    cloud, lab, walls = _stairwell()  # their top 0.75 m above the landing: out of view
    d = describe_scene(cloud, lab)
    byl = {p.label: p for p in d.planes}
    assert all(byl[w].orientation == "vertical" and byl[w].touches_border for w in walls)
    flight = _flight(d)
    assert len(flight & set(range(1, STEPS + 1))) >= 4
    assert not (flight & set(walls))
    # nor is either wall a proposal of its own (it was judged the stairwell's)
    assert not any(set(o.planes) & set(walls) for o in d.objects)
    # the tops are out of view: room walls
    for w in walls:
        assert top_line(byl[w], d.planes.up, cloud.xyz, lab) is None
        assert top_at_border(byl[w], d.planes.up, cloud.xyz, lab) >= 0.5
        assert room_wall(byl[w], d.planes.up, cloud.xyz, lab)
    # off: both walls join the flight across it (group_channels), as before walls36
    d0 = describe_scene(cloud, lab, proposal_params=ProposalParams(channel_room_walls=False))
    assert set(walls) <= _flight(d0)


def test_walls_whose_top_is_seen_still_join():
    # their top 0.3 m above the landing, seen and level: up to side_wall_rise_max above the
    # flight such walls stay its sides (tests/test_proposals_cavities.py), as before walls36
    cloud, lab, walls = _stairwell(wall_top=0.3)
    d = describe_scene(cloud, lab)
    byl = {p.label: p for p in d.planes}
    assert top_line(byl[walls[1]], d.planes.up, cloud.xyz, lab) is not None
    assert not room_wall(byl[walls[1]], d.planes.up, cloud.xyz, lab)
    assert set(walls) <= _flight(d)


def test_closed_strings_whose_tops_follow_the_flight_still_join():
    cloud, lab, walls = _stairwell(follow=0.35)
    d = describe_scene(cloud, lab)
    byl = {p.label: p for p in d.planes}
    flight = _flight(d)
    assert top_line(byl[walls[0]], d.planes.up, cloud.xyz, lab) is not None
    assert not room_wall(byl[walls[0]], d.planes.up, cloud.xyz, lab)
    assert set(walls) <= flight
    d0 = describe_scene(cloud, lab, proposal_params=ProposalParams(channel_room_walls=False))
    assert _flight(d0) == flight


def test_the_option_is_a_proposal_parameter():
    assert ProposalParams().channel_room_walls is True
    assert ProposalParams(channel_room_walls=False).channel_room_walls is False
