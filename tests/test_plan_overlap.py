"""``over/2`` (planerel.features.plan_overlap): a shelf's boards lie one over another in plan
view, a flight's treads do not.  Footprint geometry by hand, then ray-cast scenes
(tests/scenes_analytic.py) described and written as facts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scenes_analytic import floor, render, stairs
from test_proposals_cavities import _shelf

from planerel.features.facts import describe_scene, scene_facts
from planerel.features.plan_overlap import plan_overlap

UP = (0.0, 0.0, 1.0)


def _square(cx, cy, z, half=0.5):
    return [(cx - half, cy - half, z), (cx + half, cy - half, z), (cx + half, cy + half, z),
            (cx - half, cy + half, z)]


def test_footprint_overlap_by_hand():
    # one square over another: whole; side by side: none; shifted by half: half
    assert plan_overlap(_square(0, 0, 1), _square(0, 0, 0), UP) == pytest.approx(1.0)
    assert plan_overlap(_square(0, 0, 1), _square(1.0, 0, 0), UP) == pytest.approx(0.0)
    assert plan_overlap(_square(0, 0, 1), _square(0.5, 0, 0), UP) == pytest.approx(0.5)
    # over the larger one: a small board wholly over a large one (a descending flight's
    # lowest tread over the lower floor) covers 4 % of it
    assert plan_overlap(_square(0, 0, 1, half=0.1), _square(0, 0, 0), UP) == pytest.approx(0.04)
    # points on a line have no footprint
    assert plan_overlap([(0, 0, 1), (1, 0, 1), (2, 0, 1)], _square(0, 0, 0), UP) == 0.0


def test_footprints_are_taken_along_up_not_the_camera_axis():
    # the same two squares seen by a camera rolled 30 degrees: rotate points and up alike
    a = math.radians(30)
    R = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    up = R @ np.array(UP)
    top, low = np.array(_square(0, 0, 1)) @ R.T, np.array(_square(0.5, 0, 0)) @ R.T
    assert plan_overlap(top, low, up) == pytest.approx(0.5)


def _over_facts(rects, **view):
    cloud, lab, _up, objs = render(rects, **view)
    d = describe_scene(cloud, lab)
    facts = scene_facts(d)
    obj_of = {d.plane_id(p.label): objs[p.label] for p in d.planes}
    pairs = [f[len("over("):-2].split(",") for f in facts["over"]]
    return d, facts, obj_of, [(a.strip(), b.strip()) for a, b in pairs]


def test_a_shelfs_boards_are_over_each_other_and_a_flights_treads_are_not():
    view = dict(pitch=25, cam_height=1.6, width=320, height=240, noise=0.001)
    shelf = _shelf(cx=-0.8, cy=2.6, boards=(0.4, 0.8, 1.2), height=1.3, obj=1)
    flight = stairs(0.8, 2.0, n=4, obj=2)
    d, facts, obj_of, over = _over_facts([floor()] + shelf + flight, **view)
    boards = sorted(pid for pid, o in obj_of.items() if o == 1
                    and f"orientation({pid}, horizontal)." in facts["orientation"])
    treads = [pid for pid, o in obj_of.items() if o == 2
              and f"orientation({pid}, horizontal)." in facts["orientation"]]
    assert len(boards) >= 2 and len(treads) >= 3
    # every board over every board below it; nothing of the flight over anything
    assert over and all(obj_of[a] == 1 and obj_of[b] == 1 for a, b in over)
    assert len(over) == len(boards) * (len(boards) - 1) // 2
    for a, b in over:
        assert f"above({a}, {b})." in facts["above"]
    # the fact is in the vocabulary a model's rules may use
    from planerel.ilp.prolog import model_vocabulary

    assert ("over", 2) in model_vocabulary()
