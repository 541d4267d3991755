"""synth22v: a wall-sized vertical plane whose seen top edge rises with the flight beside it is
the flight's side (a solid balustrade), not a room wall (``ProposalParams.flight_sides``;
docs/objects.md, "A balustrade is no wall (flight_sides, synth22v)").

Rendered scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py).
"""

from __future__ import annotations

import math

import numpy as np
from scenes_analytic import Rect, floor, render

from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams, _flight_steps
from planerel.features.walls import flight_caps, flight_side, top_line

RISE, RUN, STEPS = 0.17, 0.28, 6


def _scene(rail=None, level=False, far=True, height=0.55):
    """A flight of six steps rising along +x (risers facing -x), 1 m wide, between two solid
    balustrades (vertical planes y = 2.0 and y = 3.05): their top edges run ``height`` m
    above the nosings, at the flight's pitch (31 degrees) or at ``rail`` degrees; each is
    8 m long and goes on past the image's sides and under the floor.  ``level``: instead of
    the balustrades, a room wall at y = 2.0 with a level top, 1.07 m above the highest
    nosing's line middle.  The camera 3 m up, pitched 45 degrees down, 320x240: it sees the
    near balustrade's outside face and, over its top, the flight and the far balustrade's
    inside face."""
    pitch = math.atan2(RISE, RUN)
    ra = pitch if rail is None else math.radians(rail)
    x0, yn, width = -0.6, 2.0, 1.0
    y1, y2 = yn + 0.05, yn + 0.05 + width
    rects = [floor(size=8, y=3)]
    for k in range(STEPS):
        x = x0 + k * RUN
        rects.append(Rect((x, (y1 + y2) / 2, (k + 0.5) * RISE), (0, 1, 0), (0, 0, 1), width / 2, RISE / 2, 1))
        rects.append(Rect((x + RUN / 2, (y1 + y2) / 2, (k + 1) * RISE), (0, 1, 0), (1, 0, 0), width / 2, RUN / 2, 1))
    if level:
        top = height + RISE + 0.5 * STEPS * RISE
        length = STEPS * RUN + 0.2
        rects.append(Rect((x0 - 0.1 + length / 2, yn, top / 2), (1, 0, 0), (0, 0, 1), length / 2, top / 2, -1))
    else:
        e1 = (math.cos(ra), 0.0, math.sin(ra))
        e2 = (-math.sin(ra), 0.0, math.cos(ra))
        b = 1.2
        xm = x0 + STEPS * RUN / 2
        ztop = height + RISE + (xm - x0) * math.tan(pitch)  # the rail over the flight's middle
        c = (xm + b * math.sin(ra), yn, ztop - b * math.cos(ra))
        rects.append(Rect(c, e1, e2, 4.0, b, 1))
        if far:
            rects.append(Rect((c[0], y2 + 0.001, c[2]), e1, e2, 4.0, b, 1))
    cloud, lab, _up, objs = render(rects, pitch=45, cam_height=3.0, width=320, height=240)
    return cloud, lab, objs


NEAR, FAR = 13, 14  # the balustrades' labels (rects 1-12 are the steps, 0 the floor)


def _flight(d):
    """The proposal holding the most steps."""
    return max((set(o.planes) for o in d.objects), key=lambda s: len(s & set(range(1, 13))))


def test_balustrades_whose_tops_rise_with_the_flight_are_its_sides():
    cloud, lab, _objs = _scene()
    d = describe_scene(cloud, lab)
    byl = {p.label: p for p in d.planes}
    # both faces are wall-sized: support by area before this rule
    assert byl[NEAR].orientation == "vertical" and byl[NEAR].area >= 2.0
    assert byl[FAR].orientation == "vertical" and byl[FAR].area >= 2.0
    assert NEAR not in d.support and FAR not in d.support
    assert {NEAR, FAR} <= _flight(d)
    # off: both are walls and the flight's proposal lacks its sides (seed 33 s0034, s0039)
    d0 = describe_scene(cloud, lab, proposal_params=ProposalParams(flight_sides=False))
    assert NEAR in d0.support and FAR in d0.support
    assert not ({NEAR, FAR} & _flight(d0))


def test_the_near_side_alone_joins_the_flight_it_does_not_touch():
    # without the far balustrade the near face's outside meets no step at an edge: it joins by
    # the rule's own join
    cloud, lab, _objs = _scene(far=False)
    d = describe_scene(cloud, lab)
    assert NEAR not in d.support and NEAR in _flight(d)


def test_a_room_wall_with_a_level_top_beside_the_flight_stays_support():
    cloud, lab, _objs = _scene(level=True)
    d = describe_scene(cloud, lab)
    byl = {p.label: p for p in d.planes}
    assert byl[NEAR].area >= 2.0 and NEAR in d.support
    assert all(NEAR not in o.planes for o in d.objects)


def test_a_top_rising_at_another_pitch_is_no_side():
    # a face whose top rises at 15 degrees beside a 31-degree flight: its height above the
    # nosings changes by 0.6 m along the flight
    cloud, lab, _objs = _scene(rail=15.0)
    d = describe_scene(cloud, lab, proposal_params=ProposalParams(wedge_side_max=0.0))
    assert NEAR in d.support and FAR in d.support
    # with the wedge-side test (wedge96) such a face, lying under a straight 15-degree edge, is
    # a wedge's side: no support, a proposal of its own, still not the flight's
    d = describe_scene(cloud, lab)
    assert NEAR not in d.support and FAR not in d.support
    assert not ({NEAR, FAR} & _flight(d)) and {(NEAR,), (FAR,)} <= {o.planes for o in d.objects}


def test_top_line_and_caps_measure_the_rail():
    cloud, lab, _objs = _scene()
    d = describe_scene(cloud, lab, proposal_params=ProposalParams(flight_sides=False))
    byl = {p.label: p for p in d.planes}
    up = np.asarray(d.planes.up, float)
    line = top_line(byl[NEAR], up, cloud.xyz, d.labels)
    assert line is not None
    slope, _off, lo, hi, rms, _along = line
    assert abs(abs(slope) - RISE / RUN) < 0.02 and rms < 0.01 and hi - lo > 1.0
    steps = _flight_steps(d.planes, byl[NEAR], [q for q in d.planes if q.label not in d.support],
                          ProposalParams())
    assert {q.label for q in steps} <= set(range(1, 13)) and len(steps) >= 4
    caps = flight_caps(line, steps, up)
    # the rail stands 0.55 m above every nosing seen
    assert len(caps) >= 4 and all(abs(a - 0.55) < 0.03 for a, _t in caps)
    assert flight_side(byl[NEAR], steps, up, cloud.xyz, d.labels)
    # one step: nothing to follow
    assert not flight_side(byl[NEAR], steps[:1], up, cloud.xyz, d.labels)
    # a top seen over 0.2 m only (a few bins of a level wall's top past a corner can slope)
    short = (slope, _off, 0.5 * (lo + hi) - 0.1, 0.5 * (lo + hi) + 0.1, rms, _along)
    assert not flight_side(byl[NEAR], steps, up, cloud.xyz, d.labels, line=short)
    assert flight_side(byl[NEAR], steps, up, cloud.xyz, d.labels, line=short, min_extent=0.0)
    assert flight_side(byl[NEAR], steps, up, cloud.xyz, d.labels, line=line)


def test_a_top_at_the_image_border_gives_no_line():
    cloud, lab, _objs = _scene()
    d = describe_scene(cloud, lab, proposal_params=ProposalParams(flight_sides=False))
    byl = {p.label: p for p in d.planes}
    up = np.asarray(d.planes.up, float)
    # the near face seen only along the image's bottom border: its top there may go on out
    # of view, every bin of it is at the border
    lab2 = d.labels.copy()
    rows = np.arange(lab2.shape[0])[:, None]
    lab2[(lab2 == NEAR) & (rows < lab2.shape[0] - 3)] = -1
    assert top_line(byl[NEAR], up, cloud.xyz, lab2) is None
