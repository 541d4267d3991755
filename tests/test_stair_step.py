"""``stair_step/2`` (planerel.features.stair_step.stair_steps): two parallel treads or risers
of one object, the second one stair step above and beyond the first.

A pairwise relation the learner may use (the default task's ``modeb(*, stair_step(+plane,
-plane))``) in place of a hand-written flight detector: ray-cast scenes
(tests/scenes_analytic.py) are segmented, described and written as facts; the demo's rules are
learned by the real learner in tests/test_pipeline.py.
"""

from __future__ import annotations

import math

from scenes_analytic import Rect, box, floor, render, stairs
from test_proposals_cavities import _shelf

from planerel.features.facts import describe_scene, scene_facts
from planerel.features.relations import STAIR_RISE, STAIR_RUN, ProposalParams
from planerel.features.stair_step import stair_steps

VIEW = dict(pitch=25, cam_height=1.6, width=320, height=240, noise=0.001)


def _facts(rects, **view):
    cloud, lab, _up, objs = render(rects, **view)
    d = describe_scene(cloud, lab)
    facts = scene_facts(d)
    obj_of = {d.plane_id(p.label): objs[p.label] for p in d.planes}
    pairs = [tuple(x.strip() for x in f[len("stair_step("):-2].split(","))
             for f in facts["stair_step"]]
    return d, facts, obj_of, pairs


def _level(d, pid):
    (p,) = [p for p in d.planes if d.plane_id(p.label) == pid]
    return p.height


def test_a_flights_steps_are_stair_steps_and_a_shelfs_boards_are_not():
    # a shelf whose boards are one stair rise apart (0.2 m): parallel, one above the other,
    # but stacked in plan view; the flight's treads lie one run beyond each other
    shelf = _shelf(cx=-0.9, cy=2.6, boards=(0.4, 0.6, 0.8, 1.0), height=1.2, obj=1)
    flight = stairs(0.8, 2.0, n=4, obj=2)
    d, facts, obj_of, pairs = _facts([floor()] + shelf + flight, **VIEW)
    assert pairs, "no stair_step fact"
    assert all(obj_of[a] == 2 and obj_of[b] == 2 for a, b in pairs)
    # the shelf's boards are an open-riser row to open_tread_pairs (no run asked of it): the
    # footprints keep them out
    from planerel.features.open_treads import open_tread_pairs

    (so,) = [o for o in d.objects if {obj_of[d.plane_id(k)] for k in o.planes} == {1}]
    assert open_tread_pairs(d.planes, so.planes, STAIR_RISE, 0.6)
    assert stair_steps(d.planes, so.planes) == frozenset()
    # the lower plane first, one rise (0.17 m) below the higher, both parallel
    for a, b in pairs:
        assert STAIR_RISE[0] <= _level(d, b) - _level(d, a) <= STAIR_RISE[1]
        assert f"parallel({a}, {b})." in facts["parallel"]
    # every tread in view but the lowest has its lower neighbour: a chain, not a single pair
    treads = sorted((_level(d, pid), pid) for pid, o in obj_of.items() if o == 2
                    and f"orientation({pid}, horizontal)." in facts["orientation"])
    assert len(treads) >= 3
    lower = {a for a, _ in pairs}
    assert sum(pid in lower for _, pid in treads[:-1]) >= len(treads) - 2


def test_boxes_of_two_heights_make_no_stair_step():
    # touching boxes 0.25 and 0.55 m high: one level change of 0.30 m, more than a stair's rise
    rects = [floor()] + box(-0.2, 2.2, 0.4, 0.4, 0.25) + box(-0.2, 2.6, 0.4, 0.4, 0.55, obj=2)
    d, facts, _obj_of, pairs = _facts(rects, **VIEW)
    assert len(d.objects) >= 1 and facts["orientation"]
    assert pairs == []


def test_stair_steps_of_one_plane_or_none():
    cloud, lab, _up, _objs = render([floor()] + stairs(0.0, 2.0, n=3), **VIEW)
    d = describe_scene(cloud, lab)
    assert stair_steps(d.planes, ()) == frozenset()
    assert stair_steps(d.planes, (d.planes[0].label,)) == frozenset()
    # the windows are a staircase's (docs/predicates.md)
    assert STAIR_RISE == (0.08, 0.25) and STAIR_RUN == (0.15, 0.45)


def _raked_stairs(cx, y0, n=4, rise=0.18, run=0.28, width=1.0, lean=13.0, obj=1):
    """A carpeted flight: each riser leans back ``lean`` degrees from its nosing (its foot
    ``rise * tan(lean)`` further from the camera than its top), each tread runs from its
    nosing to the next riser's foot."""
    t = math.tan(math.radians(lean))
    out = []
    for k in range(n):
        y = y0 + k * run  # the nosing of step k
        e2 = (0.0, -math.sin(math.radians(lean)), math.cos(math.radians(lean)))
        out.append(Rect((cx, y + rise * t / 2, (k + 0.5) * rise), (1, 0, 0), e2, width / 2,
                        rise / (2 * math.cos(math.radians(lean))), obj))
        deep = run + rise * t
        out.append(Rect((cx, y + deep / 2, (k + 1) * rise), (1, 0, 0), (0, 1, 0), width / 2,
                        deep / 2, obj))
    return out


def test_risers_leaning_back_are_stair_steps_within_riser_tilt():
    # a real carpeted flight's risers measure 11-13 degrees off vertical (hunt92 depth_21:
    # the carpet runs from the nosing back to the tread below); seen level from a low camera
    # the treads are edge on and the risers are what shows
    rects = [floor()] + _raked_stairs(0.0, 1.6, n=4, lean=15.0)
    cloud, lab, _up, objs = render(rects, pitch=0, cam_height=0.35, width=320, height=240,
                                   noise=0.0005)
    d = describe_scene(cloud, lab)
    risers = [p.label for p in d.planes if objs[p.label] == 1 and 70 < p.incline < 85]
    assert len(risers) >= 3
    leaning = stair_steps(d.planes, risers, ProposalParams(riser_tilt=20.0))
    assert len(leaning) >= 2 and all(a in risers and b in risers for a, b in leaning)
    # a riser within riser_tilt only: at 12 degrees (the treads' tilt) none of them counts
    assert stair_steps(d.planes, risers, ProposalParams(riser_tilt=12.0)) == frozenset()
    # the default admits them
    assert stair_steps(d.planes, risers) == leaning


def test_step_kind_takes_a_tread_and_a_riser_tilt():
    from types import SimpleNamespace

    from planerel.features.relations import _step_kind

    face = SimpleNamespace(orientation="inclined", incline=76.0)
    assert _step_kind(face, 12.0) is None
    assert _step_kind(face, (12.0, 16.0)) == "riser"
    slab = SimpleNamespace(orientation="inclined", incline=14.0)
    assert _step_kind(slab, (12.0, 16.0)) is None   # the riser tilt does not widen the treads'
    assert ProposalParams(step_tilt=10.0, riser_tilt=18.0).step_tilts == (10.0, 18.0)
    import pytest

    from planerel.errors import InputError

    for bad in (-1.0, 50.0):
        with pytest.raises(InputError, match="riser_tilt"):
            ProposalParams(riser_tilt=bad)


def _open_basket(cx, y0, w=0.6, depth=0.44, h=0.3, strip=0.1, obj=1):
    """An open basket on the floor: its near wall's outside in two coplanar pieces (a lower
    strip ``strip`` high and the rest up to the rim), its far wall's inside, its floor."""
    return [
        Rect((cx, y0, strip / 2), (1, 0, 0), (0, 0, 1), w / 2, strip / 2, obj),
        Rect((cx, y0, (strip + h) / 2), (1, 0, 0), (0, 0, 1), w / 2, (h - strip) / 2, obj),
        Rect((cx, y0 + depth, h / 2), (1, 0, 0), (0, 0, 1), w / 2, h / 2, obj),
        Rect((cx, y0 + depth / 2, 0.02), (1, 0, 0), (0, 1, 0), w / 2, depth / 2, obj),
    ]


def test_an_open_baskets_walls_are_no_risers_when_the_near_one_rises_to_the_rim():
    # riser92: hidden26's wicker basket seen from above its rim: the near wall's outside (its
    # face in pieces, a lower strip pairing) and the far wall's inside, one stair rise and run
    # apart by their centroids, made a false `stairs`; the near wall's surface goes on up to
    # the rim the far wall ends at, where a flight's riser ends one rise under the next one's
    # top
    from planerel.features.relations import _step_kind

    rects = [floor()] + _open_basket(0.0, 1.4)
    cloud, lab, _up, objs = render(rects, pitch=30, cam_height=0.9, width=320, height=240,
                                   noise=0.0005)
    d = describe_scene(cloud, lab)
    mine = [p.label for p in d.planes if objs[p.label] == 1]
    risers = [p.label for p in d.planes if p.label in mine and _step_kind(p, 12.0) == "riser"]
    assert len(risers) == 3
    import numpy as np

    xyz = np.asarray(cloud.xyz, float)
    off = stair_steps(d.planes, mine, ProposalParams(riser_walls=False), xyz=xyz)
    assert off, "the strip and the far wall make no step: the case is not built"
    assert stair_steps(d.planes, mine, xyz=xyz) == frozenset()
    # without the points nothing is refused
    assert stair_steps(d.planes, mine) == off


def test_a_flights_risers_are_no_wall_pair():
    # every riser of a flight seen level from its foot ends at its nosing: none rises to the
    # next one's top, so riser_walls keeps every pair
    import numpy as np

    rects = [floor()] + _raked_stairs(0.0, 1.6, n=4, lean=0.0)
    cloud, lab, _up, objs = render(rects, pitch=0, cam_height=0.35, width=320, height=240,
                                   noise=0.0005)
    d = describe_scene(cloud, lab)
    mine = [p.label for p in d.planes if objs[p.label] == 1]
    xyz = np.asarray(cloud.xyz, float)
    with_walls = stair_steps(d.planes, mine, xyz=xyz)
    assert len(with_walls) >= 2
    assert with_walls == stair_steps(d.planes, mine, ProposalParams(riser_walls=False), xyz=xyz)
